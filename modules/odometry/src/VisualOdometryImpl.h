// The state and the steps of VisualOdometry, shared by its source files:
// VisualOdometry.cpp (a frame: features, tracking, keyframes),
// VisualOdometry_loss.cpp (untrusted and lost frames, relocalisation),
// VisualOdometry_loops.cpp (loop closing) and VisualOdometry_state.cpp
// (checkpoints).
#pragma once

#include <mrpt/poses/CPose3D.h>
#include <mrpt/system/CTimeLogger.h>

#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "avm/io/DepthCamera.h"
#include "avm/odometry/VisualOdometry.h"
#include "backend/CeresBackend.h"
#include "frontend/FeatureFrontend.h"
#include "map/KeyframeMap.h"
#include "map/LoopClosing.h"

namespace avm::odometry
{
namespace detail
{
inline Eigen::Isometry3d toIsometry(const mrpt::poses::CPose3D& p)
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

inline mrpt::poses::CPose3D toPose(const Eigen::Isometry3d& T)
{
	mrpt::math::CMatrixDouble33 R;
	for (int r = 0; r < 3; ++r)
		for (int c = 0; c < 3; ++c) R(r, c) = T.linear()(r, c);
	const Eigen::Vector3d t = T.translation();
	return mrpt::poses::CPose3D(R, mrpt::math::CVectorFixedDouble<3>({t.x(), t.y(), t.z()}));
}

struct FrameImages
{
	cv::Mat grey, depth;  //!< depth in metres, registered to the colour image
	io::DepthCamera K;
};
/** The grey image, depth in metres and camera of a registered RGB-D frame;
 *  throws std::invalid_argument without a range image or unregistered. */
FrameImages imagesOf(const mrpt::obs::CObservation3DRangeScan& obs);
}  // namespace detail

using namespace detail;

struct VisualOdometry::Impl
{
	Impl(const TOdometryOptions& o, const mrpt::poses::CPose3D& initial);
	// CTimeLogger prints its table when destroyed with data; the owner asks for it instead.
	~Impl() { stageTimer.clear(true); }
	Impl(const Impl&) = delete;
	Impl& operator=(const Impl&) = delete;

	/** Frames whose deviation from the prediction the motion gate's scale is
	 *  the median of: about a second at 30 Hz, long enough for the median to
	 *  hold through a few bad frames, short enough to follow a change of pace. */
	static constexpr std::size_t kDeviationHistory = 30;

	TOdometryOptions options;
	FeatureFrontend frontend;
	CeresBackend backend;
	Eigen::Isometry3d T_cw;  //!< latest pose (world -> camera)
	/** Camera motion of the last frame, T_cw(k) * T_cw(k-1)^-1, for the prediction. */
	Eigen::Isometry3d velocity = Eigen::Isometry3d::Identity();
	/** The velocity was measured between two tracked frames (not reset by a
	 *  start, a relocalisation or a new local map): the motion gate may judge by it. */
	bool velocityMeasured = false;
	/** [m] How far the last accepted frames' camera centres were from the
	 *  prediction, oldest first (at most kDeviationHistory): the motion
	 *  gate's scale, the odometry's own recent agreement with its motion model. */
	std::deque<double> recentDeviations;
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
	/** The session this state tracks (continueSession): the keyframes of ids
	 *  below firstKeyframe and the frames below firstFrame are the earlier
	 *  sessions', held fixed; `placing` until a frame is found among them. */
	struct Session
	{
		int firstKeyframe = 0;
		std::size_t firstFrame = 0;
		bool placing = false;
		/** Where each continued session was placed: its first keyframe to the
		 *  keyframe it was relocalised against, a constraint of the pose graph
		 *  in place of the odometry that no camera measured across the gap. */
		std::vector<PoseGraphEdge> placements;
		/** Earlier sessions' places whose points the local map joined: the
		 *  place's keyframe -> the keyframe that joined it. While that one is in
		 *  the window the place is tracked, not a loop to measure again. */
		std::map<int, int> joined;
	} session;
	mrpt::system::CTimeLogger stageTimer{true, "avm odometry stages"};
	bool reportFeatures = false;

