// Loop closing: a new keyframe that sees again a place an older keyframe saw
// is measured against that place (the candidate keyframe and its neighbours,
// in their current world poses), and the verified measurement enters a pose
// graph over all map keyframes (backend/PoseGraph.h) whose solution moves the
// drifted keyframes back.
//
// Why the neighbours: one keyframe's own depth points are noisy at the
// centimetre level and cover only its view; a place seen by several
// keyframes gives more points over a wider view, so the loop's pose is as
// good as the odometry's own (a loop off by more than the drift it corrects
// would make the trajectory worse).
#pragma once

#include <Eigen/Geometry>

#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "../Types.h"
#include "../backend/CeresBackend.h"
#include "../backend/PoseGraph.h"
#include "../frontend/FeatureFrontend.h"
#include "KeyframeMap.h"
#include "avm/odometry/TOdometryOptions.h"

namespace avm::odometry::detail
{
/** T_cw of keyframes by id: the trajectory's pose of the frame that made
 *  each, the poses the pose graph corrects (the keyframe map's own poses are
 *  the window bundle adjustment's, which the trajectory need not keep:
 *  keyframe_tracked_pose). */
using KeyframePoses = std::map<int, Eigen::Isometry3d>;

/** A verified loop: the new keyframe's pose in the old place's frame. */
struct LoopMeasurement
{
	int candidate = -1;       //!< the old keyframe whose place was seen again
	Eigen::Isometry3d T_cw;   //!< the new keyframe's pose measured against the old place
	std::size_t inliers = 0;  //!< matches within ransac_reprojection at T_cw
	double rotation = 0;      //!< [deg] T_cw's rotation from the tracked one (judgeLoop weighs the centre's shift)
	/** [m^2] Of T_cw's camera centre, from the inliers alone
	 *  (CeresBackend::RefinedPose); zero for a loop measured elsewhere
	 *  (offerLoop), which has loop_sigma alone. */
	Eigen::Matrix3d centreCovariance = Eigen::Matrix3d::Zero();
	/** The inliers: the new keyframe's features and the place's points
	 *  (numbered as placeAround numbers them). */
	std::vector<Match> inlierMatches;
};

/** The place around `candidate`: its features and those of up to
 *  `neighbours` keyframes on each side (ids up to newestId), in the world at
 *  the keyframes' current poses, numbered in keyframe and feature order. */
LandmarkMap placeAround(int candidate, int newestId, const KeyframeMap& map, int neighbours);

/** The best verified loop of the keyframe with features `f` at its tracked
 *  pose T_cw, among the place index's loop_candidates most similar keyframes
 *  of ids up to newestId but those `skip` names; nothing when none has
 *  loop_min_inliers. */
std::optional<LoopMeasurement> measureLoop(const FrameFeatures& f, const Eigen::Isometry3d& T_cw, int newestId,
	const KeyframeMap& map, const FeatureFrontend& frontend, const CeresBackend& backend,
	const TOdometryOptions& options, const std::function<bool(int)>& skip = {});

/** The keyframes' `poses` after optimising the pose graph of their
 *  odometry (each keyframe tied to the next by their relative pose in
 *  `poses`, but for a continued session's first keyframe, which its
 *  placement ties to the keyframe it was placed on), the loop constraints and
 *  the `placements`; the keyframes up to id `fixedUpTo` (the earlier
 *  sessions'), and the oldest keyframe, hold the gauge and come back as given.
 *  Nothing when Ceres returns no usable solution. */
std::optional<KeyframePoses> closeLoops(const KeyframePoses& poses, const std::vector<PoseGraphEdge>& loops,
	const std::vector<PoseGraphEdge>& placements, int fixedUpTo, const TOdometryOptions& options);

/** What the loop check makes of a loop measured at the newest keyframe. */
enum class LoopVerdict
{
	Refused,         //!< it disagrees with the track beyond both their uncertainties: a false loop
	Unconfirmed,     //!< the keyframe before measured no loop, or one that disagrees with it
	WithinOwnError,  //!< the drift it shows is within the loops' own error
	Close            //!< the drift is real: the pose graph moves the keyframes
};

struct LoopJudgement
{
	LoopVerdict verdict = LoopVerdict::Refused;
	std::string why;  //!< the figures the verdict came from, for the status line
};

/** [m] The standard deviation of a loop's camera centre along its worst
 *  axis from its inliers alone (the largest eigenvalue of
 *  centreCovariance); infinite when they do not fix the pose. Reported in
 *  the loop's status (scripts/loop-error-fit.awk reads it), not weighed:
 *  the loop check takes loop_sigma for every loop. */
double inlierSigma(const LoopMeasurement& loop);

/** The loop check, on the shift of the newest keyframe's camera centre that
 *  `loop` measures against its pose in `poses`, with per-axis standard
 *  deviations loop_sigma for a loop (the keyframe before's loop: its edge's
 *  sigmaTranslation) and odometry_sigma for each keyframe of odometry since
 *  the candidate; every test at 99 % (chi-square, 3 degrees of freedom):
 *  - refused when the shift is beyond what the loop and the odometry since
 *    the candidate together allow;
 *  - unconfirmed unless the keyframe before measured a loop (the last of
 *    `loops`) whose shift agrees within two loops' error: one loop may be
 *    off by its own error, drift shows in consecutive loops alike;
 *  - within its own error when the mean of the two shifts is within what two
 *    loops' error allows; else the drift is real and the loop closes. */
LoopJudgement judgeLoop(const LoopMeasurement& loop, int newestId, const std::vector<PoseGraphEdge>& loops,
	const KeyframePoses& poses, const TOdometryOptions& options);

/** `loop` with its rotation from the tracked pose T_cw. */
LoopMeasurement measuredFrom(LoopMeasurement loop, const Eigen::Isometry3d& T_cw);

/** The loop constraint of a measurement made at keyframe `keyframe`, `loop`
 *  in the frame of `poses`, of standard deviation loop_sigma (the same number
 *  in rad for its rotation). */
PoseGraphEdge loopEdge(
	const LoopMeasurement& loop, int keyframe, const KeyframePoses& poses, const TOdometryOptions& options);
}  // namespace avm::odometry::detail
