// Ceres residual of one observation: the reprojection error in pixels and,
// weighted, the depth error in the same pixel units (fx * (z - d) / d, the
// image shift a lateral error of that size would cause at that depth).
// Its Jacobian is written out (ReprojectionCost.cpp): the per-frame
// refinement evaluates it for every inlier in every iteration, and automatic
// differentiation through the angle-axis rotation was the largest part of the
// refinement's time (doc/decisions.md, "The refinement stays Ceres").
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "../Types.h"

namespace avm::odometry::detail
{
struct RotationTerms;  // what the residual needs of a pose's rotation alone (ReprojectionCost.cpp)

class ReprojectionDepthCost
{
   public:
	ReprojectionDepthCost(const Observation& obs, const io::DepthCamera& K, double depthWeight)
		: m_u(obs.pixel.x()), m_v(obs.pixel.y()), m_depth(obs.depth), m_K(K), m_depthWeight(depthWeight)
	{
	}

	/** The residual of `pose` = T_cw (angle-axis (3) then translation (3))
	 *  and `point` in the world; each Jacobian (row-major, 3x6 and 3x3) is
	 *  written when not null. */
	void evaluate(
		const double* pose, const double* point, double* residual, double* poseJacobian, double* pointJacobian) const;
	/** The same with the pose's rotation terms worked out already. */
	void evaluate(const RotationTerms& terms, const double* pose, const double* point, double* residual,
		double* poseJacobian, double* pointJacobian) const;

	/** The residual of a pose and a point that both move (bundle adjustment). */
	static ceres::CostFunction* create(const Observation& obs, const io::DepthCamera& K, double depthWeight);

	/** The residual of a pose against a fixed point (tracking): Ceres then
	 *  solves for 6 parameters instead of 9, the same derivatives. */
	static ceres::CostFunction* createFixedPoint(
		const Observation& obs, const Eigen::Vector3d& point, const io::DepthCamera& K, double depthWeight);

   private:
	double m_u, m_v, m_depth;
	io::DepthCamera m_K;
	double m_depthWeight;
};
}  // namespace avm::odometry::detail
