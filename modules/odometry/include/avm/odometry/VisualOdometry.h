// Feature-based RGB-D visual odometry: ORB features with depth, matched to a
// local map of recent landmarks, PnP RANSAC from a constant-velocity guess,
// then a robust Ceres pose refinement and a sliding-window bundle adjustment
// over the last keyframes. Features inside person boxes are left out. The
// keyframes of the whole run stay in a map with a place-recognition index:
// a lost frame is relocalised against it, back in the old map's frame, and a
// new keyframe that sees an old place again closes a loop (a pose graph over
// the keyframes, Ceres) that corrects the drift of every pose since.
//
// Frames: every pose is the camera OPTICAL frame (z forward, x right, y down)
// in the world, the convention of TUM trajectories and of avm rawlogs.
#pragma once

#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <opencv2/core/types.hpp>

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "avm/odometry/TOdometryOptions.h"

namespace mrpt::serialization
{
class CArchive;
}

namespace avm::odometry
{
/** A loop verified at a keyframe (loop closure on): where it puts the
 *  camera and where the odometry had it, both relative to the camera of the
 *  old keyframe whose place it saw again. Against the ground truth's relative
 *  pose of the same two frames (loopAccuracy, OdometryRun.h) this says how
 *  good a loop measurement is beside the drift it would correct. */
struct LoopReport
{
	std::size_t candidateFrame = 0;  //!< the old keyframe's frame (process() calls, from 0)
	std::size_t inliers = 0;         //!< matches with the place after the refinement
	mrpt::poses::CPose3D measured;   //!< this camera in the old keyframe's camera frame, as the loop measured it
	mrpt::poses::CPose3D tracked;    //!< and as the odometry had tracked it
};

/** How good a frame's own pose measurement is, beside the motion model's
 *  prediction: filled for a frame whose pose was measured against the local
 *  map (tracked, or bridged as untrusted); zeros otherwise. */
struct TrackQuality
{
	/** Share of the image's cells (8 x 6) that hold an inlier, in [0, 1]: a
	 *  view filled by people leaves its inliers in a corner. */
	double spread = 0;
	/** [m] The measured camera centre's standard deviation along its worst
	 *  axis (the largest eigenvalue of its covariance from the inliers,
	 *  CeresBackend); infinite when the inliers do not fix the pose. */
	double centreSigma = 0;
	/** [m] Per-axis standard deviation of the constant-velocity model's
	 *  centre, from the odometry's own recent frames (the median of their
	 *  squared distances from the prediction, over chi-square(3)'s median),
	 *  times 1 + the frames bridged since the last measured one (a constant
	 *  velocity carried over n frames is n times as far off); 0 while there
	 *  are too few of them. */
	double predictionSigma = 0;
	/** The measured centre's distance from the prediction, squared, in the
	 *  metric of the two covariances together (Mahalanobis; chi-square with
	 *  3 degrees of freedom when both hold); 0 without a prediction sigma. */
	double motionChi2 = 0;
};

struct OdometryEstimate
{
	mrpt::poses::CPose3D pose;  //!< camera optical frame in the world (never NaN)
	/** False while a continued session has not yet found its frames in the
	 *  earlier sessions' keyframe map (VisualOdometry::continueSession): the
	 *  frame has no pose, `pose` means nothing, and trajectory() leaves it out. */
	bool placed = true;
	bool tracked = false;   //!< false: the pose is bridged by the motion model
	bool keyframe = false;  //!< the frame became a keyframe
	/** A loop closed at this frame and moved the poses of earlier frames:
	 *  VisualOdometry::trajectory() has them. */
	bool loopClosed = false;
	/** The track came back at this frame after this many lost frames; their
	 *  poses, bridged by the motion model at the time, are placed between
	 *  the last tracked pose and this one in VisualOdometry::trajectory(). */
	std::size_t bridgedFramesPlaced = 0;
	/** The loop verified at this keyframe, whether it moved the poses or not. */
	std::optional<LoopReport> loop;
	std::size_t inliers = 0;      //!< matches consistent with the pose
	double reprojectionRmse = 0;  //!< [px] over the inliers
	TrackQuality quality;
	std::string status;  //!< "tracking", "initialised", or why tracking was lost
	/** [px] The frame's features with depth, and those a person box took away;
	 *  empty unless VisualOdometry::reportFeatures() is on (the live view). */
	std::vector<cv::Point2f> features, maskedFeatures;
};

class VisualOdometry
{
   public:
	/** Throws std::invalid_argument for bad options (see TOdometryOptions::validate)
	 *  or a non-finite initial pose. */
	explicit VisualOdometry(const TOdometryOptions& options, const mrpt::poses::CPose3D& initialPose = {});
	~VisualOdometry();
	VisualOdometry(VisualOdometry&&) noexcept;
	VisualOdometry& operator=(VisualOdometry&&) noexcept;

