#include "BatchUpdate.h"

#include <algorithm>
#include <array>

#include "KeySet.h"
#include "OcTreeKeys.h"

namespace avm::detail
{
namespace
{
constexpr unsigned kDepth = kKeyBits;

/** Spreads the 16 bits of v to every third bit. */
inline std::uint64_t spread3(std::uint64_t v)
{
	v &= kKeyMask;
	v = (v | (v << 16)) & 0x0000FF0000FFull;
	v = (v | (v << 8)) & 0x00F00F00F00Full;
	v = (v | (v << 4)) & 0x0C30C30C30C3ull;
	v = (v | (v << 2)) & 0x249249249249ull;
	return v;
}

/** Inverse of spread3: every third bit, from bit 0, packed into 16 bits. */
inline std::uint64_t compact3(std::uint64_t v)
{
	v &= 0x249249249249ull;
	v = (v | (v >> 2)) & 0x0C30C30C30C3ull;
	v = (v | (v >> 4)) & 0x00F00F00F00Full;
	v = (v | (v >> 8)) & 0x0000FF0000FFull;
	v = (v | (v >> 16)) & kKeyMask;
	return v;
}

/** Bits of level b of the three key components form octomap's child index
 *  (k0 -> 1, k1 -> 2, k2 -> 4) in group b, most significant level first. */
inline std::uint64_t mortonOf(const octomap::OcTreeKey& k)
{
	return spread3(k[0]) | (spread3(k[1]) << 1) | (spread3(k[2]) << 2);
}

inline octomap::OcTreeKey keyOfMorton(std::uint64_t morton)
{
	return octomap::OcTreeKey(static_cast<octomap::key_type>(compact3(morton)),
		static_cast<octomap::key_type>(compact3(morton >> 1)), static_cast<octomap::key_type>(compact3(morton >> 2)));
}

/** Child index at `depth` (root = 0) of the key with this Morton code. */
inline unsigned childAt(std::uint64_t morton, unsigned depth)
{
	return static_cast<unsigned>((morton >> (3 * (kDepth - 1 - depth))) & 7u);
}

/** Deepest depth whose node both keys pass through. */
inline unsigned sharedDepth(std::uint64_t a, std::uint64_t b)
{
	const std::uint64_t x = a ^ b;
	if (x == 0) return kDepth;
	const unsigned highest = 63u - static_cast<unsigned>(__builtin_clzll(x));
	return kDepth - 1 - highest / 3;
}
}  // namespace

void BatchUpdate::add(std::uint64_t packed, bool hit) { m_updates.push_back(mortonOf(unpackKey(packed)) << 1 | hit); }

void BatchUpdate::sortByMorton()
{
	// LSD radix sort on the 48-bit codes (above the hit bit), 8 bits a
	// pass. The keys of one scan share most high bits: passes over digits
	// that no two codes differ in are skipped.
	std::uint64_t varying = 0;
	for (const auto u : m_updates) varying |= u ^ m_updates.front();
	m_scratch.resize(m_updates.size());
	for (unsigned shift = 1; shift < 49; shift += 8)
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
