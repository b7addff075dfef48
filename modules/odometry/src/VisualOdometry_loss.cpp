// Frames whose own pose is not to be had or not to be trusted: bridged by
// the motion model, placed once the track is back, relocalised against the
// keyframe map, or the start of a new local map.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "VisualOdometryImpl.h"
#include "avm/io/Trajectory.h"

namespace avm::odometry
{
OdometryEstimate VisualOdometry::Impl::lost(const FrameFeatures& f, const std::string& why)
{
	OdometryEstimate e;
	const bool trackable = int(f.keypoints.size()) >= options.min_inliers;
	if (trackable)
	{
		mrpt::system::CTimeLoggerEntry relocalisationTimer(stageTimer, "5 relocalisation");
		auto r = relocalise(f, nullptr);
		relocalisationTimer.stop();
		if (r)
		{
			// Back in the old map's frame: a new local map starts at the
			// relocalised pose. The motion across the gap is unknown.
			const std::string after = std::to_string(lostFrames + 1);
			restartLocalMap(f, r->T_cw);
			T_cw = keyframeMap.find(window.back().id)->T_cw;
			velocity = Eigen::Isometry3d::Identity();
			velocityMeasured = false;
			e.tracked = e.keyframe = true;
			e.inliers = r->inliers.size();
			e.reprojectionRmse = r->rmse;
			e.status = "relocalised on keyframe " + std::to_string(r->keyframe) + " after " + after + " lost frames";
			e.pose = toPose(T_cw.inverse());
			return e;
		}
		++lostFramesWithFeatures;
	}
	e = bridge("lost: " + why + "; pose bridged by the motion model");
	// The old map is kept while the frames may still relocalise against it;
	// after relocalisation_frames frames that could have but did not, a new
	// local map starts here so that tracking goes on (in a frame that has
	// drifted by the bridge; the keyframe map keeps the old keyframes).
	if (trackable && lostFramesWithFeatures > options.relocalisation_frames)
	{
		restartLocalMap(f, T_cw);
		e.keyframe = true;
		e.status += "; re-initialised";
	}
	return e;
}

OdometryEstimate VisualOdometry::Impl::bridge(const std::string& why)
{
	OdometryEstimate e;
	++lostFrames;
	T_cw = velocity * T_cw;
	e.status = why;
	e.pose = toPose(T_cw.inverse());
	return e;
}

std::optional<std::string> VisualOdometry::Impl::implausibleMotion(double deviation) const
{
	// Judged against a measured velocity and enough history only, and for at
	// most relocalisation_frames frames in a row: a camera that really
	// changed its motion is followed again after that.
	if (options.motion_gate <= 0 || !velocityMeasured || recentDeviations.size() < kDeviationHistory ||
		lostFrames >= options.relocalisation_frames)
		return std::nullopt;
	std::vector<double> sorted(recentDeviations.begin(), recentDeviations.end());
	std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
	const double median = sorted[sorted.size() / 2];
	if (deviation <= options.motion_gate * median) return std::nullopt;
	char why[160];
	std::snprintf(why, sizeof(why),
		"untrusted: the tracked pose is %.3f m from the motion model's, %.0f times the recent median; pose bridged",
		deviation, deviation / median);
	return std::string(why);
}

void VisualOdometry::Impl::placeBridgedFrames(std::size_t count)
{
	if (frames.size() < count + 2) return;
	const FramePose& from = frames[frames.size() - count - 2];
	const FramePose& to = frames.back();
	const io::Trajectory ends{{from.timestamp, toPose(from.T_cw.inverse())}, {to.timestamp, toPose(to.T_cw.inverse())}};
	for (std::size_t k = frames.size() - count - 1; k + 1 < frames.size(); ++k)
		if (const auto pose = io::interpolatePose(ends, frames[k].timestamp, std::numeric_limits<double>::infinity()))
			frames[k].T_cw = toIsometry(*pose).inverse();
}

void VisualOdometry::Impl::restartLocalMap(const FrameFeatures& f, const Eigen::Isometry3d& T)
{
	velocityMeasured = false;
	window.clear();
	landmarks.clear();
	addKeyframe(f, {}, T);
	lostFrames = lostFramesWithFeatures = 0;
}

std::optional<VisualOdometry::Impl::Relocalisation> VisualOdometry::Impl::relocalise(
	const FrameFeatures& f, std::vector<KeyframeMap::Candidate>* tried) const
{
	std::optional<Relocalisation> best;
	const auto candidates = keyframeMap.candidates(f.descriptors, std::size_t(options.relocalisation_candidates));
	if (tried) *tried = candidates;
	for (const auto& c : candidates)
	{
		const MapKeyframe& kf = *keyframeMap.find(c.keyframe);
		const LandmarkMap points = pointsOf(kf);
		const auto matches = frontend.matchByDescriptor(f, points);
		if (int(matches.size()) < options.relocalisation_min_inliers) continue;
		const auto pnp = frontend.solvePnp(f, points, matches, kf.T_cw);
		if (!pnp) continue;
		auto refined = backend.refinePnp(f, *pnp, matches, points);
		if (!refined || int(refined->inliers.size()) < options.relocalisation_min_inliers ||
			(best && refined->inliers.size() <= best->inliers.size()))
			continue;
		const double rmse = std::sqrt(refined->squaredErrors / double(refined->inliers.size()));
		best = Relocalisation{c.keyframe, refined->T_cw, std::move(refined->inliers), rmse};
	}
	return best;
}

VisualOdometry::PlaceQuery VisualOdometry::Impl::queryPlace(
	const mrpt::obs::CObservation3DRangeScan& obs, const std::vector<cv::Rect>& boxes) const
{
	const auto [grey, depth, K] = imagesOf(obs);
	const auto f = frontend.extract(grey, depth, K, options.mask_people ? boxes : std::vector<cv::Rect>{});
	PlaceQuery q;
	std::vector<KeyframeMap::Candidate> candidates;
	const auto r = f.keypoints.empty() ? std::nullopt : relocalise(f, &candidates);
	for (const auto& c : candidates) q.candidates.emplace_back(std::size_t(c.keyframe), c.score);
	if (r)
	{
		q.accepted = true;
		q.keyframe = std::size_t(r->keyframe);
		q.inliers = r->inliers.size();
		q.pose = toPose(r->T_cw.inverse());
	}
	return q;
}
}  // namespace avm::odometry
