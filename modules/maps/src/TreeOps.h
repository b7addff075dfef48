// Small octree helpers shared by the map's source files.
#pragma once

#include <mrpt/math/TBoundingBox.h>
#include <octomap/OcTree.h>

#include <memory>

#include "OcTreeKeys.h"
#include "avm/maps/CAdaptiveOctoMap.h"

namespace avm::detail
{
/** An empty tree with the options' resolution and sensor model. */
std::unique_ptr<octomap::OcTree> makeTree(const CAdaptiveOctoMap::TTreeOptions& o);

/** Deletes everything `tree` holds inside `range` (pruned leaves that reach
 *  out of it are split first). */
void eraseKeyRange(octomap::OcTree& tree, const KeyRange& range);

inline mrpt::math::TPoint3D toTPoint(const octomap::point3d& p) { return {p.x(), p.y(), p.z()}; }
}  // namespace avm::detail
