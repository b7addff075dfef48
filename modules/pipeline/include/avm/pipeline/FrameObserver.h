// What a run tells the parts that watch it. MappingPipeline's loop only runs
// frames; the program connects observers (MappingPipeline::addObserver: the
// live view, the checkpoints) and each is told, on the loop's thread, in the
// order they were connected:
//
//   betweenFrames(run)     before the first frame and after each one
//   onFrameMapped(frame)   a frame with its pose, just before its insertion
//   onFrameInserted(frame) a frame in the map, its insertion finished (the
//                          run's frames, and the map rebuild's)
//   onFramesEnded(run)     after the last frame, before the end of the run
//                          (the detections still due, the map rebuild, outputs)
//   onMapStartedOver()     the map rebuild cleared the map: every mapped
//                          frame is inserted again
//   writeStats(run, json)  the map final: what it measured, into stats.json
//   onRunFinished(run)     the outputs written
//   onRunFailed(run)       the run ended on an error after its first frame
//                          was read: it writes no outputs
//
// An observer changes nothing of the run: the map, trajectory and outputs are
// the same with any observers or none. It reads what it needs of a moment
// (the map, the trajectory, the frame) and makes its own copy of it.
#pragma once

#include <mrpt/img/TPixelCoord.h>
#include <mrpt/math/TBoundingBox.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "avm/io/JsonWriter.h"
#include "avm/io/RgbdFrame.h"
#include "avm/io/Trajectory.h"

namespace avm
{
class CAdaptiveOctoMap;
}

namespace avm::pipeline
{
struct RunSummary;

/** The run between two frames: what an observer may read, and save. */
class RunState
{
   public:
	virtual ~RunState() = default;
	/** A run resumed from a checkpoint (it did not start at the first frame). */
	virtual bool resumed() const = 0;
	/** The last frame processed (restored by a resume); before the first,
	 *  nothing, or a continued run's earlier session's last frame. */
	virtual std::optional<std::size_t> lastFrame() const = 0;
	/** False while an applied detection's persons wait for a frame with a
	 *  pose: a checkpoint then could not be resumed from. */
	virtual bool canCheckpoint() const = 0;
	/** Writes the run's checkpoint into `file` (atomically), what
	 *  MappingPipeline::resume continues from; its time counts in
	 *  stats.json "checkpoint". */
	virtual void writeCheckpoint(const std::filesystem::path& file) = 0;
};

/** A person box of a detection, and the person it was taken for. */
struct DetectedPerson
{
	double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  //!< [px]
	std::uint32_t personId = 0;             //!< 0: not taken for a person
	double score = 0;
};

/** A frame with its pose, the moment before its insertion: the map holds
 *  every frame before it and the persons due, and nothing is being inserted.
 *  The references are only valid during the call. */
struct MappedFrame
{
	const io::RgbdFrame& frame;
	const mrpt::poses::CPose3D& pose;
	std::size_t framesMapped = 0;  //!< before this one
	const CAdaptiveOctoMap& map;
	const io::Trajectory& trajectory;  //!< the run's poses, this frame's included
	std::optional<std::size_t> switchFrame;
	/** Each stage's mean time so far [ms]: odometry, detection, map. */
	std::vector<std::pair<std::string, double>> stageMeansMs;
	/** The latest detection's boxes (detection_lag_frames old). */
	const std::vector<DetectedPerson>& latestPersons;
	/** [px] The odometry's features in this frame, and those a person box
	 *  took away; empty unless an observer showsFeatures(). */
	const std::vector<mrpt::img::TPixelCoordf>& features;
	const std::vector<mrpt::img::TPixelCoordf>& maskedFeatures;
};

/** A frame in the map, once its insertion has finished: nothing else is
 *  being inserted. The references are only valid during the call. */
struct InsertedFrame
{
	const mrpt::obs::CObservation3DRangeScan& observation;
	const mrpt::poses::CPose3D& pose;
	/** The boxes whose points this insertion took as free-only (moving
	 *  persons: they carve free space and mark nothing occupied),
	 *  CAdaptiveOctoMap::lastFreeOnlyBoxes(). */
	const std::vector<mrpt::math::TBoundingBox>& freeOnlyBoxes;
	const CAdaptiveOctoMap& map;
};

/** The run at its end: the map final (rebuilt, when it was). */
struct FinishedRun
{
	const RunSummary& summary;
	/** The finished map: both trees with their free space. */
	const CAdaptiveOctoMap& map;
	const io::Trajectory& trajectory;
	std::optional<std::size_t> lastFrame;  //!< the last frame processed
};

class FrameObserver
{
   public:
	virtual ~FrameObserver() = default;
	/** False ends the run as `stop` does (the view's window was closed); may
	 *  block (a paused view). */
	virtual bool betweenFrames(RunState& /*run*/) { return true; }
	virtual void onFrameMapped(const MappedFrame& /*frame*/) {}
	virtual void onFrameInserted(const InsertedFrame& /*frame*/) {}
	virtual void onFramesEnded(RunState& /*run*/) {}
	virtual void onMapStartedOver() {}
	/** Its sections of stats.json, written inside its top object. */
	virtual void writeStats(const FinishedRun& /*run*/, io::JsonWriter& /*stats*/) {}
	virtual void onRunFinished(const FinishedRun& /*run*/) {}
	virtual void onRunFailed(const RunState& /*run*/) {}
	/** Whether MappedFrame should hold the odometry's features (the
	 *  odometry collects them only then). */
	virtual bool showsFeatures() const { return false; }
};
}  // namespace avm::pipeline
