// Where a camera is, from the T_cw (world to camera) the odometry keeps.
#pragma once

#include <Eigen/Geometry>

namespace avm::test
{
inline Eigen::Vector3d centreOf(const Eigen::Isometry3d& T_cw) { return T_cw.inverse().translation(); }
}  // namespace avm::test
