// Feature-based RGB-D visual odometry: ORB features with depth, matched to a
// local map of recent landmarks, PnP RANSAC from a constant-velocity guess,
// then a robust Ceres pose refinement and a sliding-window bundle adjustment
// over the last keyframes. Features inside person boxes are left out.
//
// Frames: every pose is the camera OPTICAL frame (z forward, x right, y down)
// in the world, the convention of TUM trajectories and of avm rawlogs.
#pragma once

#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <opencv2/core/types.hpp>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "avm/odometry/TOdometryOptions.h"

namespace mrpt::serialization
{
class CArchive;
}

namespace avm::odometry
{
struct OdometryEstimate
{
	mrpt::poses::CPose3D pose;    //!< camera optical frame in the world (never NaN)
	bool tracked = false;         //!< false: the pose is bridged by the motion model
	bool keyframe = false;        //!< the frame became a keyframe
	std::size_t inliers = 0;      //!< matches consistent with the pose
	double reprojectionRmse = 0;  //!< [px] over the inliers
	std::string status;           //!< "tracking", "initialised", or why tracking was lost
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

	/** Fills OdometryEstimate::features and maskedFeatures from now on. The
	 *  masked ones cost a second ORB detection on the masked pixels; tracking
	 *  is the same either way. */
	void reportFeatures(bool on);

	const TOdometryOptions& options() const;
	std::size_t keyframeCount() const;
	std::size_t landmarkCount() const;
	/** Time spent per stage so far (features, matching + PnP, refinement,
	 *  bundle adjustment), as MRPT's CTimeLogger table. */
	std::string stageTimesText() const;

   private:
	struct Impl;
	std::unique_ptr<Impl> m_impl;
};
}  // namespace avm::odometry
