// A pose as Ceres optimises it in the back end: the angle-axis and the
// translation of T_cw (p_camera = R p_world + t), six doubles.
#pragma once

#include <ceres/rotation.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>

namespace avm::odometry::detail
{
using PoseParams = std::array<double, 6>;

inline PoseParams toParams(const Eigen::Isometry3d& T)
{
	PoseParams p;
	const Eigen::Matrix3d R = T.rotation();
	ceres::RotationMatrixToAngleAxis(ceres::ColumnMajorAdapter3x3(R.data()), p.data());
	for (int i = 0; i < 3; ++i) p[3 + i] = T.translation()[i];
	return p;
}

inline bool isFinite(const PoseParams& p)
{
	for (const double v : p)
		if (!std::isfinite(v)) return false;
	return true;
}

/** The pose of the parameters, or `fallback` if Ceres left something non-finite. */
inline Eigen::Isometry3d fromParams(const PoseParams& p, const Eigen::Isometry3d& fallback)
{
	if (!isFinite(p)) return fallback;
	Eigen::Matrix3d R;
	ceres::AngleAxisToRotationMatrix(p.data(), ceres::ColumnMajorAdapter3x3(R.data()));
	Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
	T.linear() = R;
	T.translation() << p[3], p[4], p[5];
	return T;
}
}  // namespace avm::odometry::detail
