#include "avm/odometry/VisualOdometry.h"

#include <mrpt/core/Clock.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/CTimeLogger.h>

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <limits>
#include <optional>
#include <stdexcept>

#include "avm/io/RgbdFrame.h"
#include "avm/io/Trajectory.h"
#include "StateStream.h"
#include "backend/CeresBackend.h"
#include "frontend/FeatureFrontend.h"
#include "map/KeyframeMap.h"
#include "map/LoopClosing.h"

namespace avm::odometry
{
using namespace detail;

namespace
{
Eigen::Isometry3d toIsometry(const mrpt::poses::CPose3D& p)
{
	Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
	const auto& R = p.getRotationMatrix();
	for (int r = 0; r < 3; ++r)
	{
		for (int c = 0; c < 3; ++c) T.linear()(r, c) = R(r, c);
		T.translation()[r] = p.translation()[r];
	}
	return T;
}

mrpt::poses::CPose3D toPose(const Eigen::Isometry3d& T)
{
	mrpt::math::CMatrixDouble33 R;
	for (int r = 0; r < 3; ++r)
		for (int c = 0; c < 3; ++c) R(r, c) = T.linear()(r, c);
	const Eigen::Vector3d t = T.translation();
	return mrpt::poses::CPose3D(R, mrpt::math::CVectorFixedDouble<3>({t.x(), t.y(), t.z()}));
}

/** Checked before the front end builds its detector from them. */
const TOdometryOptions& validated(const TOdometryOptions& o)
{
	o.validate("odometry");
	return o;
}

double rotationAngleDeg(const Eigen::Matrix3d& R) { return mrpt::RAD2DEG(Eigen::AngleAxisd(R).angle()); }

struct FrameImages
{
	cv::Mat grey, depth;  //!< depth in metres, registered to the colour image
	io::DepthCamera K;
};

FrameImages imagesOf(const mrpt::obs::CObservation3DRangeScan& obs)
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

/** Layout version of the saveState stream; change it with the layout. */
constexpr std::uint8_t stateVersion = 5;
}  // namespace

struct VisualOdometry::Impl
{
	explicit Impl(const TOdometryOptions& o, const mrpt::poses::CPose3D& initial)
		: options(validated(o)), frontend(options), backend(options), T_cw(toIsometry(initial).inverse())
	{
		if (!io::isFinite(initial)) throw std::invalid_argument("VisualOdometry: the initial pose is not finite");
	}
	// CTimeLogger prints its table when destroyed with data; the owner asks for it instead.
	~Impl() { stageTimer.clear(true); }
	Impl(const Impl&) = delete;
	Impl& operator=(const Impl&) = delete;

	TOdometryOptions options;
	FeatureFrontend frontend;
	CeresBackend backend;
	Eigen::Isometry3d T_cw;  //!< latest pose (world -> camera)
	/** Camera motion of the last frame, T_cw(k) * T_cw(k-1)^-1, for the prediction. */
	Eigen::Isometry3d velocity = Eigen::Isometry3d::Identity();
	LandmarkMap landmarks;
	std::deque<Keyframe> window;
	int nextLandmarkId = 0;
	KeyframeMap keyframeMap{options};
	int nextKeyframeId = 0;
	/** Consecutive lost frames, and those of them with enough features to
	 *  track (only these count towards giving up the old map). */
	int lostFrames = 0, lostFramesWithFeatures = 0;
	/** Verified loop constraints between map keyframes, kept for every later
	 *  pose graph; those naming an evicted keyframe go. */
	std::vector<PoseGraphEdge> loops;
	/** Every frame process() saw: its pose, and the keyframe it was tracked
	 *  against, with which a closed loop moves it. */
	struct FramePose
	{
		int keyframe = -1;
		Eigen::Isometry3d T_cw;
		double timestamp = 0;  //!< [s] the observation's
	};
	std::vector<FramePose> frames;
	mrpt::system::CTimeLogger stageTimer{true, "avm odometry stages"};
	bool reportFeatures = false;

