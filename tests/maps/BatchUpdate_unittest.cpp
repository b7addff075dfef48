// The Morton-ordered batch sweep must give exactly the tree that octomap's
// own updateNode() gives for the same updates (clamping, early stop at the
// clamping thresholds, pruning, inner-node maxima), on real scans.
#include <gtest/gtest.h>

#include <map>
#include <tuple>

#include "BatchUpdate.h"
#include "BonnFrames.h"
#include "KeySet.h"

namespace
{
std::map<std::tuple<int, int, int, int>, float> leavesOf(const octomap::OcTree& t)
{
	std::map<std::tuple<int, int, int, int>, float> out;
	for (auto it = t.begin_leafs(); it != t.end_leafs(); ++it)
		out[{it.getKey()[0], it.getKey()[1], it.getKey()[2], static_cast<int>(it.getDepth())}] = it->getLogOdds();
	return out;
}
}  // namespace

TEST(BatchUpdate, GivesTheSameTreeAsUpdateNodeOnBonnScans)
{
	// Every 4th of the first 60 frames: enough repeats to reach the clamping
	// thresholds and make octomap prune.
	const auto frames = avm::test::bonnFrames(60, 4);
	for (const double res : {0.05, 0.2})
	{
		octomap::OcTree reference(res), batched(res);
		avm::detail::BatchUpdate batch;
		for (const auto& f : frames)
		{
			const auto cloud = avm::test::worldCloud(f);
			octomap::KeySet freeCells, occupiedCells;
			reference.computeUpdate(cloud.points, cloud.origin, freeCells, occupiedCells, 5.0);
			for (const auto& k : freeCells) reference.updateNode(k, false);
			for (const auto& k : occupiedCells) reference.updateNode(k, true);
			for (const auto& k : freeCells) batch.add(avm::detail::packKey(k), false);
			for (const auto& k : occupiedCells) batch.add(avm::detail::packKey(k), true);
			batch.applyTo(batched);
		}
		ASSERT_GT(reference.size(), 1000u);
		EXPECT_EQ(batched.size(), reference.size()) << "resolution " << res;
		EXPECT_TRUE(leavesOf(batched) == leavesOf(reference)) << "resolution " << res;
		// Inner nodes hold their children's maximum, as octomap keeps them.
		EXPECT_EQ(batched.getRoot()->getLogOdds(), reference.getRoot()->getLogOdds());
	}
}
