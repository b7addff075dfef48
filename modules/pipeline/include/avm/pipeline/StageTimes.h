// What a run measures about itself: wall-clock durations of one pipeline
// stage, frame by frame, summarised as mean / median / 95th percentile
// (CTimeLogger keeps no percentiles), the process's peak memory and CPU time,
// and how much of the machine a hypervisor took meanwhile.
#pragma once

#include <cstddef>
#include <optional>
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

/** [s] CPU time (user + system, all threads) this process has used so far. */
double processCpuSeconds();

/** The share of the machine's CPU time, from construction to stolen(), that a
 *  hypervisor gave to other guests (Linux /proc/stat "steal"). Wall-clock
 *  speeds of runs on a virtual machine only compare at similar steal. */
class StolenCpuTime
{
   public:
	StolenCpuTime();
	/** [0..1], or nothing where /proc/stat is not readable. */
	std::optional<double> stolen() const;

   private:
	struct Ticks
	{
		unsigned long long steal = 0, total = 0;
	};
	static std::optional<Ticks> read();
	std::optional<Ticks> m_start;
};
}  // namespace avm::pipeline
