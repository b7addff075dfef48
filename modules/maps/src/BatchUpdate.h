// One scan's octree updates in a single depth-first sweep: keys sorted in
// Morton order share their path from the root with the previous key, so each
// node is visited once per scan instead of once per key (octomap's updateNode
// searches and then descends 16 levels for every key). Gives the same tree as
// calling updateNode(key, occupied) for every key (clamping, early abort at
// the clamping thresholds, pruning, inner-node maxima).
#pragma once

#include <octomap/OcTree.h>

#include <cstdint>
#include <vector>

namespace avm::detail
{
class BatchUpdate
{
   public:
	void clear() { m_updates.clear(); }
	/** `packed` as packKey(); hit = occupied measurement, else a miss. */
	void add(std::uint64_t packed, bool hit);
	/** Applies the collected updates to `tree` and clears them. */
	void applyTo(octomap::OcTree& tree);

   private:
	/** Morton code << 1 | hit: one word, so that sorting moves little. */
	using Update = std::uint64_t;
	void sortByMorton();

	std::vector<Update> m_updates, m_scratch;
};
}  // namespace avm::detail
