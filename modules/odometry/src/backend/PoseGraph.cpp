#include "PoseGraph.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <array>

#include "PoseParams.h"

namespace avm::odometry::detail
{
namespace
{
/** The error of T_to * T_from^-1 against the measurement, as the angle-axis
 *  and translation of Z^-1 * T_to * T_from^-1, each over its sigma. */
struct RelativePoseCost
{
	explicit RelativePoseCost(const PoseGraphEdge& e)
	{
		const Eigen::Isometry3d Zinv = e.T_to_from.inverse();
		Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(zR.data()) = Zinv.rotation();
		for (int i = 0; i < 3; ++i) zt[i] = Zinv.translation()[i];
		wt = 1.0 / e.sigmaTranslation;
		wr = 1.0 / e.sigmaRotation;
	}

	template <typename T>
	bool operator()(const T* from, const T* to, T* residual) const
	{
		// Rotation matrices (row-major) of both poses.
		T Rf[9], Rt[9];
		ceres::AngleAxisToRotationMatrix(from, ceres::RowMajorAdapter3x3(Rf));
		ceres::AngleAxisToRotationMatrix(to, ceres::RowMajorAdapter3x3(Rt));
		// T_to * T_from^-1: R = Rt Rf^T, t = t_to - R t_from.
		T R[9], t[3];
		for (int r = 0; r < 3; ++r)
			for (int c = 0; c < 3; ++c)
				R[3 * r + c] = Rt[3 * r] * Rf[3 * c] + Rt[3 * r + 1] * Rf[3 * c + 1] + Rt[3 * r + 2] * Rf[3 * c + 2];
		for (int r = 0; r < 3; ++r)
			t[r] = to[3 + r] - (R[3 * r] * from[3] + R[3 * r + 1] * from[4] + R[3 * r + 2] * from[5]);
		// Z^-1 * (R, t).
		T E[9], et[3];
		for (int r = 0; r < 3; ++r)
		{
			for (int c = 0; c < 3; ++c)
				E[3 * r + c] = T(zR[3 * r]) * R[c] + T(zR[3 * r + 1]) * R[3 + c] + T(zR[3 * r + 2]) * R[6 + c];
			et[r] = T(zR[3 * r]) * t[0] + T(zR[3 * r + 1]) * t[1] + T(zR[3 * r + 2]) * t[2] + T(zt[r]);
		}
		T angleAxis[3];
		ceres::RotationMatrixToAngleAxis(ceres::RowMajorAdapter3x3<const T>(E), angleAxis);
		for (int i = 0; i < 3; ++i)
		{
			residual[i] = angleAxis[i] * T(wr);
			residual[3 + i] = et[i] * T(wt);
		}
		return true;
	}

	std::array<double, 9> zR;
	std::array<double, 3> zt;
	double wt, wr;
};
}  // namespace

PoseGraphResult optimisePoseGraph(const std::map<int, Eigen::Isometry3d>& nodes,
	const std::vector<PoseGraphEdge>& edges, int fixedUpTo, int iterations)
{
	PoseGraphResult result;
	std::map<int, PoseParams> params;
	for (const auto& [id, T] : nodes) params[id] = toParams(T);

	ceres::Problem problem;
	// A whitened residual beyond 2 sigma counts linearly: one wrong loop pulls
	// less than a right one holds.
	for (const auto& e : edges)
	{
		const auto from = params.find(e.from), to = params.find(e.to);
		if (from == params.end() || to == params.end() || e.from == e.to) continue;
		auto* cost = new ceres::AutoDiffCostFunction<RelativePoseCost, 6, 6, 6>(new RelativePoseCost(e));
		problem.AddResidualBlock(
			cost, e.robust ? new ceres::HuberLoss(2.0) : nullptr, from->second.data(), to->second.data());
	}
	for (auto& [id, p] : params)
		if (id <= fixedUpTo && problem.HasParameterBlock(p.data())) problem.SetParameterBlockConstant(p.data());

	ceres::Solver::Options options;
	options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
	options.max_num_iterations = iterations;
	options.num_threads = 1;
	options.logging_type = ceres::SILENT;
	ceres::Solver::Summary summary;
	ceres::Solve(options, &problem, &summary);
	result.initialCost = summary.initial_cost;
	result.finalCost = summary.final_cost;
	result.usable = summary.IsSolutionUsable();
	for (const auto& [id, p] : params)
	{
		result.usable = result.usable && isFinite(p);
		result.poses[id] = id <= fixedUpTo ? nodes.at(id) : fromParams(p, nodes.at(id));
	}
	return result;
}
}  // namespace avm::odometry::detail
