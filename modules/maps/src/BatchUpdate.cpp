#include "BatchUpdate.h"

#include <algorithm>
#include <array>

#include "KeySet.h"
#include "OcTreeKeys.h"

namespace avm::detail
{
namespace
{
/** The tree's depth: a key's bits per axis (OcTreeKeys.h). */
constexpr unsigned kDepth = kKeyBits;
}  // namespace

void BatchUpdate::add(std::uint64_t packed, bool hit) { m_updates.push_back(mortonOf(unpackKey(packed)) << 1 | hit); }

void BatchUpdate::sortByMorton()
{
	// LSD radix sort on the Morton codes (above the hit bit), 8 bits a
	// pass. The keys of one scan share most high bits: passes over digits
	// that no two codes differ in are skipped.
	std::uint64_t varying = 0;
	for (const auto u : m_updates) varying |= u ^ m_updates.front();
	m_scratch.resize(m_updates.size());
	for (unsigned shift = 1; shift < 1 + kMortonBits; shift += 8)
	{
		if (((varying >> shift) & 0xFF) == 0) continue;
		std::array<std::size_t, 257> count{};
		for (const auto u : m_updates) count[((u >> shift) & 0xFF) + 1]++;
		for (unsigned i = 0; i < 256; i++) count[i + 1] += count[i];
		for (const auto u : m_updates) m_scratch[count[(u >> shift) & 0xFF]++] = u;
		m_updates.swap(m_scratch);
	}
}

void BatchUpdate::applyTo(octomap::OcTree& tree)
{
	if (m_updates.empty()) return;
	sortByMorton();
	const float hitLog = tree.getProbHitLog(), missLog = tree.getProbMissLog();
	const float clampMax = tree.getClampingThresMaxLog(), clampMin = tree.getClampingThresMinLog();
	auto saturated = [&](const octomap::OcTreeNode* n, bool hit)
	{ return hit ? n->getLogOdds() >= clampMax : n->getLogOdds() <= clampMin; };

	std::size_t begin = 0;
	if (!tree.getRoot())
	{
		// octomap creates the root only through its own update path.
		tree.updateNode(keyOfMorton(m_updates.front() >> 1), (m_updates.front() & 1) != 0);
		begin = 1;
	}
	struct Step
	{
		octomap::OcTreeNode* node;
		bool created;
	};
	std::array<Step, kDepth + 1> path{};
	path[0] = {tree.getRoot(), false};
	// path[0..reached] is the current path; path[reached] is a leaf.
	unsigned reached = 0;
	// Inner nodes of the path below `depth` are complete: prune them or give
	// them their children's maximum, deepest first.
	auto finishBelow = [&](unsigned depth)
	{
		for (unsigned d = reached; d-- > depth;)
		{
			auto* n = path[d].node;
			if (!tree.pruneNode(n)) n->updateOccupancyChildren();
		}
	};
	std::uint64_t previous = 0;
	for (std::size_t i = begin; i < m_updates.size(); i++)
	{
		const std::uint64_t morton = m_updates[i] >> 1;
		const bool hit = (m_updates[i] & 1) != 0;
		unsigned depth = i > begin ? std::min(sharedDepth(previous, morton), reached) : 0;
		finishBelow(depth + 1);
		reached = depth;
		previous = morton;
		bool skip = false;
		for (; depth < kDepth; depth++)
		{
			auto* node = path[depth].node;
			const unsigned pos = childAt(morton, depth);
			bool created = false;
			if (!tree.nodeChildExists(node, pos))
			{
				if (!tree.nodeHasChildren(node) && !path[depth].created)
				{
					// A pruned leaf: no change if it is already clamped.
					if (saturated(node, hit))
					{
						skip = true;
						break;
					}
					tree.expandNode(node);
				}
				else
				{
					tree.createNodeChild(node, pos);
					created = true;
				}
			}
			path[depth + 1] = {tree.getNodeChild(node, pos), created};
			reached = depth + 1;
		}
		if (skip) continue;
		auto* leaf = path[kDepth].node;
		if (!path[kDepth].created && saturated(leaf, hit)) continue;
		tree.updateNodeLogOdds(leaf, hit ? hitLog : missLog);
	}
	finishBelow(0);
	m_updates.clear();
}
}  // namespace avm::detail
