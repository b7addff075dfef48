// What a run tells the parts that watch it. MappingPipeline's loop only runs
// frames; the program connects observers (MappingPipeline::addObserver: the
// live view, the checkpoints) and each is told, on the loop's thread, in the
// order they were connected:
//
//   betweenFrames(run)   before the first frame and after each one
//   onFrameMapped(frame) a frame with its pose, just before its insertion
//   onFramesEnded(run)   after the last frame, before the end of the run
//                        (the detections still due, the map rebuild, outputs)
//   onRunFinished(run)   the outputs written
//
// An observer changes nothing of the run: the map, trajectory and outputs are
// the same with any observers or none.
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <functional>
#include <optional>

#include "avm/io/RgbdFrame.h"
#include "avm/viewer/MapSnapshot.h"

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
	/** Writes OUTDIR/checkpoint.bin (atomically), what `avm-map --resume
	 *  OUTDIR` continues from; its time counts in stats.json "checkpoint". */
	virtual void writeCheckpoint() = 0;
};

/** A frame with its pose, the moment before its insertion: the map holds
 *  every frame before it and the persons due, and nothing is being inserted. */
struct MappedFrame
{
	const io::RgbdFrame& frame;
	const mrpt::poses::CPose3D& pose;
	std::size_t framesMapped = 0;  //!< before this one
	/** What the live view draws of this moment: the map, trajectory, camera,
	 *  image, person boxes, odometry features and the run's figures. Only
	 *  valid during the call. */
	std::function<viewer::MapSnapshot(const viewer::SnapshotOptions&)> snapshot;
};

/** The run, its outputs written. */
struct FinishedRun
{
	const RunSummary& summary;
	/** The finished map: both trees with their free space, the trajectory,
	 *  the camera at its last pose. */
	std::function<viewer::MapSnapshot()> snapshot;
};

class FrameObserver
{
   public:
	virtual ~FrameObserver() = default;
	/** False ends the run as `stop` does (the view's window was closed); may
	 *  block (a paused view). */
	virtual bool betweenFrames(RunState& /*run*/) { return true; }
	virtual void onFrameMapped(const MappedFrame& /*frame*/) {}
	virtual void onFramesEnded(RunState& /*run*/) {}
	virtual void onRunFinished(const FinishedRun& /*run*/) {}
	/** Whether MappedFrame::snapshot should hold the odometry's features
	 *  (the odometry collects them only then). */
	virtual bool showsFeatures() const { return false; }
};
}  // namespace avm::pipeline
