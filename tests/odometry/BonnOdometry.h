// Shared by the odometry tests on the Bonn sequence (VisualOdometry_bonn_*):
// the sequence's person boxes, detected once, runs of it whole, with frames
// spoilt, or played forward and backward, and the ways a view is spoilt.
#pragma once
#include <gtest/gtest.h>

#include <functional>
#include <iostream>
#include <optional>
#include <vector>

#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>
#include <opencv2/core.hpp>

#include "avm/io/RgbdFrame.h"
#include "avm/io/Trajectory.h"
#include "avm/odometry/OdometryRun.h"

namespace avm::test
{
/** The person boxes the project's detector (YOLOX-Nano) finds in frame `f`,
 *  detected once for every frame of the sequence and kept for all the runs. */
std::vector<cv::Rect> personBoxesOf(const io::RgbdFrame& f);

/** The whole sequence, people masked by personBoxesOf or not masked. */
odometry::OdometryRun runBonn(bool maskPeople, odometry::TOdometryOptions opt = {});

/** The odometry without what steadies it: keyframes take the window bundle
 *  adjustment's pose, no motion prior or gate, one refinement round, a
 *  window of 8 keyframes and 250 landmarks, person boxes grown by 10 px
 *  only. It drifts enough on the sequence played forward and back (7.5 cm)
 *  for its loops to close, where the built-in odometry's 13 mm stays within
 *  the loops' own error (with 30 px margins alone it ends 15 mm off). */
odometry::TOdometryOptions driftingOdometry();

/** Called after every frame of a run with the frame and its estimate. */
using AfterFrame =
	std::function<void(odometry::VisualOdometry&, const io::RgbdFrame&, const odometry::OdometryEstimate&)>;

/** A false loop, as a place recogniser that took a look-alike place for the
 *  start would offer: at the first keyframe from the `from`-th frame on, the camera
 *  measured against frame 0's keyframe `offset` metres (along the old
 *  camera's x axis) from where the ground truth has it. */
struct WrongLoop
{
	WrongLoop(std::size_t fromFrame, double offsetMetres) : from(fromFrame), offset(offsetMetres) {}

	std::size_t from;  //!< counted in frames processed
	double offset;     //!< [m]
	std::size_t seen = 0;
	std::optional<mrpt::poses::CPose3D> start;
	std::optional<odometry::VisualOdometry::LoopOutcome> outcome;

	void operator()(odometry::VisualOdometry& vo, const io::RgbdFrame& f, const odometry::OdometryEstimate& e)
	{
		const std::size_t n = seen++;
		if (!start) start = f.groundTruth.value();
		if (outcome || !e.keyframe || n < from) return;
		const auto truth = f.groundTruth.value() - *start;
		outcome = vo.offerLoop(0,
			mrpt::poses::CPose3D(truth.x() + offset, truth.y(), truth.z(), truth.yaw(), truth.pitch(), truth.roll()));
	}
	/** Asserts the loop was offered and refused. */
	void expectRefused() const
	{
		ASSERT_TRUE(outcome.has_value()) << "no keyframe from frame " << from << " on";
		std::cout << "a loop " << offset << " m off offered: " << outcome->said << "\n";
		EXPECT_FALSE(outcome->closed);
		EXPECT_EQ(outcome->said.rfind("refused", 0), 0u) << outcome->said;
	}
};

/** The masked run with frames [first, last] spoilt by `spoil` (no person
 *  boxes there: the detector would not see one either). Per frame: the
 *  estimate. */
std::vector<odometry::OdometryEstimate> runBonnSpoilt(std::size_t first, std::size_t last,
	const std::function<void(mrpt::obs::CObservation3DRangeScan&)>& spoil, io::Trajectory& trajectory,
	const odometry::TOdometryOptions& options = {}, const AfterFrame& after = {});

/** The frames [first, last] of the sequence, read in one pass. */
std::vector<io::RgbdFrame> bonnFrames(std::size_t first, std::size_t last);

struct ForwardBackward
{
	double endError = 0;  //!< [m] of the last pose (frame 0 again) against its ground truth
	std::size_t loopsClosed = 0;
	std::size_t frames = 0;
	/** Every verified loop's measured and tracked poses against the ground truth. */
	std::vector<odometry::LoopAccuracy> loops;
};

/** The sequence played forward, then backward (frames 0..299, 298..0: one
 *  sequence whose end shows the camera its start again), people masked. The
 *  backward half is read in chunks, to keep a few frames in memory at once. */
ForwardBackward playForwardBackward(const odometry::TOdometryOptions& opt, const AfterFrame& after = {});

/** Motion blur of someone passing right in front of the lens: the colour
 *  image heavily smoothed (61 px kernel, sigma 20 px), the depth kept. */
void blurView(mrpt::obs::CObservation3DRangeScan& obs);

/** A view filled by people close to the lens: all but the image's left
 *  1/parts flat grey without depth, as a crowd too close for the depth
 *  camera, or masked out, leaves it. */
void keepLeftOf(mrpt::obs::CObservation3DRangeScan& obs, int parts);

/** keepLeftOf the image's sixth. */
inline void fillViewWithPeople(mrpt::obs::CObservation3DRangeScan& obs) { keepLeftOf(obs, 6); }

/** The camera's ground truth of the sequence, one pose a frame. */
io::Trajectory groundTruth();

/** ATE RMSE [m] of frames [from, from + count) of `est` against groundTruth(). */
double ate(const io::Trajectory& est, std::size_t from, std::size_t count);
}  // namespace avm::test
