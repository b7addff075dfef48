// avm-map's checkpoint, OUTDIR/checkpoint.bin: all a killed run needs to go
// on (avm-map --resume OUTDIR). A finished run writes the same at its end as
// its session, OUTDIR/session.bin: all a next run needs to continue it
// (avm-map --continue OUTDIR). One MRPT archive, in this order:
//   "avm-checkpoint", version
//   CheckpointedRun    the configuration (with --set), rawlog, pose source
//   CheckpointProgress the run's time so far and its log
//   the FrameProcessor's state (src/FrameProcessor_state.cpp)
//   every map of the map definition (MRPT serialization)
// Written aside, flushed to the disk and renamed (io::writeFileAtomically):
// a kill or a power loss at any instant leaves the previous checkpoint whole.
#pragma once

#include <mrpt/maps/CMultiMetricMap.h>

#include <filesystem>
#include <string>

#include "FrameProcessor.h"
#include "avm/pipeline/MappingPipeline.h"

namespace avm::pipeline::detail
{
/** What the run had cost when the checkpoint was taken. */
struct CheckpointProgress
{
	double seconds = 0, cpuSeconds = 0;  //!< wall and process CPU time of the run so far
	std::string log;                     //!< the run's log so far
};

/** Writes a checkpoint into `file` (a CheckpointWriter's, or a finished
 *  run's session: io::RunFolder::session), finishing the processor's
 *  insertion in flight; the processor must be readyForCheckpoint(). */
void writeCheckpoint(const std::filesystem::path& file, const CheckpointedRun& run, const CheckpointProgress& progress,
	const mrpt::maps::CMultiMetricMap& maps, FrameProcessor& processor);

/** The run of the checkpoint `file`. Throws std::runtime_error naming the
 *  file when there is none or it is not a complete checkpoint. */
CheckpointedRun readCheckpointedRun(const std::filesystem::path& file);
/** Restores the maps (made from the same definition) and a fresh processor
 *  from the checkpoint `file`. Throws std::runtime_error naming the file when
 *  it is missing, truncated or holds another run's maps. */
CheckpointProgress readCheckpoint(
	const std::filesystem::path& file, mrpt::maps::CMultiMetricMap& maps, FrameProcessor& processor);
/** The same from the session of the finished run in `previous`. */
CheckpointProgress readSession(
	const std::filesystem::path& previous, mrpt::maps::CMultiMetricMap& maps, FrameProcessor& processor);
/** The same from `file`; an error names it and `what` failed. */
CheckpointProgress readState(const std::filesystem::path& file, const std::string& what,
	mrpt::maps::CMultiMetricMap& maps, FrameProcessor& processor);
/** The session file of the finished run in `previous`; throws
 *  std::runtime_error in one line when there is none (an interrupted run's
 *  folder: it says to resume it first). */
std::filesystem::path sessionFile(const std::filesystem::path& previous);
}  // namespace avm::pipeline::detail