	OdometryEstimate process(const mrpt::obs::CObservation3DRangeScan& obs, const std::vector<cv::Rect>& boxes);
	/** The frame's pose from its features: tracked, initialised, relocalised or bridged. */
	OdometryEstimate track(const FrameFeatures& f);
	/** The first keyframe, at the initial pose, once a frame has enough features. */
	OdometryEstimate initialise(const FrameFeatures& f);
	/** A continued session's frame looked up among all the keyframes: placed
	 *  there, a new local map starts at its pose; else not placed. */
	OdometryEstimate place(const FrameFeatures& f);
	void continueSession();
	VisualOdometry::PlaceQuery queryPlace(
		const mrpt::obs::CObservation3DRangeScan& obs, const std::vector<cv::Rect>& boxes) const;
	/** Whether a frame tracked at T with `inliers` inliers makes a keyframe
	 *  (keyframe_translation, keyframe_rotation, keyframe_overlap). */
	bool needsKeyframe(const Eigen::Isometry3d& T, std::size_t inliers);
	/** A keyframe at T from the frame's matched inliers and new landmarks for
	 *  the unmatched features; runs the window bundle adjustment. */
	void addKeyframe(const FrameFeatures& f, const std::vector<Match>& inliers, const Eigen::Isometry3d& T);
	void forgetUnobservedLandmarks();
	/** Looks for a loop at the newest keyframe (features f); when a verified
	 *  loop shows drift, optimises the pose graph and moves everything with
	 *  it. What it found goes to e's status; e.loopClosed when the poses moved. */
	void closeLoop(const FrameFeatures& f, OdometryEstimate& e);
	/** The loop check (judgeLoop) on a loop measured at the newest keyframe,
	 *  and the pose graph when it says close. */
	VisualOdometry::LoopOutcome considerLoop(const LoopMeasurement& loop);
	VisualOdometry::LoopOutcome offerLoop(std::size_t oldFrame, const mrpt::poses::CPose3D& measured);
	/** The index in `frames` of the frame that made keyframe `keyframe`; frames.size() when none did. */
	std::size_t frameThatMade(int keyframe) const;
	/** The trajectory's pose of every map keyframe (KeyframePoses), the
	 *  current frame's for a keyframe it made. */
	KeyframePoses trackedPoses() const;
	/** Moves every keyframe of `to` (the window's too) from its pose `from`
	 *  to `to`, its keyframe map pose, landmarks and this session's frames
	 *  with it, and the current frame with the newest keyframe. */
	void moveTo(const KeyframePoses& from, const KeyframePoses& to);
	/** The newest keyframe's features that a loop matched observe the place's
	 *  points (placeAround the loop's candidate, of keyframes up to
	 *  newestPlaceKeyframe) from now on. */
	void joinPlace(const LoopMeasurement& loop, int newestPlaceKeyframe);
	/** Whether `keyframe` is within loop_neighbours of an earlier session's
	 *  place that a keyframe of the window joined. */
	bool inJoinedPlace(int keyframe) const;
	/** The `count` frames before the newest, bridged while the track was
	 *  lost, placed between the last tracked frame and the newest one,
	 *  which found the track again, by timestamp (io::interpolatePose): the
	 *  camera went from the one to the other, the motion model only guessed
	 *  where. A frame whose stamp is not between the two keeps its guess. */
	void placeBridgedFrames(std::size_t count);
	/** Drops the local map and starts a new one with this frame as its keyframe at T; the loss is over. */
	void restartLocalMap(const FrameFeatures& f, const Eigen::Isometry3d& T);
	OdometryEstimate lost(const FrameFeatures& f, const std::string& why);
	/** Why a tracked pose at `deviation` [m] from the prediction is not to be
	 *  trusted (motion_gate), or nothing. */
	std::optional<std::string> implausibleMotion(double deviation) const;
	/** The frame's pose from the motion model, the local map kept: its own
	 *  pose was not to be had or not trusted. One more lost frame. */
	OdometryEstimate bridge(const std::string& why);

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
}  // namespace avm::odometry
