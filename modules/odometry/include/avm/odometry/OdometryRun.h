// Running the odometry over a whole rawlog: the trajectory (TUM, camera
// optical frame), the per-frame estimates and the time each frame took. The
// odometry benchmark (avm-odometry) and the tests run through this.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "avm/evaluation/TrajectoryEvaluation.h"
#include "avm/io/RgbdFrame.h"
#include "avm/io/Trajectory.h"
#include "avm/odometry/VisualOdometry.h"

namespace avm::odometry
{
/** Person boxes of a frame (pixels of its colour image). */
using PersonBoxSource = std::function<std::vector<cv::Rect>(const io::RgbdFrame&)>;

struct FrameRecord
{
	std::size_t index = 0;
	double timestamp = 0;  //!< [s] UNIX time
	OdometryEstimate estimate;
	std::size_t personBoxes = 0;
	double milliseconds = 0;     //!< wall time of VisualOdometry::process (not I/O or detection)
	double cpuMilliseconds = 0;  //!< CPU time of the calling thread in it (unaffected by other processes)
	std::optional<mrpt::poses::CPose3D> groundTruth;  //!< the rawlog's, when it has one (camera optical frame)
};

/** How far a loop's measured and tracked poses (relative to the old
 *  keyframe's camera) are from the ground truth's relative pose of the same
 *  two frames. */
struct LoopAccuracy
{
	evaluation::PoseError measured, tracked;
};
LoopAccuracy loopAccuracy(
	const LoopReport& loop, const mrpt::poses::CPose3D& truthOld, const mrpt::poses::CPose3D& truthNew);

struct OdometryRun
{
	std::vector<FrameRecord> frames;
	std::string stageTimes;  //!< VisualOdometry::stageTimesText() at the end of the run
	io::Trajectory trajectory() const;
	std::size_t lostFrames() const;
	std::size_t keyframes() const;
	/** "frames N, lost L, keyframes K", then wall and thread-CPU ms per frame
	 *  (mean, median, p95, max), one line each. */
	std::string timingSummary() const;
	/** Writes one CSV line per frame (atomically). */
	void writeFrameStats(const std::filesystem::path& csv) const;
	/** Writes one CSV line per verified loop (atomically): the frames, the
	 *  measured and tracked relative poses, and their loopAccuracy when both
	 *  frames have ground truth. */
	void writeLoops(const std::filesystem::path& csv) const;
	/** The loopAccuracy of every verified loop whose two frames have ground truth, in frame order. */
	std::vector<LoopAccuracy> loopAccuracies() const;
	/** "loops N verified, C closed", and with ground truth the mean and
	 *  largest error of the measured and of the tracked relative poses; empty
	 *  when no loop was verified. */
	std::string loopSummary() const;
};

/** Runs the odometry over the rawlog's frames (the first maxFrames, 0 = all),
 *  starting at the first frame's ground truth when the rawlog has it (so the
 *  trajectory is in the ground truth's world), else at the identity.
 *  progress(done) is called after every frame. */
OdometryRun runOdometry(const std::filesystem::path& rawlog, const TOdometryOptions& options,
	const PersonBoxSource& personBoxes = {}, std::size_t maxFrames = 0,
	const std::function<void(std::size_t)>& progress = {});

/** One box per person in the observation's pixelLabels, as
 *  avm/persons/PersonLabels.h reads them ("person/k" labels as avm-detect
 *  writes them, or each connected region of a plain "person" label); none
 *  when there are no labels. */
std::vector<cv::Rect> personBoxesFromLabels(const mrpt::obs::CObservation3DRangeScan& obs);

/** Options from `section` of an ini file; throws std::runtime_error naming
 *  the file when it cannot be read, std::invalid_argument for a bad value.
 *  Keys in the section that the options do not know go to unknownKeys. */
TOdometryOptions loadOdometryOptions(
	const std::filesystem::path& ini, const std::string& section, std::vector<std::string>& unknownKeys);
}  // namespace avm::odometry
