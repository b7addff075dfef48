// Space that changes tree: when a low voxel enters the high-resolution space
// (a person's region arrives) what the low tree knew there moves down into the
// high tree, and when it leaves (the region ends or moves on) what the high
// tree learnt there is folded back into the low voxel. Either way the voxel is
// then removed from the tree it left, so no space is held twice and nothing
// mapped is dropped: high-resolution detail is coarsened, never lost.
#pragma once

#include <octomap/OcTree.h>

#include <cstdint>

#include "SurfaceSketch.h"

namespace avm::detail
{
/** The low voxel `lowKey` (packed, KeySet.h) moves into `high`, to the high
 *  voxels `high` does not know yet. When the sketch never saw it, all of them
 *  take its log-odds (clamped to the high tree's limits, occupied stays
 *  occupied). Else the sketch's surface voxels come back occupied, as a voxel
 *  hit once (occupied low voxel) or just occupied (free low voxel), and the
 *  others stay unknown (occupied low voxel) or take its log-odds (free low
 *  voxel). `sketch` may be null. */
void refineIntoHighTree(octomap::OcTree& low, octomap::OcTree& high, std::uint64_t lowKey, SurfaceSketch* sketch);

/** The high voxels inside low voxel `lowKey` fold into it, as octomap merges
 *  children into their parent: the largest known log-odds, so the low voxel
 *  is occupied if any high voxel is, free if all known ones are free, and
 *  unknown (untouched) if none is known. The occupied high voxels become the
 *  sketch's bits of the low voxel. */
void coarsenIntoLowTree(octomap::OcTree& high, octomap::OcTree& low, std::uint64_t lowKey, SurfaceSketch& sketch);
}  // namespace avm::detail
