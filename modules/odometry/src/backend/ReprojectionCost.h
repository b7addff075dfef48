// Ceres residual of one observation: the reprojection error in pixels and,
// weighted, the depth error in the same pixel units (fx * (z - d) / d, the
// image shift a lateral error of that size would cause at that depth).
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>

#include "../Types.h"

namespace avm::odometry::detail
{
class ReprojectionDepthCost
{
   public:
	ReprojectionDepthCost(const Observation& obs, const io::DepthCamera& K, double depthWeight)
		: m_u(obs.pixel.x()), m_v(obs.pixel.y()), m_depth(obs.depth), m_K(K), m_depthWeight(depthWeight)
	{
	}

	/** pose = T_cw as angle-axis (3) then translation (3); point in the world. */
	template <typename T>
	bool operator()(const T* const pose, const T* const point, T* residual) const
	{
		T pc[3];
		ceres::AngleAxisRotatePoint(pose, point, pc);
		pc[0] += pose[3];
		pc[1] += pose[4];
		pc[2] += pose[5];
		if (pc[2] < T(1e-3)) pc[2] = T(1e-3);  // keeps a point that slipped behind finite
		T pixel[2];
		m_K.opticalPixelOf(pc, pixel);
		residual[0] = pixel[0] - T(m_u);
		residual[1] = pixel[1] - T(m_v);
		residual[2] = T(m_depthWeight * m_K.fx / m_depth) * (pc[2] - T(m_depth));
		return true;
	}

	static ceres::CostFunction* create(const Observation& obs, const io::DepthCamera& K, double depthWeight)
	{
		return new ceres::AutoDiffCostFunction<ReprojectionDepthCost, 3, 6, 3>(
			new ReprojectionDepthCost(obs, K, depthWeight));
	}

   private:
	double m_u, m_v, m_depth;
	io::DepthCamera m_K;
	double m_depthWeight;
};
}  // namespace avm::odometry::detail
