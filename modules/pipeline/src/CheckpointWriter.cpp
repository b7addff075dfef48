#include "avm/pipeline/CheckpointWriter.h"

namespace avm::pipeline
{
bool CheckpointWriter::betweenFrames(RunState& run)
{
	if (m_interval <= 0) return true;
	// Before the first frame of a new run or of a continued session (whose
	// last frame is the earlier session's): a kill at any instant resumes.
	const bool first = !m_written && !run.resumed();
	if (first || (m_sinceLast.Tac() >= m_interval && run.canCheckpoint())) write(run);
	return true;
}

void CheckpointWriter::onFramesEnded(RunState& run)
{
	// Before the detections still due are applied: a resumed run applies them itself.
	const bool holdsLast = m_written && m_writtenAfter == run.lastFrame();
	if (m_interval > 0 && run.canCheckpoint() && !holdsLast) write(run);
}

void CheckpointWriter::write(RunState& run)
{
	run.writeCheckpoint();
	m_sinceLast.Tic();
	m_written = true;
	m_writtenAfter = run.lastFrame();
}
}  // namespace avm::pipeline
