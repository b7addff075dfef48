// What the process used, besides its stages' durations (io::TimingSamples):
// its peak memory and CPU time, and how much of the machine a hypervisor took
// meanwhile.
#pragma once

#include <optional>

namespace avm::pipeline
{
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
