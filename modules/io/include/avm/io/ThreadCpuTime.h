// CPU time of the calling thread: unlike wall time it does not count the time
// other threads and processes take on a shared machine, so a stage's work is
// measured the same on a busy 2-core machine as on an idle one.
#pragma once

#include <ctime>

namespace avm::io
{
/** [ms] CPU time the calling thread has used so far. */
inline double threadCpuMs()
{
	timespec ts{};
	::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
	return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}
}  // namespace avm::io
