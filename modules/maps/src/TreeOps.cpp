#include "TreeOps.h"

#include <algorithm>
#include <vector>

namespace avm::detail
{
std::unique_ptr<octomap::OcTree> makeTree(const TTreeOptions& o)
{
	auto t = std::make_unique<octomap::OcTree>(o.resolution);
	t->setProbHit(o.probHit);
	t->setProbMiss(o.probMiss);
	t->setClampingThresMin(o.clampingThresMin);
	t->setClampingThresMax(o.clampingThresMax);
	t->setOccupancyThres(o.occupancyThres);
	return t;
}

namespace
{
/** Removes the node at `target` depth containing `key` below `node` (at
 *  `depth`); true when `node` is left without children and must go too.
 *  The removed node must be a leaf (or a pruned leaf above `target`, which is
 *  split on the way down). octomap 1.9.7's own deleteNode() deletes such an
 *  emptied inner node with its (empty) child array still allocated, which its
 *  node destructor asserts against, and its deleteNodeChild() counts a whole
 *  subtree as one node: hence leaf by leaf. */
bool eraseRecurs(
	octomap::OcTree& t, octomap::OcTreeNode* node, unsigned depth, const octomap::OcTreeKey& key, unsigned target)
{
	if (depth == target) return true;
	const unsigned pos = octomap::computeChildIdx(key, static_cast<int>(t.getTreeDepth() - 1 - depth));
	if (!t.nodeChildExists(node, pos))
	{
		if (t.nodeHasChildren(node) || node == t.getRoot()) return false;  // nothing there
		t.expandNode(node);                                                // a pruned leaf: split it to remove a part
	}
	auto* child = t.getNodeChild(node, pos);
	if (!eraseRecurs(t, child, depth + 1, key, target)) return false;
	// Free the child's child array (allocated even when emptied): give it 8
	// equal children and prune them, which releases the array through
	// octomap's public API; then the child can be deleted safely.
	t.expandNode(child);
	t.pruneNode(child);
	t.deleteNodeChild(node, pos);
	if (!t.nodeHasChildren(node)) return node != t.getRoot();
	node->updateOccupancyChildren();
	return false;
}

void eraseNode(octomap::OcTree& t, const octomap::OcTreeKey& key, unsigned depth)
{
	if (!t.getRoot()) return;
	eraseRecurs(t, t.getRoot(), 0, key, depth);
	if (!t.nodeHasChildren(t.getRoot())) t.clear();
}
}  // namespace

void setNodeValues(octomap::OcTree& tree, const std::vector<octomap::OcTreeKey>& keys, float logOdds)
{
	if (keys.empty()) return;
	for (const auto& k : keys) tree.setNodeValue(k, logOdds, /*lazy_eval=*/true);
	// In Morton order the keys under any one node are consecutive, at every
	// depth: the nodes on their paths come each once from one pass per depth.
	std::vector<std::uint64_t> codes;
	codes.reserve(keys.size());
	for (const auto& k : keys) codes.push_back(mortonOf(k));
	std::sort(codes.begin(), codes.end());
	std::vector<octomap::OcTreeKey> mortonOrder;
	mortonOrder.reserve(codes.size());
	for (const auto code : codes) mortonOrder.push_back(keyOfMorton(code));
	auto pruneOrUpdate = [&tree](octomap::OcTreeNode* node)
	{
		if (!tree.pruneNode(node)) node->updateOccupancyChildren();
	};
	for (unsigned depth = tree.getTreeDepth() - 1; depth > 0; depth--)
	{
		bool first = true;
		octomap::OcTreeKey previous;
		for (const auto& k : mortonOrder)
		{
			const auto atDepth = tree.adjustKeyAtDepth(k, depth);
			if (!first && atDepth == previous) continue;
			first = false;
			previous = atDepth;
			// Deeper nodes are done and nothing above is pruned yet: the
			// search ends at the node itself.
			pruneOrUpdate(tree.search(atDepth, depth));
		}
	}
	// Not in the loop: octomap's search reads depth 0 as the full depth.
	pruneOrUpdate(tree.getRoot());
}

void eraseKeyRange(octomap::OcTree& tree, const KeyRange& range)
{
	if (tree.size() == 0) return;
	const unsigned maxDepth = tree.getTreeDepth();
	struct Doomed
	{
		octomap::OcTreeKey key;
		unsigned depth;
	};
	// Collect first: deleting while iterating would invalidate the iterator.
	std::vector<Doomed> doomed;
	for (auto it = tree.begin_leafs_bbx(range.first(), range.last()), end = tree.end_leafs_bbx(); it != end; ++it)
	{
		const unsigned depth = it.getDepth();
		const unsigned span = keySpanAtDepth(depth);
		// The leaf's first key: its key with the bits below its depth cleared.
		const auto key = it.getIndexKey();
		if (range.containsCube(key, span))
		{
			doomed.push_back({key, depth});
			continue;
		}
		// A pruned leaf reaching out of the range: its finest voxels inside.
		range.forEachKeyOfCube(key, span, [&](const octomap::OcTreeKey& k) { doomed.push_back({k, maxDepth}); });
	}
	for (const auto& d : doomed) eraseNode(tree, d.key, d.depth);
}
}  // namespace avm::detail
