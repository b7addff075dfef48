// Small octree helpers shared by the map's source files.
#pragma once

#include <mrpt/math/TBoundingBox.h>
#include <octomap/OcTree.h>

#include <memory>

#include "avm/maps/CAdaptiveOctoMap.h"

namespace avm::detail
{
/** An empty tree with the options' resolution and sensor model. */
std::unique_ptr<octomap::OcTree> makeTree(const CAdaptiveOctoMap::TTreeOptions& o);

/** Deletes every finest-level voxel of `tree` whose centre is in `box`
 *  (pruned leaves that straddle the box are split first). */
void deleteSpace(octomap::OcTree& tree, const mrpt::math::TBoundingBox& box);

inline mrpt::math::TPoint3D toTPoint(const octomap::point3d& p) { return {p.x(), p.y(), p.z()}; }
}  // namespace avm::detail
