// Small octree helpers shared by the map's source files.
#pragma once

#include <mrpt/math/TBoundingBox.h>
#include <octomap/OcTree.h>

#include <memory>
#include <vector>

#include "OcTreeKeys.h"
#include "avm/maps/MapTypes.h"

namespace avm::detail
{
/** An empty tree with the options' resolution and sensor model. */
std::unique_ptr<octomap::OcTree> makeTree(const TTreeOptions& o);

/** Deletes everything `tree` holds inside `range` (pruned leaves that reach
 *  out of it are split first). */
void eraseKeyRange(octomap::OcTree& tree, const KeyRange& range);

/** The same tree as tree.setNodeValue(k, logOdds) for each of `keys` in
 *  turn, when none of them is known in `tree` (so none lies under a pruned
 *  leaf). octomap prunes or updates every node on a key's path after each
 *  key; here each node is pruned or updated once, after all the keys, deepest
 *  first, which is what the last key's pass leaves: a node collapses only
 *  once every key under it is set, and none is set under it afterwards. */
void setNodeValues(octomap::OcTree& tree, const std::vector<octomap::OcTreeKey>& keys, float logOdds);

inline mrpt::math::TPoint3D toTPoint(const octomap::point3d& p) { return {p.x(), p.y(), p.z()}; }
}  // namespace avm::detail