	/** Tracks one registered RGB-D frame (colour + depth + intrinsics). The
	 *  person boxes (pixels of this image) are masked out when mask_people is
	 *  on. Throws std::invalid_argument if the observation has no colour or no
	 *  range image; a frame without usable depth or texture is a lost frame. */
	OdometryEstimate process(
		const mrpt::obs::CObservation3DRangeScan& obs, const std::vector<cv::Rect>& personBoxes = {});

	/** Writes the tracking state (pose, motion model, local map, keyframe
	 *  window) to a checkpoint, every number bit-exact, so that a run resumed
	 *  with loadState() gives exactly the poses of an uninterrupted run. The
	 *  options and the stage times are not part of it: resume with the same
	 *  options. */
	void saveState(mrpt::serialization::CArchive& out) const;
	/** Replaces the whole tracking state with one that saveState() wrote.
	 *  Throws std::runtime_error on a truncated, corrupt or other-version
	 *  stream, and then leaves the state as it was. */
	void loadState(mrpt::serialization::CArchive& in);

	/** Makes the state loadState() read (a finished run's) the start of a new
	 *  session, as a robot's next run in the same building: the keyframe map,
	 *  its place index and loops and the frames' poses are kept and stay where
	 *  they are (a later loop holds every earlier keyframe and frame fixed);
	 *  the tracking starts over, not placed. Each frame is then looked up
	 *  among all the keyframes by place recognition (as a lost frame is
	 *  relocalised) until one is placed; the frames before it are not placed
	 *  (OdometryEstimate::placed) and get no pose. From the placed frame on,
	 *  tracking, relocalisation and loop closing work on the whole map. */
	void continueSession();
	/** Frames of the earlier sessions (continueSession), at the front of trajectory(). */
	std::size_t framesBeforeSession() const;

	/** Fills OdometryEstimate::features and maskedFeatures from now on. The
	 *  masked ones cost a second ORB detection on the masked pixels; tracking
	 *  is the same either way. */
	void reportFeatures(bool on);

	/** Place recognition of a frame against the keyframe map, as a lost frame
	 *  would be relocalised, without changing the state. Keyframe ids count
	 *  the frames that process() reported as keyframes, from 0. */
	struct PlaceQuery
	{
		/** (keyframe id, similarity in [0, 1]) of the index's candidates,
		 *  best first; similarity 0 while the vocabulary is not trained yet. */
		std::vector<std::pair<std::size_t, double>> candidates;
		bool accepted = false;      //!< a candidate passed the geometric check
		std::size_t keyframe = 0;   //!< the accepted keyframe
		std::size_t inliers = 0;    //!< its inliers after the refinement
		mrpt::poses::CPose3D pose;  //!< the relocalised pose (camera optical frame in the world)
	};
	PlaceQuery queryPlace(
		const mrpt::obs::CObservation3DRangeScan& obs, const std::vector<cv::Rect>& personBoxes = {}) const;

	/** What the loop check made of a loop. */
	struct LoopOutcome
	{
		bool closed = false;  //!< the keyframes and frames moved (trajectory() has them)
		std::string said;     //!< refused, kept (not confirmed, within the loops' own error) or closed, and why
	};
	/** A loop measured outside the odometry (another place recogniser, a
	 *  fiducial marker, a map server): the camera of the frame just
	 *  processed, which must have made a keyframe, at `measured` in the
	 *  camera frame of frame `oldFrame` (which made a keyframe the keyframe
	 *  map still holds). It goes through the same check as the odometry's own
	 *  loops (loop_sigma, odometry_sigma), whether loop_closure is on or not.
	 *  Throws std::logic_error when the last frame made no keyframe and
	 *  std::invalid_argument for a bad oldFrame or a non-finite pose. */
	LoopOutcome offerLoop(std::size_t oldFrame, const mrpt::poses::CPose3D& measured);

	const TOdometryOptions& options() const;
	/** Keyframes of the local window (bundle adjustment). */
	std::size_t keyframeCount() const;
	/** Keyframes kept for relocalisation (at most map_max_keyframes). */
	std::size_t mapKeyframeCount() const;
	std::size_t landmarkCount() const;
	/** The pose of every frame process() has seen, in order, as the closed
	 *  loops have corrected them (without loops: the poses it returned). */
	std::vector<mrpt::poses::CPose3D> trajectory() const;
	/** Time spent per stage so far (features, matching + PnP, refinement,
	 *  bundle adjustment, relocalisation), as MRPT's CTimeLogger table. */
	std::string stageTimesText() const;

   private:
	struct Impl;
	std::unique_ptr<Impl> m_impl;
};
}  // namespace avm::odometry
