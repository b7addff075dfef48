#include "ProcessUsage.h"

#include <sys/resource.h>

#include <fstream>
#include <numeric>
#include <sstream>
#include <string>

namespace avm::pipeline
{
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
