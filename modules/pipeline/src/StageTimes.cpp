#include "avm/pipeline/StageTimes.h"

#include <sys/resource.h>

#include <algorithm>
#include <fstream>
#include <numeric>
#include <sstream>
#include <string>

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

double processCpuSeconds()
{
	rusage usage{};
	getrusage(RUSAGE_SELF, &usage);
	const auto seconds = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
	return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

StolenCpuTime::StolenCpuTime() : m_start(read()) {}

std::optional<StolenCpuTime::Ticks> StolenCpuTime::read()
{
	// "cpu  user nice system idle iowait irq softirq steal guest guest_nice";
	// guest time is already counted in user.
	std::ifstream in("/proc/stat");
	std::string line;
	if (!std::getline(in, line) || line.rfind("cpu ", 0) != 0) return std::nullopt;
	std::istringstream fields(line.substr(4));
	unsigned long long v[8] = {};
	for (auto& x : v)
		if (!(fields >> x)) return std::nullopt;
	Ticks t;
	t.steal = v[7];
	t.total = std::accumulate(std::begin(v), std::end(v), 0ULL);
	return t;
}

std::optional<double> StolenCpuTime::stolen() const
{
	const auto end = read();
	if (!m_start || !end || end->total <= m_start->total) return std::nullopt;
	return double(end->steal - m_start->steal) / double(end->total - m_start->total);
}
}  // namespace avm::pipeline
