#include "avm/odometry/VisualOdometry.h"

#include <mrpt/core/Clock.h>
#include <mrpt/core/bits_math.h>

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "TrackQuality.h"
#include "VisualOdometryImpl.h"
#include "avm/io/RgbdFrame.h"
#include "avm/io/Trajectory.h"

namespace avm::odometry
{
namespace
{
/** Checked before the front end builds its detector from them. */
const TOdometryOptions& validated(const TOdometryOptions& o)
{
	o.validate("odometry");
	return o;
}

double rotationAngleDeg(const Eigen::Matrix3d& R) { return mrpt::RAD2DEG(Eigen::AngleAxisd(R).angle()); }
}  // namespace

FrameImages detail::imagesOf(const mrpt::obs::CObservation3DRangeScan& obs)
{
	if (!obs.hasRangeImage) throw std::invalid_argument("VisualOdometry: observation without a range image");
	FrameImages out;
	cv::cvtColor(io::colourImage(obs), out.grey, cv::COLOR_BGR2GRAY);
	out.depth = io::depthInMetres(obs);
	if (out.depth.size() != out.grey.size())
		throw std::invalid_argument("VisualOdometry: depth and colour images differ in size (not registered)");
	out.K = io::DepthCamera::of(obs);
	return out;
}

VisualOdometry::Impl::Impl(const TOdometryOptions& o, const mrpt::poses::CPose3D& initial)
	: options(validated(o)), frontend(options), backend(options), T_cw(toIsometry(initial).inverse())
{
	if (!io::isFinite(initial)) throw std::invalid_argument("VisualOdometry: the initial pose is not finite");
}

OdometryEstimate VisualOdometry::Impl::process(
	const mrpt::obs::CObservation3DRangeScan& obs, const std::vector<cv::Rect>& boxes)
{
	const auto [grey, depth, K] = imagesOf(obs);
	std::vector<cv::KeyPoint> masked;
	const auto f = [&]
	{
		mrpt::system::CTimeLoggerEntry t(stageTimer, "1 features");
		return frontend.extract(grey, depth, K, options.mask_people ? boxes : std::vector<cv::Rect>{},
			reportFeatures ? &masked : nullptr, &stageTimer);
	}();
	const std::size_t bridged = std::size_t(lostFrames);
	auto e = session.placing ? place(f) : track(f);
	// A frame not placed in a continued session's map has no pose to keep.
	if (e.placed)
		frames.push_back({window.empty() ? -1 : window.back().id, T_cw, mrpt::Clock::toDouble(obs.timestamp)});
	if (e.tracked && bridged > 0)
	{
		placeBridgedFrames(bridged);
		e.bridgedFramesPlaced = bridged;
	}
	if (reportFeatures)
	{
		cv::KeyPoint::convert(f.keypoints, e.features);
		cv::KeyPoint::convert(masked, e.maskedFeatures);
	}
	return e;
}

OdometryEstimate VisualOdometry::Impl::initialise(const FrameFeatures& f)
{
	OdometryEstimate e;
	e.pose = toPose(T_cw.inverse());
	if (int(f.keypoints.size()) < options.min_inliers)
	{
		e.status = "lost: not initialised, " + std::to_string(f.keypoints.size()) + " features with depth";
		return e;
	}
	addKeyframe(f, {}, T_cw);
	e.tracked = e.keyframe = true;
	e.status = "initialised";
	return e;
}

OdometryEstimate VisualOdometry::Impl::track(const FrameFeatures& f)
{
	if (window.empty()) return initialise(f);
	if (int(f.keypoints.size()) < options.min_inliers)
		return lost(f, std::to_string(f.keypoints.size()) + " features with depth (no depth or no texture)");

	const Eigen::Isometry3d predicted = velocity * T_cw;
	mrpt::system::CTimeLoggerEntry matchTimer(stageTimer, "2 matching + PnP");
	auto matches = frontend.matchByProjection(f, landmarks, predicted);
	auto pnp = frontend.solvePnp(f, landmarks, matches, predicted);
	if (!pnp)
	{
		matches = frontend.matchByDescriptor(f, landmarks);
		pnp = frontend.solvePnp(f, landmarks, matches, T_cw);
	}
	matchTimer.stop();
	if (!pnp) return lost(f, std::to_string(matches.size()) + " matches, PnP found no consistent pose");

	mrpt::system::CTimeLoggerEntry refineTimer(stageTimer, "3 pose refinement");
	std::optional<CeresBackend::CentrePrior> prior;
	if (options.motion_prior_sigma > 0 && velocityMeasured && lostFrames == 0)
		prior = CeresBackend::CentrePrior{predicted.inverse().translation(), options.motion_prior_sigma};
	const auto refined = backend.refinePnp(f, *pnp, matches, landmarks, prior);
	refineTimer.stop();
	if (!refined) return lost(f, "the pose refinement diverged");
	Eigen::Isometry3d T = refined->T_cw;
	const auto& inliers = refined->inliers;
	const double sq = refined->squaredErrors;
	if (int(inliers.size()) < options.min_inliers)
		return lost(f, std::to_string(inliers.size()) + " inliers after refinement");
	const Eigen::Vector3d offPrediction = T.inverse().translation() - predicted.inverse().translation();
	const double deviation = offPrediction.norm();
	// The prediction's error grows with every frame it is carried over a
	// bridge: its variance with the square of the frames since a measured one.
	const bool judged = velocityMeasured && recentDeviations.size() >= kDeviationHistory;
	const double carried = double(1 + lostFrames);
	const TrackQuality quality = qualityOf(f, inliers, refined->centreCovariance, offPrediction,
		judged ? predictionVariance(recentDeviations) * carried * carried : 0.0);
	if (const auto why = implausibleMotion(deviation))
	{
		auto bridged = bridge(*why);
		bridged.quality = quality;
		bridged.inliers = inliers.size();
		return bridged;
	}

	OdometryEstimate e;
	e.quality = quality;
	e.tracked = true;
	e.inliers = inliers.size();
	e.reprojectionRmse = std::sqrt(sq / inliers.size());
	e.status = "tracking";
	// Found the kept local map again after a loss: the bridged pose says
	// nothing of the motion across the gap.
	const bool recovered = lostFrames > 0;
	if (recovered) e.status = "tracking again after " + std::to_string(lostFrames) + " lost frames";
	lostFrames = lostFramesWithFeatures = 0;

	const Eigen::Isometry3d previous = T_cw;
	if (needsKeyframe(T, inliers.size()))
	{
		addKeyframe(f, inliers, T);
		if (!options.keyframe_tracked_pose) T = keyframeMap.find(window.back().id)->T_cw;
		e.keyframe = true;
	}
	if (velocityMeasured && !recovered)
	{
		recentDeviations.push_back(deviation);
		if (recentDeviations.size() > kDeviationHistory) recentDeviations.pop_front();
	}
	velocity = recovered ? Eigen::Isometry3d::Identity() : Eigen::Isometry3d(T * previous.inverse());
	velocityMeasured = !recovered;
	T_cw = T;
	// The velocity is a motion in the camera frame: a loop's correction of the
	// world leaves it as it is.
	if (e.keyframe && options.loop_closure) closeLoop(f, e);
	e.pose = toPose(T_cw.inverse());
	return e;
}

bool VisualOdometry::Impl::needsKeyframe(const Eigen::Isometry3d& T, std::size_t inliers)
{
	// When the camera moved or turned enough, or sees too little of the last
	// keyframe's landmarks. Overlap: inliers relative to the most the last
	// keyframe's map gave any frame.
	auto& last = window.back();
	const Eigen::Isometry3d rel = T * keyframeMap.find(last.id)->T_cw.inverse();
	last.bestInliers = std::max(last.bestInliers, inliers);
	const double overlap = double(inliers) / double(last.bestInliers);
	return rel.translation().norm() > options.keyframe_translation ||
		   rotationAngleDeg(rel.rotation()) > options.keyframe_rotation || overlap < options.keyframe_overlap;
}

void VisualOdometry::Impl::addKeyframe(
	const FrameFeatures& f, const std::vector<Match>& inliers, const Eigen::Isometry3d& T)
{
	Keyframe kf;
	kf.id = nextKeyframeId++;
	// The window's keyframes stay in the map whatever its cap: their poses are kept there.
	const std::size_t windowSize = std::size_t(std::max(1, options.window_size));
	const std::size_t leaving = window.size() + 1 > windowSize ? window.size() + 1 - windowSize : 0;
	const int keepFrom = leaving < window.size() ? window[leaving].id : kf.id;
	keyframeMap.add(kf.id, MapKeyframe{T, f.descriptors.clone(), f.points, {}}, keepFrom);
	std::vector<bool> matched(f.keypoints.size(), false);
	for (const auto& m : inliers)
	{
		matched[m.feature] = true;
		landmarks.at(m.landmark).descriptor = f.descriptor(m.feature);
		kf.observations.push_back(observationOf(f, m.feature, m.landmark));
	}
	const Eigen::Isometry3d T_wc = T.inverse();
	for (std::size_t i = 0; i < f.keypoints.size(); ++i)
	{
		if (matched[i]) continue;
		const int id = nextLandmarkId++;
		landmarks[id] = Landmark{T_wc * f.points[i], f.descriptor(int(i))};
		kf.observations.push_back(observationOf(f, int(i), id));
	}
	window.push_back(std::move(kf));
	while (window.size() > windowSize) window.pop_front();
	forgetUnobservedLandmarks();
	if (options.window_size >= 2)
	{
		mrpt::system::CTimeLoggerEntry t(stageTimer, "4 window bundle adjustment");
		std::vector<Eigen::Isometry3d> poses;
		for (const auto& k : window) poses.push_back(keyframeMap.find(k.id)->T_cw);
		backend.bundleAdjust(window, poses, landmarks, f.K);
		for (std::size_t k = 0; k < window.size(); ++k) keyframeMap.updatePose(window[k].id, poses[k]);
	}
}

void VisualOdometry::Impl::forgetUnobservedLandmarks()
{
	std::unordered_map<int, bool> seen;
	for (const auto& kf : window)
		for (const auto& o : kf.observations) seen[o.landmark] = true;
	for (auto it = landmarks.begin(); it != landmarks.end();)
		it = seen.count(it->first) ? std::next(it) : landmarks.erase(it);
}

VisualOdometry::VisualOdometry(const TOdometryOptions& options, const mrpt::poses::CPose3D& initialPose)
	: m_impl(std::make_unique<Impl>(options, initialPose))
{
}
VisualOdometry::~VisualOdometry() = default;
VisualOdometry::VisualOdometry(VisualOdometry&&) noexcept = default;
VisualOdometry& VisualOdometry::operator=(VisualOdometry&&) noexcept = default;

OdometryEstimate VisualOdometry::process(
	const mrpt::obs::CObservation3DRangeScan& obs, const std::vector<cv::Rect>& personBoxes)
{
	return m_impl->process(obs, personBoxes);
}
void VisualOdometry::reportFeatures(bool on) { m_impl->reportFeatures = on; }
void VisualOdometry::saveState(mrpt::serialization::CArchive& out) const { m_impl->saveState(out); }
void VisualOdometry::loadState(mrpt::serialization::CArchive& in) { m_impl->loadState(in); }
VisualOdometry::LoopOutcome VisualOdometry::offerLoop(std::size_t oldFrame, const mrpt::poses::CPose3D& measured)
{
	return m_impl->offerLoop(oldFrame, measured);
}
const TOdometryOptions& VisualOdometry::options() const { return m_impl->options; }
std::size_t VisualOdometry::keyframeCount() const { return m_impl->window.size(); }
std::size_t VisualOdometry::mapKeyframeCount() const { return m_impl->keyframeMap.size(); }
VisualOdometry::PlaceQuery VisualOdometry::queryPlace(
	const mrpt::obs::CObservation3DRangeScan& obs, const std::vector<cv::Rect>& personBoxes) const
{
	return m_impl->queryPlace(obs, personBoxes);
}
std::size_t VisualOdometry::landmarkCount() const { return m_impl->landmarks.size(); }
std::vector<mrpt::poses::CPose3D> VisualOdometry::trajectory() const
{
	std::vector<mrpt::poses::CPose3D> poses;
	poses.reserve(m_impl->frames.size());
	for (const auto& frame : m_impl->frames) poses.push_back(toPose(frame.T_cw.inverse()));
	return poses;
}
std::string VisualOdometry::stageTimesText() const { return m_impl->stageTimer.getStatsAsText(); }
}  // namespace avm::odometry
