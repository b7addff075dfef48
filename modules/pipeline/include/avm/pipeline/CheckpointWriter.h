// avm-map's checkpoints as an observer of the run (avm/pipeline/FrameObserver.h):
// one before the first frame (not in a resumed run: its checkpoint is there),
// one every `interval_s` of run time between two frames, and one after the
// last frame, unless the last one already holds it. What a checkpoint holds:
// src/Checkpoint.h; what resumes from it: MappingPipeline::resume.
#pragma once

#include <mrpt/system/CTicTac.h>

#include <optional>

#include "avm/pipeline/FrameObserver.h"

namespace avm::pipeline
{
class CheckpointWriter : public FrameObserver
{
   public:
	/** [pipeline] checkpoint_interval_s; 0 writes none. */
	explicit CheckpointWriter(double intervalSeconds) : m_interval(intervalSeconds) {}

	bool betweenFrames(RunState& run) override;
	void onFramesEnded(RunState& run) override;

   private:
	void write(RunState& run);

	double m_interval;
	mrpt::system::CTicTac m_sinceLast;
	bool m_written = false;
	std::optional<std::size_t> m_writtenAfter;  // the last frame of the last checkpoint
};
}  // namespace avm::pipeline
