// avm-map's checkpoints as an observer of the run (avm/pipeline/FrameObserver.h):
// the writer owns its file, OUTDIR/checkpoint.bin. It writes one before the
// first frame (not in a resumed run: its checkpoint is there), one every
// `interval_s` of run time between two frames, and one after the last frame,
// unless the last one already holds it; it removes the file once the run has
// finished (a finished run has nothing left to resume) or failed on its input
// (resuming would meet the same input), and keeps it when the run was
// interrupted. What a checkpoint holds: src/Checkpoint.h; what resumes from
// it: MappingPipeline::resume(file()).
#pragma once

#include <mrpt/system/CTicTac.h>

#include <filesystem>
#include <optional>

#include "avm/pipeline/FrameObserver.h"
#include "avm/pipeline/MappingPipeline.h"

namespace avm::pipeline
{
class CheckpointWriter : public FrameObserver
{
   public:
	/** The checkpoint of the run whose output folder is `outDir`, written
	 *  every `intervalSeconds` ([pipeline] checkpoint_interval_s; 0 writes
	 *  none). */
	explicit CheckpointWriter(const std::filesystem::path& outDir, double intervalSeconds = 0);

	/** OUTDIR/checkpoint.bin (io::RunFolder::checkpoint). */
	const std::filesystem::path& file() const { return m_file; }
	/** The run of the checkpoint in file(), what `avm-map --resume OUTDIR`
	 *  makes its pipeline from. Throws std::runtime_error naming the file
	 *  when there is none or it is not a complete checkpoint. */
	CheckpointedRun checkpointedRun() const;

	bool betweenFrames(RunState& run) override;
	void onFramesEnded(RunState& run) override;
	void onRunFinished(const FinishedRun& run) override;
	void onRunFailed(const RunState& run) override;

   private:
	void write(RunState& run);

	std::filesystem::path m_file;
	double m_interval;
	mrpt::system::CTicTac m_sinceLast;
	bool m_written = false;
	std::optional<std::size_t> m_writtenAfter;  // the last frame of the last checkpoint
};
}  // namespace avm::pipeline