	OdometryEstimate process(const mrpt::obs::CObservation3DRangeScan& obs, const std::vector<cv::Rect>& boxes);
	/** The frame's pose from its features: tracked, initialised, relocalised or bridged. */
	OdometryEstimate track(const FrameFeatures& f);
	VisualOdometry::PlaceQuery queryPlace(
		const mrpt::obs::CObservation3DRangeScan& obs, const std::vector<cv::Rect>& boxes) const;
	/** A keyframe at T from the frame's matched inliers and new landmarks for
	 *  the unmatched features; runs the window bundle adjustment. */
	void addKeyframe(const FrameFeatures& f, const std::vector<Match>& inliers, const Eigen::Isometry3d& T);
	void forgetUnobservedLandmarks();
	/** Looks for a loop at the newest keyframe (features f); when a verified
	 *  loop shows drift, optimises the pose graph and moves everything with
	 *  it. What it found goes to e's status; e.loopClosed when the poses moved. */
	void closeLoop(const FrameFeatures& f, OdometryEstimate& e);
	/** Moves the map keyframes to `poses` (T_cw by id), the local map rigidly
	 *  with the current frame to `newestPose`, and every frame with its
	 *  keyframe. */
	void moveTo(const std::map<int, Eigen::Isometry3d>& poses, const Eigen::Isometry3d& newestPose);
	/** The newest keyframe's features that a loop matched observe the place's points from now on. */
	void joinPlace(const LoopMeasurement& loop);
	/** The `count` frames before the newest, bridged while the track was
	 *  lost, placed between the last tracked frame and the newest one,
	 *  which found the track again, by timestamp (io::interpolatePose): the
	 *  camera went from the one to the other, the motion model only guessed
	 *  where. A frame whose stamp is not between the two keeps its guess. */
	void placeBridgedFrames(std::size_t count);
	/** Drops the local map and starts a new one with this frame as its keyframe at T; the loss is over. */
	void restartLocalMap(const FrameFeatures& f, const Eigen::Isometry3d& T);
	OdometryEstimate lost(const FrameFeatures& f, const std::string& why);

	struct Relocalisation
	{
		int keyframe = -1;
		Eigen::Isometry3d T_cw;
		std::vector<Match> inliers;
		double rmse = 0;
	};
	/** The frame's pose against the keyframe map: each candidate of the
	 *  place index in turn, descriptor matches to its features, PnP RANSAC,
	 *  Ceres refinement; the candidate with the most inliers, if it has
	 *  relocalisation_min_inliers. */
	std::optional<Relocalisation> relocalise(const FrameFeatures& f, std::vector<KeyframeMap::Candidate>* tried) const;
	void saveState(mrpt::serialization::CArchive& out) const;
	void loadState(mrpt::serialization::CArchive& in);
};

OdometryEstimate VisualOdometry::Impl::lost(const FrameFeatures& f, const std::string& why)
{
	OdometryEstimate e;
	++lostFrames;
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
			const std::string after = std::to_string(lostFrames);
			restartLocalMap(f, r->T_cw);
			T_cw = window.back().T_cw;
			velocity = Eigen::Isometry3d::Identity();
			e.tracked = e.keyframe = true;
			e.inliers = r->inliers.size();
			e.reprojectionRmse = r->rmse;
			e.status = "relocalised on keyframe " + std::to_string(r->keyframe) + " after " + after + " lost frames";
			e.pose = toPose(T_cw.inverse());
			return e;
		}
		++lostFramesWithFeatures;
	}
	T_cw = velocity * T_cw;  // bridged by the constant-velocity model
	e.status = "lost: " + why + "; pose bridged by the motion model";
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
	e.pose = toPose(T_cw.inverse());
	return e;
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

