#include "CeresBackend.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <functional>
#include <limits>
#include <unordered_map>

#include "PoseParams.h"
#include "ReprojectionCost.h"

namespace avm::odometry::detail
{
namespace
{
ceres::Solver::Options solverOptions(int iterations, int threads, ceres::LinearSolverType solver)
{
	ceres::Solver::Options o;
	o.linear_solver_type = solver;
	o.max_num_iterations = iterations;
	o.num_threads = threads;
	o.logging_type = ceres::SILENT;
	o.minimizer_progress_to_stdout = false;
	return o;
}

/** The camera centre -R^T t of a pose against its prior, over the prior's
 *  sigma: in standard deviations, as the pixel residuals beside it are (about
 *  a pixel of noise each), so that Ceres weighs the two fairly. */
struct CentrePriorCost
{
	template <typename T>
	bool operator()(const T* pose, T* residual) const
	{
		const T inverse[3] = {-pose[0], -pose[1], -pose[2]};
		T rotated[3];
		ceres::AngleAxisRotatePoint(inverse, pose + 3, rotated);
		for (int i = 0; i < 3; ++i) residual[i] = (-rotated[i] - T(prior.centre[i])) / T(prior.sigma);
		return true;
	}
	CeresBackend::CentrePrior prior;
};

/** One robust reprojection-and-depth residual per observation of a fixed landmark, on `pose`. */
std::vector<ceres::ResidualBlockId> addObservations(ceres::Problem& problem, ceres::LossFunction& loss,
	PoseParams& pose, const std::vector<Observation>& observations, const LandmarkMap& landmarks,
	const io::DepthCamera& K, double depthWeight)
{
	std::vector<ceres::ResidualBlockId> blocks;
	for (const auto& o : observations)
		blocks.push_back(problem.AddResidualBlock(
			ReprojectionDepthCost::createFixedPoint(o, landmarks.at(o.landmark).position, K, depthWeight), &loss,
			pose.data()));
	return blocks;
}
}  // namespace

void CeresBackend::refinePose(Eigen::Isometry3d& T_cw, const std::vector<Observation>& observations,
	const LandmarkMap& landmarks, const io::DepthCamera& K, const std::optional<CentrePrior>& prior) const
{
	if (m_options.refine_iterations == 0 || observations.empty()) return;
	PoseParams pose = toParams(T_cw);
	ceres::Problem::Options po;
	po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
	ceres::Problem problem(po);
	ceres::HuberLoss loss(m_options.huber_delta);
	addObservations(problem, loss, pose, observations, landmarks, K, m_options.depth_weight);
	if (prior)
		problem.AddResidualBlock(
			new ceres::AutoDiffCostFunction<CentrePriorCost, 3, 6>(new CentrePriorCost{*prior}), nullptr, pose.data());
	ceres::Solver::Summary summary;
	// Six parameters: the normal equations are 6x6, where QR factors the whole
	// Jacobian (three rows an inlier); the pose is well conditioned, and the
	// trajectories came out the same to the byte (sub300, the whole sequence).
	ceres::Solve(solverOptions(m_options.refine_iterations, m_options.threads, ceres::DENSE_NORMAL_CHOLESKY), &problem,
		&summary);
	T_cw = fromParams(pose, T_cw);
}

std::optional<CeresBackend::RefinedPose> CeresBackend::refinePnp(const FrameFeatures& f,
	const FeatureFrontend::PnpResult& pnp, const std::vector<Match>& matches, const LandmarkMap& landmarks,
	const std::optional<CentrePrior>& prior) const
{
	RefinedPose r{pnp.T_cw, pnp.inliers, 0};
	for (int round = 0; round < m_options.refine_rounds && !r.inliers.empty(); ++round)
	{
		refinePose(r.T_cw, observationsOf(f, r.inliers), landmarks, f.K, prior);
		if (!r.T_cw.matrix().allFinite()) return std::nullopt;
		auto inliers = inliersAt(r.T_cw, f, matches, landmarks, m_options.ransac_reprojection, r.squaredErrors);
		// The same inliers again: the pose is already their refinement.
		const bool settled = std::equal(inliers.begin(), inliers.end(), r.inliers.begin(), r.inliers.end(),
			[](const Match& a, const Match& b) { return a.feature == b.feature && a.landmark == b.landmark; });
		r.inliers = std::move(inliers);
		if (settled) break;
	}
	r.centreCovariance = centreCovariance(r.T_cw, observationsOf(f, r.inliers), landmarks, f.K);
	return r;
}

Eigen::Matrix3d CeresBackend::centreCovariance(const Eigen::Isometry3d& T_cw,
	const std::vector<Observation>& observations, const LandmarkMap& landmarks, const io::DepthCamera& K) const
{
	const Eigen::Matrix3d unknown = Eigen::Matrix3d::Identity() * std::numeric_limits<double>::infinity();
	const int rows = 3 * int(observations.size());
	if (rows <= 6) return unknown;
	PoseParams pose = toParams(T_cw);
	// The robust problem's Jacobian and residuals as Ceres evaluates them, without
	// building a Problem: each residual and its Jacobian scaled by sqrt(rho'),
	// which is Ceres' correction for a loss whose rho'' <= 0, as Huber's is.
	const ceres::HuberLoss loss(m_options.huber_delta);
	Eigen::Matrix<double, 6, 6> JtJ = Eigen::Matrix<double, 6, 6>::Zero();
	double squares = 0;
	for (const auto& o : observations)
	{
		Eigen::Vector3d residual;
		Eigen::Matrix<double, 3, 6, Eigen::RowMajor> J;
		ReprojectionDepthCost(o, K, m_options.depth_weight)
			.evaluate(pose.data(), landmarks.at(o.landmark).position.data(), residual.data(), J.data(), nullptr);
		if (!residual.allFinite() || !J.allFinite()) return unknown;
		double rho[3];
		loss.Evaluate(Eigen::Map<const Eigen::VectorXd>(residual.data(), 3).squaredNorm(), rho);
		const double scale = std::sqrt(rho[1]);
		J *= scale;
		residual *= scale;
		for (int row = 0; row < 3; ++row) JtJ += J.row(row).transpose() * J.row(row);
		for (int row = 0; row < 3; ++row) squares += residual[row] * residual[row];
	}
	const Eigen::FullPivLU<Eigen::Matrix<double, 6, 6>> lu(JtJ);
	if (!lu.isInvertible()) return unknown;
	const Eigen::Matrix<double, 6, 6> poseCovariance = squares / double(rows - 6) * lu.inverse();
	// The centre's Jacobian in the pose parameters: the prior's cost at unit sigma is the centre itself.
	const CentrePriorCost centre{CentrePrior{Eigen::Vector3d::Zero(), 1.0}};
	ceres::AutoDiffCostFunction<CentrePriorCost, 3, 6> centreOf(new CentrePriorCost(centre));
	double c[3];
	Eigen::Matrix<double, 3, 6, Eigen::RowMajor> G;
	double* jacobians[1] = {G.data()};
	const double* parameters[1] = {pose.data()};
	if (!centreOf.Evaluate(parameters, c, jacobians)) return unknown;
	return G * poseCovariance * G.transpose();
}

void CeresBackend::bundleAdjust(const std::deque<Keyframe>& window, std::vector<Eigen::Isometry3d>& windowPoses,
	LandmarkMap& landmarks, const io::DepthCamera& K) const
{
	if (window.size() < 2) return;
	std::unordered_map<int, int> seenBy;
	for (const auto& kf : window)
		for (const auto& o : kf.observations) ++seenBy[o.landmark];

	std::vector<PoseParams> poses;
	for (const auto& T : windowPoses) poses.push_back(toParams(T));
	std::unordered_map<int, std::array<double, 3>> points;
	// The landmarks seen most often tie the window together best; a cap on
	// their number bounds the time a keyframe takes. The anchored points (a
	// joined place's, held fixed; one view ties a pose to them) have a cap
	// of their own: a continued session's window sees up to 1,700 of them,
	// which tripled its residuals, and letting them take the free points'
	// share instead made the continuations' trajectories worse.
	std::vector<std::pair<int, int>> unanchored, anchoredRanked;  // (views, id)
	for (const auto& [id, n] : seenBy)
		if (landmarks.at(id).anchored)
			anchoredRanked.emplace_back(n, id);
		else if (n >= 2)
			unanchored.emplace_back(n, id);
	const auto keepMostViewed = [cap = m_options.ba_max_landmarks](std::vector<std::pair<int, int>>& ranked)
	{
		if (cap <= 0 || ranked.size() <= std::size_t(cap)) return;
		std::nth_element(ranked.begin(), ranked.begin() + cap, ranked.end(), std::greater<>());
		ranked.resize(std::size_t(cap));
	};
	keepMostViewed(unanchored);
	keepMostViewed(anchoredRanked);
	std::vector<int> inProblem, anchored;
	for (const auto& [n, id] : unanchored) inProblem.push_back(id);
	for (const auto& [n, id] : anchoredRanked) anchored.push_back(id);
	inProblem.insert(inProblem.end(), anchored.begin(), anchored.end());
	for (const int id : inProblem)
	{
		const auto& p = landmarks.at(id).position;
		points[id] = {p.x(), p.y(), p.z()};
	}
	if (points.empty()) return;

	ceres::Problem::Options po;
	po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
	ceres::Problem problem(po);
	ceres::HuberLoss loss(m_options.huber_delta);
	for (std::size_t k = 0; k < window.size(); ++k)
		for (const auto& o : window[k].observations)
		{
			auto it = points.find(o.landmark);
			if (it == points.end()) continue;
			problem.AddResidualBlock(
				ReprojectionDepthCost::create(o, K, m_options.depth_weight), &loss, poses[k].data(), it->second.data());
		}
	if (!problem.HasParameterBlock(poses.front().data())) return;  // nothing ties the window to its anchor
	for (const int id : anchored)
		if (problem.HasParameterBlock(points[id].data())) problem.SetParameterBlockConstant(points[id].data());
	// Anchored points hold the window where the place is only while some
	// keyframe sees as many of them as a tracked pose needs; a few of them
	// leave the window free to turn about them (after a loop it ran away by
	// up to 15 cm a keyframe on the whole Bonn sequence, and a keyframe was
	// made at every frame), so the oldest pose holds it then.
	std::size_t mostAnchoredSeen = 0;
	if (!anchored.empty())
		for (const auto& kf : window)
			mostAnchoredSeen = std::max(
				mostAnchoredSeen, std::size_t(std::count_if(kf.observations.begin(), kf.observations.end(),
									  [&](const Observation& o)
									  { return points.count(o.landmark) && landmarks.at(o.landmark).anchored; })));
	if (mostAnchoredSeen < std::size_t(m_options.min_inliers)) problem.SetParameterBlockConstant(poses.front().data());
	ceres::Solver::Summary summary;
	ceres::Solve(solverOptions(m_options.ba_iterations, m_options.threads, ceres::DENSE_SCHUR), &problem, &summary);
	if (!summary.IsSolutionUsable()) return;

	for (std::size_t k = 0; k < window.size(); ++k) windowPoses[k] = fromParams(poses[k], windowPoses[k]);
	for (const auto& [id, p] : points)
		if (std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))
			landmarks.at(id).position = Eigen::Vector3d(p[0], p[1], p[2]);
}
}  // namespace avm::odometry::detail
