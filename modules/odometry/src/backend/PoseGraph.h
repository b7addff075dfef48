// The pose graph of loop closing: keyframe poses tied by the odometry's
// relative motions between consecutive keyframes and by verified loop
// constraints, optimised together with Ceres so that a loop's correction is
// spread along the path that drifted instead of landing on one keyframe.
#pragma once

#include <Eigen/Geometry>

#include <map>
#include <vector>

namespace avm::odometry::detail
{
/** A relative-pose measurement between keyframes `from` and `to`:
 *  T_to_from = T_cw(to) * T_cw(from)^-1 (camera `from` to camera `to`), with
 *  its standard deviations. */
struct PoseGraphEdge
{
	int from = -1, to = -1;
	Eigen::Isometry3d T_to_from = Eigen::Isometry3d::Identity();
	double sigmaTranslation = 0.01;  //!< [m]
	double sigmaRotation = 0.01;     //!< [rad]
	/** Huber-robust (loop constraints: one may be wrong), else plain least squares. */
	bool robust = false;
};

struct PoseGraphResult
{
	bool usable = false;  //!< Ceres returned a finite solution
	double initialCost = 0, finalCost = 0;
	/** The poses (T_cw) of every node, optimised; the fixed nodes unchanged. */
	std::map<int, Eigen::Isometry3d> poses;
};

/** Optimises the poses T_cw of `nodes` (by id) under `edges` (edges naming a
 *  node that is not there are left out), holding the nodes of ids up to
 *  `fixedUpTo` (the gauge), which come back exactly as given;
 *  single-threaded, so the same graph always gives the same poses. */
PoseGraphResult optimisePoseGraph(const std::map<int, Eigen::Isometry3d>& nodes,
	const std::vector<PoseGraphEdge>& edges, int fixedUpTo, int iterations);
}  // namespace avm::odometry::detail
