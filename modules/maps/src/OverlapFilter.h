// Algorithm 2 of Choi & Shin (2025), overlap filtering, in one place: once the
// paper policy has switched, a point goes into the high tree, and the map
// shows a high voxel, only where the low tree has no node. The ray integrator
// (what is inserted) and the queries (what is shown) both ask here, so the
// map never represents the same space twice.
#pragma once

#include <mrpt/math/TPoint3D.h>
#include <octomap/OcTree.h>

namespace avm::detail
{
/** True where the high tree may map or show the point `p`. Because the high
 *  resolution divides the low one, a high voxel lies in exactly one low voxel,
 *  so testing its centre tests all of it. */
inline bool overlapFilterAdmits(const octomap::OcTree& low, const mrpt::math::TPoint3D& p)
{
	return low.search(p.x, p.y, p.z) == nullptr;
}
}  // namespace avm::detail
