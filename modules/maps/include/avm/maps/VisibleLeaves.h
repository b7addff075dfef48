// The leaves a dual-octree map shows, walked in one place: the map itself (its
// stats, scene, pictures) and avm-view's snapshot of a finished run (the trees
// read back from map_low.bt / map_high.bt) both walk them here, so what
// Algorithm 2 hides is decided once (src/OverlapFilter.h).
#pragma once

#include <functional>

#include "avm/maps/MapTypes.h"

namespace octomap
{
class OcTree;
}

namespace avm
{
/** Calls `visit` for every leaf of `tree`, except, when `hiddenBy` is given
 *  (the low tree, for the high tree of a paper-policy map), the leaves whose
 *  centre `hiddenBy` has a node at (Algorithm 2). */
void forEachVisibleLeaf(
	const octomap::OcTree& tree, const octomap::OcTree* hiddenBy, const std::function<void(const TLeafVoxel&)>& visit);
}  // namespace avm