OdometryEstimate VisualOdometry::Impl::process(
	const mrpt::obs::CObservation3DRangeScan& obs, const std::vector<cv::Rect>& boxes)
{
	const auto [grey, depth, K] = imagesOf(obs);
	std::vector<cv::KeyPoint> masked;
	const auto f = [&]
	{
		mrpt::system::CTimeLoggerEntry t(stageTimer, "1 features");
		return frontend.extract(
			grey, depth, K, options.mask_people ? boxes : std::vector<cv::Rect>{}, reportFeatures ? &masked : nullptr);
	}();
	const std::size_t bridged = std::size_t(lostFrames);
	auto e = track(f);
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

OdometryEstimate VisualOdometry::Impl::track(const FrameFeatures& f)
{
	if (window.empty())
	{
		if (int(f.keypoints.size()) < options.min_inliers)
		{
			OdometryEstimate e;
			e.pose = toPose(T_cw.inverse());
			e.status = "lost: not initialised, " + std::to_string(f.keypoints.size()) + " features with depth";
			return e;
		}
		addKeyframe(f, {}, T_cw);
		OdometryEstimate e;
		e.pose = toPose(T_cw.inverse());
		e.tracked = e.keyframe = true;
		e.status = "initialised";
		return e;
	}
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
	if (options.motion_prior_sigma > 0 && lostFrames == 0)
		prior = CeresBackend::CentrePrior{predicted.inverse().translation(), options.motion_prior_sigma};
	const auto refined = backend.refinePnp(f, *pnp, matches, landmarks, prior);
	refineTimer.stop();
	if (!refined) return lost(f, "the pose refinement diverged");
	Eigen::Isometry3d T = refined->T_cw;
	const auto& inliers = refined->inliers;
	const double sq = refined->squaredErrors;
	if (int(inliers.size()) < options.min_inliers)
		return lost(f, std::to_string(inliers.size()) + " inliers after refinement");

	OdometryEstimate e;
	e.tracked = true;
	e.inliers = inliers.size();
	e.reprojectionRmse = std::sqrt(sq / inliers.size());
	e.status = "tracking";
	// Found the kept local map again after a loss: the bridged pose says
	// nothing of the motion across the gap.
	const bool recovered = lostFrames > 0;
	if (recovered) e.status = "tracking again after " + std::to_string(lostFrames) + " lost frames";
	lostFrames = lostFramesWithFeatures = 0;

	// Keyframe when the camera moved or turned enough, or sees too little of
	// the last keyframe's landmarks.
	// Overlap: inliers relative to the most the last keyframe's map gave any frame.
	auto& last = window.back();
	const Eigen::Isometry3d rel = T * last.T_cw.inverse();
	last.bestInliers = std::max(last.bestInliers, inliers.size());
	const double overlap = double(inliers.size()) / double(last.bestInliers);
	const Eigen::Isometry3d previous = T_cw;
	if (rel.translation().norm() > options.keyframe_translation ||
		rotationAngleDeg(rel.rotation()) > options.keyframe_rotation || overlap < options.keyframe_overlap)
	{
		addKeyframe(f, inliers, T);
		if (!options.keyframe_tracked_pose) T = window.back().T_cw;
		e.keyframe = true;
	}
	velocity = recovered ? Eigen::Isometry3d::Identity() : Eigen::Isometry3d(T * previous.inverse());
	T_cw = T;
	// The velocity is a motion in the camera frame: a loop's correction of the
	// world leaves it as it is.
	if (e.keyframe && options.loop_closure) closeLoop(f, e);
	e.pose = toPose(T_cw.inverse());
	return e;
}

void VisualOdometry::Impl::closeLoop(const FrameFeatures& f, OdometryEstimate& e)
{
	mrpt::system::CTimeLoggerEntry timer(stageTimer, "6 loop closing");
	const Keyframe& newest = window.back();
	const auto loop =
		measureLoop(f, T_cw, newest.id - options.loop_min_separation, keyframeMap, frontend, backend, options);
	if (!loop) return;
	const Eigen::Isometry3d T_candidate = keyframeMap.find(loop->candidate)->T_cw;
	// The frame that made a keyframe is the first tracked against it.
	const auto made =
		std::find_if(frames.begin(), frames.end(), [&](const FramePose& p) { return p.keyframe == loop->candidate; });
	e.loop = LoopReport{std::size_t(made - frames.begin()), loop->inliers, toPose(T_candidate * loop->T_cw.inverse()),
		toPose(T_candidate * T_cw.inverse())};
	char said[160];
	std::snprintf(said, sizeof(said), "; loop with keyframe %d (%zu inliers, %.3f m, %.2f deg): ", loop->candidate,
		loop->inliers, loop->translation, loop->rotation);
	e.status += said;
	if (loop->translation > options.loop_max_correction)
	{
		e.status += "refused, beyond loop_max_correction";
		return;
	}
	loops.erase(std::remove_if(loops.begin(), loops.end(),
					[&](const PoseGraphEdge& l) { return !keyframeMap.find(l.from) || !keyframeMap.find(l.to); }),
		loops.end());
	// A loop moves the poses only when it shows more drift than its own error
	// and the loop of the keyframe before found the same.
	const bool drifted =
		loop->translation >= options.loop_min_correction || loop->rotation >= options.loop_min_rotation;
	const bool confirmed = drifted && confirmsLoopBefore(*loop, newest, loops, keyframeMap, options);
	loops.push_back(loopEdge(*loop, newest.id, keyframeMap, options));
	if (!confirmed)
	{
		e.status += drifted ? "kept, not confirmed by the keyframe before" : "kept, within its own error";
		return;
	}
	const auto poses = closeLoops(keyframeMap, loops, options);
	if (!poses)
	{
		e.status += "kept, the pose graph found no solution";
		return;
	}
	// The graph moved the place too; the loop measured the new keyframe
	// against the place as it was.
	const Eigen::Isometry3d T_loop = loop->T_cw * (T_candidate.inverse() * poses->at(loop->candidate));
	moveTo(*poses, T_loop);
	joinPlace(*loop);
	e.status += "closed, poses corrected";
	e.loopClosed = true;
}

void VisualOdometry::Impl::joinPlace(const LoopMeasurement& loop)
{
	// The new keyframe's features that matched the place now observe the
	// place's points: tracking goes on against the old map there, not against
	// the drifted copy the local map made of it.
	Keyframe& newest = window.back();
	const LandmarkMap place =
		placeAround(loop.candidate, newest.id - options.loop_min_separation, keyframeMap, options.loop_neighbours);
	for (const auto& m : loop.inlierMatches)
	{
		const auto o = std::find_if(newest.observations.begin(), newest.observations.end(),
			[&](const Observation& o) { return o.feature == m.feature; });
		if (o == newest.observations.end()) continue;
		const int id = nextLandmarkId++;
		landmarks[id] = place.at(m.landmark);
		landmarks[id].anchored = true;
		o->landmark = id;
	}
	forgetUnobservedLandmarks();
}

void VisualOdometry::Impl::moveTo(const std::map<int, Eigen::Isometry3d>& poses, const Eigen::Isometry3d& newestPose)
{
	// Each keyframe's correction D, T_cw(new) = T_cw(old) * D: a change of
	// the world frame that a frame tracked against the keyframe shares.
	std::map<int, Eigen::Isometry3d> corrections;
	for (const auto& [id, T] : poses) corrections[id] = keyframeMap.find(id)->T_cw.inverse() * T;
	// The local map moves rigidly with the frame that closed the loop (its
	// pose is where the next frames are tracked from), so that tracking goes
	// on against landmarks and window poses that agree with each other.
	const Eigen::Isometry3d D = T_cw.inverse() * newestPose;
	for (auto& kf : window)
	{
		corrections[kf.id] = D;
		kf.T_cw = kf.T_cw * D;
	}
	const Eigen::Isometry3d Dinv = D.inverse();
	for (auto& [id, lm] : landmarks) lm.position = Dinv * lm.position;
	T_cw = T_cw * D;
	for (const auto& [id, c] : corrections) keyframeMap.updatePose(id, keyframeMap.find(id)->T_cw * c);
	// A frame whose keyframe has left the map moves with the next one kept.
	for (auto& frame : frames)
	{
		auto c = corrections.lower_bound(frame.keyframe);
		if (c == corrections.end()) c = std::prev(c);
		frame.T_cw = frame.T_cw * c->second;
	}
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

void VisualOdometry::Impl::addKeyframe(
	const FrameFeatures& f, const std::vector<Match>& inliers, const Eigen::Isometry3d& T)
{
	Keyframe kf;
	kf.id = nextKeyframeId++;
	kf.T_cw = T;
	keyframeMap.add(kf.id, MapKeyframe{T, f.descriptors.clone(), f.points, {}});
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
	while (window.size() > std::size_t(std::max(1, options.window_size))) window.pop_front();
	forgetUnobservedLandmarks();
	if (options.window_size >= 2)
	{
		mrpt::system::CTimeLoggerEntry t(stageTimer, "4 window bundle adjustment");
		backend.bundleAdjust(window, landmarks, f.K);
		for (const auto& k : window) keyframeMap.updatePose(k.id, k.T_cw);
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

void VisualOdometry::Impl::saveState(mrpt::serialization::CArchive& out) const
{
	out << stateVersion;
	writePose(out, T_cw);
	writePose(out, velocity);
	out << std::int32_t(nextLandmarkId);
	// In id order, so that one state always gives the same bytes.
	std::vector<int> ids;
	ids.reserve(landmarks.size());
	for (const auto& [id, lm] : landmarks) ids.push_back(id);
	std::sort(ids.begin(), ids.end());
	out << std::uint32_t(ids.size());
	for (const int id : ids)
	{
		const Landmark& lm = landmarks.at(id);
		out << std::int32_t(id);
		write(out, lm.position.data(), 3);
		write(out, lm.descriptor.data(), lm.descriptor.size());
		out << lm.anchored;
	}
	out << std::uint32_t(window.size());
	for (const auto& kf : window)
	{
		out << std::int32_t(kf.id);
		writePose(out, kf.T_cw);
		out << std::uint64_t(kf.bestInliers) << std::uint32_t(kf.observations.size());
		for (const auto& o : kf.observations)
		{
			out << std::int32_t(o.landmark) << std::int32_t(o.feature);
			write(out, o.pixel.data(), 2);
			out << o.depth;
		}
	}
	out << std::int32_t(nextKeyframeId) << std::int32_t(lostFrames) << std::int32_t(lostFramesWithFeatures);
	keyframeMap.save(out);
	out << std::uint32_t(loops.size());
	for (const auto& e : loops)
	{
		out << std::int32_t(e.from) << std::int32_t(e.to);
		writePose(out, e.T_to_from);
		out << e.sigmaTranslation << e.sigmaRotation << e.robust;
	}
	out << std::uint64_t(frames.size());
	for (const auto& frame : frames)
	{
		out << std::int32_t(frame.keyframe);
		writePose(out, frame.T_cw);
		out << frame.timestamp;
	}
}

void VisualOdometry::Impl::loadState(mrpt::serialization::CArchive& in)
{
	// Everything is read and checked before any of it replaces the state.
	if (const auto version = read<std::uint8_t>(in); version != stateVersion)
		throw badState("odometry state of version " + std::to_string(version) + ", this build reads version " +
					   std::to_string(stateVersion));
	const Eigen::Isometry3d pose = readPose(in), motion = readPose(in);
	const int nextId = read<std::int32_t>(in);
	LandmarkMap map;
	for (auto n = read<std::uint32_t>(in); n > 0; --n)
	{
		const int id = read<std::int32_t>(in);
		Landmark lm;
		read(in, lm.position.data(), 3);
		read(in, lm.descriptor.data(), lm.descriptor.size());
		lm.anchored = read<bool>(in);
		if (id < 0 || id >= nextId || !lm.position.allFinite() || !map.emplace(id, lm).second)
			throw badState("corrupt odometry state (landmark " + std::to_string(id) + ")");
	}
	std::deque<Keyframe> keyframes;
	for (auto n = read<std::uint32_t>(in); n > 0; --n)
	{
		Keyframe& kf = keyframes.emplace_back();
		kf.id = read<std::int32_t>(in);
		kf.T_cw = readPose(in);
		kf.bestInliers = read<std::uint64_t>(in);
		for (auto m = read<std::uint32_t>(in); m > 0; --m)
		{
			Observation& o = kf.observations.emplace_back();
			o.landmark = read<std::int32_t>(in);
			o.feature = read<std::int32_t>(in);
			read(in, o.pixel.data(), 2);
			o.depth = read<double>(in);
			if (!map.count(o.landmark))
				throw badState("corrupt odometry state (a keyframe observes the unknown landmark " +
							   std::to_string(o.landmark) + ")");
		}
	}
	const int nextKeyframe = read<std::int32_t>(in);
	const int lost = read<std::int32_t>(in), lostWithFeatures = read<std::int32_t>(in);
	KeyframeMap places(options);
	places.load(in);
	std::vector<PoseGraphEdge> loopEdges;
	for (auto n = read<std::uint32_t>(in); n > 0; --n)
	{
		PoseGraphEdge& e = loopEdges.emplace_back();
		e.from = read<std::int32_t>(in);
		e.to = read<std::int32_t>(in);
		e.T_to_from = readPose(in);
		e.sigmaTranslation = read<double>(in);
		e.sigmaRotation = read<double>(in);
		e.robust = read<bool>(in);
		if (e.from < 0 || e.to < 0 || e.from >= nextKeyframe || e.to >= nextKeyframe || !(e.sigmaTranslation > 0) ||
			!(e.sigmaRotation > 0))
			throw badState("corrupt odometry state (loop constraint)");
	}
	std::vector<FramePose> framePoses;
	for (auto n = read<std::uint64_t>(in); n > 0; --n)
	{
		FramePose& frame = framePoses.emplace_back();
		frame.keyframe = read<std::int32_t>(in);
		frame.T_cw = readPose(in);
		frame.timestamp = read<double>(in);
		if (frame.keyframe < -1 || frame.keyframe >= nextKeyframe)
			throw badState("corrupt odometry state (frame of keyframe " + std::to_string(frame.keyframe) + ")");
		if (!std::isfinite(frame.timestamp)) throw badState("corrupt odometry state (frame timestamp)");
	}
	for (const auto& kf : keyframes)
		if (kf.id < 0 || kf.id >= nextKeyframe)
			throw badState("corrupt odometry state (keyframe id " + std::to_string(kf.id) + ")");
	if (lost < 0 || lostWithFeatures < 0 || lostWithFeatures > lost)
		throw badState("corrupt odometry state (lost frame counts)");
	T_cw = pose;
	velocity = motion;
	nextLandmarkId = nextId;
	landmarks = std::move(map);
	window = std::move(keyframes);
	nextKeyframeId = nextKeyframe;
	lostFrames = lost;
	lostFramesWithFeatures = lostWithFeatures;
	keyframeMap = std::move(places);
	loops = std::move(loopEdges);
	frames = std::move(framePoses);
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
