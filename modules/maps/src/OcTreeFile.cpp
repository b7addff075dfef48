// The maximum-likelihood, pruned form is computed while writing instead of on a
// copy, so no second tree is ever held in memory: a node whose eight children
// are leaves of one state (occupied or free) is written as that leaf, as
// octomap's toMaxLikelihood() + prune() would leave it. prune() collapses one
// depth at a time from the finest up, never the root, and stops at the first
// depth where nothing collapsed; the same rule is kept here. Test OcTreeFile.*
// pins the bytes against octomap's own writeBinary.
#include "avm/maps/OcTreeFile.h"

#include <octomap/OcTree.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "avm/io/AtomicFile.h"

namespace avm
{
namespace
{
// AbstractOccupancyOcTree::binaryFileHeader, which octomap keeps protected.
const std::string kBinaryFileHeader = "# Octomap OcTree binary file";

enum class NodeState
{
	Free,
	Occupied,
	Inner
};

/** A node in the pruned maximum-likelihood tree: its state and, when inner,
 *  its subtree in octomap's binary node stream (two bytes of two bits a child,
 *  then the inner children's subtrees) and its number of nodes. */
struct EncodedNode
{
	NodeState state = NodeState::Inner;
	std::string bytes;
	std::size_t nodes = 1;
};

NodeState leafState(const octomap::OcTree& tree, const octomap::OcTreeNode* node)
{
	return tree.isNodeOccupied(node) ? NodeState::Occupied : NodeState::Free;
}

/** One encoding pass: nodes at depths >= minDepth may collapse; collapsed[d]
 *  counts those that did at depth d. */
struct Encoder
{
	const octomap::OcTree& tree;
	unsigned minDepth;
	std::vector<std::size_t> collapsed;

	EncodedNode encode(const octomap::OcTreeNode* node, unsigned depth);
};

EncodedNode Encoder::encode(const octomap::OcTreeNode* node, unsigned depth)
{
	std::array<EncodedNode, 8> children;
	std::array<bool, 8> exists{};
	for (unsigned i = 0; i < 8; i++)
	{
		if (!(exists[i] = tree.nodeChildExists(node, i))) continue;
		const auto* child = tree.getNodeChild(node, i);
		if (tree.nodeHasChildren(child))
			children[i] = encode(child, depth + 1);
		else
			children[i].state = leafState(tree, child);
	}
	EncodedNode out;
	const bool collapsible = depth > 0 && depth >= minDepth && children[0].state != NodeState::Inner &&
							 std::all_of(exists.begin(), exists.end(), [](bool e) { return e; }) &&
							 std::all_of(children.begin(), children.end(),
								 [&](const EncodedNode& c) { return c.state == children[0].state; });
	if (collapsible)
	{
		++collapsed[depth];
		out.state = children[0].state;
		return out;
	}
	// octomap's bits per child: 00 none, 10 free leaf, 01 occupied leaf, 11 inner.
	unsigned char bits[2] = {0, 0};
	for (unsigned i = 0; i < 8; i++)
	{
		if (!exists[i]) continue;
		const unsigned shift = 2 * (i % 4);
		const bool low = children[i].state != NodeState::Occupied, high = children[i].state != NodeState::Free;
		bits[i / 4] |= static_cast<unsigned char>((low ? 1u : 0u) << shift | (high ? 1u : 0u) << (shift + 1));
		out.nodes += 1;
	}
	out.bytes.assign(reinterpret_cast<const char*>(bits), 2);
	for (unsigned i = 0; i < 8; i++)
		if (exists[i] && children[i].state == NodeState::Inner)
		{
			out.bytes += children[i].bytes;
			out.nodes += children[i].nodes - 1;
		}
	return out;
}

/** The pruned tree's root: a pass where every depth may collapse, then, if
 *  prune() would have stopped early, one with its last depth as the limit. */
EncodedNode encodeRoot(const octomap::OcTree& tree, const octomap::OcTreeNode* root)
{
	const unsigned depths = tree.getTreeDepth();
	Encoder all{tree, 1, std::vector<std::size_t>(depths + 1, 0)};
	EncodedNode out = all.encode(root, 0);
	unsigned last = depths - 1;  // prune()'s last pass
	while (last > 1 && all.collapsed[last] > 0) --last;
	if (last == 1) return out;
	Encoder limited{tree, last, std::vector<std::size_t>(depths + 1, 0)};
	return limited.encode(root, 0);
}
}  // namespace

std::string binaryTreeBytes(const octomap::OcTree& tree)
{
	EncodedNode root;
	root.nodes = 0;
	if (const auto* r = tree.getRoot()) root = encodeRoot(tree, r);
	// The header as AbstractOccupancyOcTree::writeBinaryConst writes it.
	std::ostringstream s;
	s << kBinaryFileHeader << "\n# (feel free to add / change comments, but leave the first line as it is!)\n#\n";
	s << "id " << tree.getTreeType() << std::endl;
	s << "size " << root.nodes << std::endl;
	s << "res " << tree.getResolution() << std::endl;
	s << "data" << std::endl;
	s << root.bytes;
	return s.str();
}

void writeBinaryTree(const octomap::OcTree& tree, const std::filesystem::path& file)
{
	const auto bytes = binaryTreeBytes(tree);
	io::writeFileAtomically(file,
		[&](const std::filesystem::path& tmp)
		{
			std::ofstream f(tmp, std::ios::binary);
			f << bytes;
			if (!f.flush()) throw std::runtime_error(file.string() + ": cannot write");
		});
}

std::unique_ptr<octomap::OcTree> readBinaryTree(const std::filesystem::path& file)
{
	std::ifstream f(file, std::ios::binary);
	if (!f) throw std::runtime_error(file.string() + ": cannot open");
	const auto bad = [&](const std::string& why) { return std::runtime_error(file.string() + ": " + why); };
	std::string line;
	if (!std::getline(f, line) || line != kBinaryFileHeader) throw bad("not an octomap .bt file");
	std::string id;
	double resolution = 0;
	while (std::getline(f, line) && line != "data")
	{
		std::istringstream words(line);
		std::string key;
		words >> key;
		if (key == "id") words >> id;
		if (key == "res") words >> resolution;
	}
	if (id != "OcTree" || !(resolution > 0)) throw bad("not an OcTree .bt file (id '" + id + "')");
	// readBinaryData, unlike readBinary, reads the nodes without a word on stderr.
	auto tree = std::make_unique<octomap::OcTree>(resolution);
	if (f.peek() != std::char_traits<char>::eof()) tree->readBinaryData(f);
	if (f.bad() || f.fail()) throw bad("truncated octree data");
	return tree;
}
}  // namespace avm
