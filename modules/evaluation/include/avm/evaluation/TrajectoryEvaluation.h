// Accuracy of an estimated trajectory against ground truth: the absolute
// trajectory error (ATE) after the best rigid (SE(3), Horn/Umeyama) alignment,
// and the relative pose error (RPE) over a fixed time step, expressed per second;
// and how much the camera centre accelerates from pose to pose, in the estimate
// and in the ground truth: a hand-held or robot camera moves smoothly, so an
// estimate that accelerates far more than its ground truth is noisy from frame
// to frame, whatever the calibration between the two (which RPE depends on).
// Both trajectories are in the same frame convention (for avm: the camera
// optical frame in the world, as TUM ground truth).
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "avm/io/IniKeyOptions.h"
#include "avm/io/Trajectory.h"

namespace avm::evaluation
{
struct TEvaluationOptions : public io::CIniKeyOptions<TEvaluationOptions>
{
	/** [s] an estimated pose is matched with the ground-truth pose nearest in
	 *  time when they are at most this far apart. */
	double maxTimeDifference = 0.02;
	/** Index of the first estimated pose evaluated (0-based). */
	std::size_t firstFrame = 0;
	/** Number of estimated poses evaluated from firstFrame; 0 = all. */
	std::size_t maxFrames = 0;
	/** [s] time step of the relative pose error. */
	double rpeDelta = 1.0;

	/** Every key: name, member, unit, description, check. */
	static io::IniKeys<TEvaluationOptions> iniKeys();
};

/** Summary of a set of non-negative errors. */
struct ErrorStatistics
{
	double rmse = 0, mean = 0, median = 0, max = 0;
	std::size_t count = 0;
};

struct TrajectoryErrors
{
	ErrorStatistics ate;             //!< [m] position error after alignment
	ErrorStatistics rpeTranslation;  //!< [m/s] relative translation error per second
	ErrorStatistics rpeRotation;     //!< [deg/s] relative rotation error per second
	/** [m] The translation error of the motion from each matched pose to the
	 *  next: a jump of the estimate shows here at its full size, where the
	 *  RPE per second averages it with the frames around it. */
	ErrorStatistics frameToFrame;
	/** [m/s^2] the estimated camera centre's acceleration at each matched
	 *  pose between two others (cameraAcceleration), and the ground truth's
	 *  at the same poses. */
	ErrorStatistics acceleration, groundTruthAcceleration;
	std::size_t matchedPairs = 0;    //!< estimated poses with a ground-truth match
	std::size_t evaluatedPoses = 0;  //!< estimated poses in the frame range
	/** The alignment applied to the estimate: gt ≈ alignment (+) estimate. */
	mrpt::poses::CPose3D alignment;
};

/** Index pairs (estimate, ground truth): each estimated pose with the
 *  ground-truth pose nearest in time, if within maxTimeDifference. The
 *  ground truth in time order (io::inTimeOrder). */
std::vector<std::pair<std::size_t, std::size_t>> associateByTimestamp(
	const io::Trajectory& estimate, const io::Trajectory& groundTruth, double maxTimeDifference);

/** The rigid transform T minimising sum |T*src_i - dst_i|^2 (Horn/Umeyama,
 *  no scale). Throws std::invalid_argument if fewer than 3 pairs or sizes differ. */
mrpt::poses::CPose3D alignRigid(
	const std::vector<mrpt::math::TPoint3D>& src, const std::vector<mrpt::math::TPoint3D>& dst);

/** How far an estimated pose is from the true one: the distance between
 *  their positions [m] and the angle of the rotation between them [deg]. */
struct PoseError
{
	double metres = 0, degrees = 0;
};
PoseError poseError(const mrpt::poses::CPose3D& estimate, const mrpt::poses::CPose3D& truth);

/** [m/s^2] The camera centre's acceleration at each pose between two others:
 *  |v(k, k+1) - v(k-1, k)| over half the time from pose k-1 to k+1, with v
 *  the mean velocity between two poses. Poses closer in time than 1 ms are
 *  skipped (a repeated timestamp says nothing of the motion). */
std::vector<double> cameraAcceleration(const io::Trajectory& poses);

/** Statistics of a list of errors (all zero for an empty list). */
ErrorStatistics statisticsOf(std::vector<double> errors);

/** ATE, RPE and accelerations of `estimate` against `groundTruth`, either in
 *  any order (sessions mapped in another order than they were recorded): both
 *  are taken in time order, the estimate's frame range (firstFrame,
 *  maxFrames) in its own order first. Throws std::runtime_error when fewer
 *  than 3 poses can be matched (nothing meaningful to align). */
TrajectoryErrors evaluateTrajectory(
	const io::Trajectory& estimate, const io::Trajectory& groundTruth, const TEvaluationOptions& options);

/** A human-readable multi-line report of the errors. */
std::string formatReport(const TrajectoryErrors& errors);
}  // namespace avm::evaluation
