#include "avm/pipeline/StageTimes.h"

#include <sys/resource.h>

#include <algorithm>
#include <numeric>

namespace avm::pipeline
{
StageSummary StageTimes::summary() const
{
	StageSummary s;
	s.count = m_samples.size();
	if (m_samples.empty()) return s;
	std::vector<double> sorted = m_samples;
	std::sort(sorted.begin(), sorted.end());
	const auto at = [&](double q) { return sorted[static_cast<std::size_t>(q * double(sorted.size() - 1) + 0.5)]; };
	s.totalMs = std::accumulate(sorted.begin(), sorted.end(), 0.0);
	s.meanMs = s.totalMs / double(s.count);
	s.medianMs = at(0.5);
	s.p95Ms = at(0.95);
	s.maxMs = sorted.back();
	return s;
}

double peakMemoryMb()
{
	rusage usage{};
	getrusage(RUSAGE_SELF, &usage);
	return usage.ru_maxrss / 1024.0;  // ru_maxrss is in KiB on Linux
}
}  // namespace avm::pipeline
