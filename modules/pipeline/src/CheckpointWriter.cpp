#include "avm/pipeline/CheckpointWriter.h"

#include "Checkpoint.h"
#include "avm/io/RunFolder.h"

namespace avm::pipeline
{
namespace fs = std::filesystem;

CheckpointWriter::CheckpointWriter(const fs::path& outDir, double intervalSeconds)
	: m_file(io::RunFolder(outDir).checkpoint()), m_interval(intervalSeconds)
{
}

CheckpointedRun CheckpointWriter::checkpointedRun() const { return detail::readCheckpointedRun(m_file); }

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

void CheckpointWriter::onRunFinished(const FinishedRun& run)
{
	if (!run.summary.interrupted) fs::remove(m_file);
}

void CheckpointWriter::onRunFailed(const RunState& run)
{
	// A resumed run that fails keeps the checkpoint it failed on, for the
	// user to see; a new run's would resume into the same failure.
	if (run.resumed()) return;
	std::error_code ignored;
	fs::remove(m_file, ignored);
}

void CheckpointWriter::write(RunState& run)
{
	run.writeCheckpoint(m_file);
	m_sinceLast.Tic();
	m_written = true;
	m_writtenAfter = run.lastFrame();
}
}  // namespace avm::pipeline
