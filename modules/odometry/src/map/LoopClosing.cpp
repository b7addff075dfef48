#include "LoopClosing.h"

#include <mrpt/core/bits_math.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>

#include "../TrackQuality.h"

namespace avm::odometry::detail
{
namespace
{
Eigen::Vector3d cameraCentre(const Eigen::Isometry3d& T_cw)
{
	return -(T_cw.rotation().transpose() * T_cw.translation());
}

/** The share of keyframe a's points that keyframe b's camera sees: in front
 *  of it and inside its image. */
double shareSeen(const MapKeyframe& a, const MapKeyframe& b, const io::DepthCamera& K, cv::Size image)
{
	if (a.points.empty()) return 0;
	const Eigen::Isometry3d T_ba = b.T_cw * a.T_cw.inverse();
	std::size_t seen = 0;
	for (const auto& p : a.points)
	{
		const Eigen::Vector3d pb = T_ba * p;
		if (pb.z() <= 0) continue;
		const Eigen::Vector2d px = K.opticalPixelOf(pb);
		seen += px.x() >= 0 && px.y() >= 0 && px.x() < image.width && px.y() < image.height;
	}
	return double(seen) / double(a.points.size());
}

}  // namespace

std::vector<int> covisibleWith(
	int candidate, int newestId, const KeyframeMap& map, const io::DepthCamera& K, cv::Size image, int count)
{
	const MapKeyframe& c = *map.find(candidate);
	std::vector<std::pair<double, int>> shared;  // (share, id)
	for (const auto& [id, kf] : map.keyframes())
	{
		if (id > newestId) break;
		if (id == candidate) continue;
		const double share = std::min(shareSeen(c, kf, K, image), shareSeen(kf, c, K, image));
		if (share > 0) shared.emplace_back(share, id);
	}
	std::sort(shared.begin(), shared.end(), std::greater<>());
	std::vector<int> place{candidate};
	for (std::size_t i = 0; i < shared.size() && int(i) < count; ++i) place.push_back(shared[i].second);
	return place;
}

LandmarkMap placeOf(const std::vector<int>& keyframes, const KeyframeMap& map)
{
	LandmarkMap place;
	int next = 0;
	for (const int id : keyframes)
	{
		const MapKeyframe& kf = *map.find(id);
		addKeyframePoints(kf.T_cw, kf.descriptors, kf.points, next, place);
		next += kf.descriptors.rows;
	}
	return place;
}

std::optional<LoopMeasurement> measureLoop(const FrameFeatures& f, const Eigen::Isometry3d& T_cw, int newestId,
	const KeyframeMap& map, const FeatureFrontend& frontend, const CeresBackend& backend,
	const TOdometryOptions& options)
{
	// Before the vocabulary exists every keyframe is a candidate; loops wait for it.
	if (!map.trained()) return std::nullopt;
	std::optional<LoopMeasurement> best;
	for (const auto& c : map.candidates(f.descriptors, std::size_t(options.loop_candidates), newestId))
	{
		// Where the odometry thinks the camera is, the candidate's points
		// should project close to its features; when it has drifted too far
		// for that, descriptor matching from the candidate's pose.
		const MapKeyframe& kf = *map.find(c.keyframe);
		std::vector<Match> matches;
		const auto verified = frontend.locate(f, pointsOf(kf), T_cw, kf.T_cw, matches);
		if (!verified) continue;
		LoopMeasurement m;
		m.candidate = c.keyframe;
		m.place = covisibleWith(c.keyframe, newestId, map, f.K, f.imageSize, options.loop_neighbours);
		const LandmarkMap place = placeOf(m.place, map);
		matches = frontend.matchByProjection(f, place, verified->T_cw);
		const auto pnp = frontend.solvePnp(f, place, matches, verified->T_cw);
		if (!pnp) continue;
		auto refined = backend.refinePnp(f, *pnp, matches, place);
		if (!refined || int(refined->inliers.size()) < options.loop_min_inliers ||
			(best && refined->inliers.size() <= best->inliers))
			continue;
		m.T_cw = refined->T_cw;
		m.inliers = refined->inliers.size();
		m.centreCovariance = refined->centreCovariance;
		m.inlierMatches = std::move(refined->inliers);
		best = measuredFrom(std::move(m), T_cw);
	}
	return best;
}

LoopMeasurement measuredFrom(LoopMeasurement loop, const Eigen::Isometry3d& T_cw)
{
	loop.rotation = mrpt::RAD2DEG(Eigen::AngleAxisd(loop.T_cw.rotation() * T_cw.rotation().transpose()).angle());
	return loop;
}

double inlierSigma(const LoopMeasurement& loop)
{
	if (!loop.centreCovariance.allFinite()) return std::numeric_limits<double>::infinity();
	const double worst = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(loop.centreCovariance, Eigen::EigenvaluesOnly)
							 .eigenvalues()
							 .maxCoeff();
	return std::sqrt(std::max(worst, 0.0));
}

double loopSigma(const LoopMeasurement& loop, const TOdometryOptions& options)
{
	// 0: every loop is as good as any other, whatever its inliers.
	if (options.loop_covariance_scale == 0) return options.loop_sigma;
	const double fromInliers = options.loop_covariance_scale * inlierSigma(loop);
	return std::sqrt(options.loop_sigma * options.loop_sigma + fromInliers * fromInliers);
}

LoopJudgement judgeLoop(const LoopMeasurement& loop, int newestId, const std::vector<PoseGraphEdge>& loops,
	const KeyframeMap& map, const TOdometryOptions& options)
{
	// Chi-square with 3 degrees of freedom at 99 %: a camera centre's error
	// over its per-axis standard deviation stays below this 99 times in 100.
	static const double kChiSquare = chiSquare3Quantile(0.99);
	const double sigma = loopSigma(loop, options);
	const double loopVariance = sigma * sigma;
	const Eigen::Vector3d shift = cameraCentre(loop.T_cw) - cameraCentre(map.find(newestId)->T_cw);
	const int keyframesApart = newestId - loop.candidate;
	const double trackVariance = keyframesApart * options.odometry_sigma * options.odometry_sigma;
	char why[200];
	std::snprintf(why, sizeof(why), "%.3f m from the track, sigma %.3f m (inliers %.4f m)", shift.norm(), sigma,
		inlierSigma(loop));
	if (!std::isfinite(sigma)) return {LoopVerdict::Refused, std::string(why) + ": its inliers do not fix the pose"};
	if (shift.squaredNorm() > kChiSquare * (loopVariance + trackVariance))
	{
		std::snprintf(why + std::strlen(why), sizeof(why) - std::strlen(why),
			", beyond what a loop and %d keyframes of odometry allow (%.3f m)", keyframesApart,
			std::sqrt(kChiSquare * (loopVariance + trackVariance)));
		return {LoopVerdict::Refused, why};
	}
	const PoseGraphEdge* before = loops.empty() || loops.back().to != newestId - 1 ? nullptr : &loops.back();
	const MapKeyframe* from = before ? map.find(before->from) : nullptr;
	const MapKeyframe* to = before ? map.find(before->to) : nullptr;
	if (!from || !to) return {LoopVerdict::Unconfirmed, why};
	const Eigen::Vector3d shiftBefore = cameraCentre(before->T_to_from * from->T_cw) - cameraCentre(to->T_cw);
	const double bothVariance = loopVariance + before->sigmaTranslation * before->sigmaTranslation;
	if ((shift - shiftBefore).squaredNorm() > kChiSquare * bothVariance)
	{
		std::snprintf(why + std::strlen(why), sizeof(why) - std::strlen(why),
			", %.3f m from the keyframe before's loop", (shift - shiftBefore).norm());
		return {LoopVerdict::Unconfirmed, why};
	}
	const Eigen::Vector3d drift = (shift + shiftBefore) / 2;
	std::snprintf(why + std::strlen(why), sizeof(why) - std::strlen(why), ", %.3f m with the keyframe before's loop",
		drift.norm());
	return {
		drift.squaredNorm() > kChiSquare * bothVariance / 4 ? LoopVerdict::Close : LoopVerdict::WithinOwnError, why};
}

PoseGraphEdge loopEdge(
	const LoopMeasurement& loop, int keyframe, const KeyframeMap& map, const TOdometryOptions& options)
{
	PoseGraphEdge e;
	e.from = loop.candidate;
	e.to = keyframe;
	e.T_to_from = loop.T_cw * map.find(loop.candidate)->T_cw.inverse();
	e.sigmaTranslation = loopSigma(loop, options);
	e.sigmaRotation = e.sigmaTranslation;  // [rad], as a metre at 1 m
	e.robust = true;
	return e;
}

std::optional<std::map<int, Eigen::Isometry3d>> closeLoops(
	const KeyframeMap& map, const std::vector<PoseGraphEdge>& loops, const TOdometryOptions& options)
{
	const auto& keyframes = map.keyframes();
	if (keyframes.size() < 2) return std::nullopt;
	std::map<int, Eigen::Isometry3d> nodes;
	std::vector<PoseGraphEdge> edges;
	for (auto it = keyframes.begin(); it != keyframes.end(); ++it)
	{
		nodes[it->first] = it->second.T_cw;
		const auto next = std::next(it);
		if (next == keyframes.end()) break;
		// The odometry between consecutive keyframes, as it stands.
		PoseGraphEdge e;
		e.from = it->first;
		e.to = next->first;
		e.T_to_from = next->second.T_cw * it->second.T_cw.inverse();
		e.sigmaTranslation = options.odometry_sigma;
		e.sigmaRotation = options.odometry_sigma;
		edges.push_back(e);
	}
	edges.insert(edges.end(), loops.begin(), loops.end());
	// A few hundred keyframes converge in a few iterations from the odometry's poses.
	constexpr int kIterations = 20;
	auto result = optimisePoseGraph(nodes, edges, keyframes.begin()->first, kIterations);
	if (!result.usable) return std::nullopt;
	return std::move(result.poses);
}
}  // namespace avm::odometry::detail
