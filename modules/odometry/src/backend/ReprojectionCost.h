// Ceres residual of one observation: the reprojection error in pixels and,
// weighted, the depth error in the same pixel units (fx * (z - d) / d, the
// image shift a lateral error of that size would cause at that depth).
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>

#include <array>

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
	template <typename T, typename P>
	bool operator()(const T* const pose, const P* const point, T* residual) const
	{
		const T p[3] = {T(point[0]), T(point[1]), T(point[2])};
		T pc[3];
		ceres::AngleAxisRotatePoint(pose, p, pc);
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

	/** The residual of a pose and a point that both move (bundle adjustment). */
	static ceres::CostFunction* create(const Observation& obs, const io::DepthCamera& K, double depthWeight)
	{
		return new ceres::AutoDiffCostFunction<ReprojectionDepthCost, 3, 6, 3>(
			new ReprojectionDepthCost(obs, K, depthWeight));
	}

	/** The residual of a pose against a fixed point (tracking): Ceres then
	 *  differentiates 6 parameters instead of 9, the same derivatives. */
	static ceres::CostFunction* createFixedPoint(
		const Observation& obs, const Eigen::Vector3d& point, const io::DepthCamera& K, double depthWeight);

   private:
	double m_u, m_v, m_depth;
	io::DepthCamera m_K;
	double m_depthWeight;
};

/** ReprojectionDepthCost with its point held in the functor. */
struct FixedPointReprojectionDepthCost
{
	template <typename T>
	bool operator()(const T* const pose, T* residual) const
	{
		return cost(pose, point.data(), residual);
	}
	ReprojectionDepthCost cost;
	std::array<double, 3> point;
};

inline ceres::CostFunction* ReprojectionDepthCost::createFixedPoint(
	const Observation& obs, const Eigen::Vector3d& point, const io::DepthCamera& K, double depthWeight)
{
	return new ceres::AutoDiffCostFunction<FixedPointReprojectionDepthCost, 3, 6>(new FixedPointReprojectionDepthCost{
		ReprojectionDepthCost(obs, K, depthWeight), {point.x(), point.y(), point.z()}});
}
}  // namespace avm::odometry::detail
