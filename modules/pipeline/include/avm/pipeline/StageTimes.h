// What a run measures about itself: wall-clock durations of one pipeline
// stage, frame by frame, summarised as mean / median / 95th percentile
// (CTimeLogger keeps no percentiles), and the process's peak memory.
#pragma once

#include <cstddef>
#include <vector>

namespace avm::pipeline
{
struct StageSummary
{
	std::size_t count = 0;
	double meanMs = 0, medianMs = 0, p95Ms = 0, maxMs = 0, totalMs = 0;
};

class StageTimes
{
   public:
	void add(double milliseconds) { m_samples.push_back(milliseconds); }
	StageSummary summary() const;

   private:
	std::vector<double> m_samples;
};

/** [MiB] Peak resident memory of this process so far. */
double peakMemoryMb();
}  // namespace avm::pipeline
