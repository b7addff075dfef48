#include "avm/io/TimingSummary.h"

#include <algorithm>
#include <cstdio>
#include <numeric>

namespace avm::io
{
TimingSummary summariseTimes(std::vector<double> ms)
{
	TimingSummary s;
	s.count = ms.size();
	if (ms.empty()) return s;
	std::sort(ms.begin(), ms.end());
	const auto at = [&](double q) { return ms[static_cast<std::size_t>(q * double(ms.size() - 1) + 0.5)]; };
	s.totalMs = std::accumulate(ms.begin(), ms.end(), 0.0);
	s.meanMs = s.totalMs / double(s.count);
	s.medianMs = at(0.5);
	s.p95Ms = at(0.95);
	s.maxMs = ms.back();
	return s;
}

std::string describeTimes(const TimingSummary& s)
{
	char text[128];
	std::snprintf(
		text, sizeof(text), "mean %.1f median %.1f p95 %.1f max %.1f", s.meanMs, s.medianMs, s.p95Ms, s.maxMs);
	return text;
}
}  // namespace avm::io
