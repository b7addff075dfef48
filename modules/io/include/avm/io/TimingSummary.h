// Durations of one piece of work, one sample at a time (a frame's stage, a
// detector call), summarised as count, mean, median, 95th percentile, max and
// total: the one summary every avm program and stats.json print (MRPT's
// CTimeLogger keeps no percentiles). Percentiles by one rule: the sorted
// sample at rank q * (n - 1), rounded to the nearest.
#pragma once

#include <cstddef>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

namespace avm::io
{
struct TimingSummary
{
	std::size_t count = 0;
	double meanMs = 0, medianMs = 0, p95Ms = 0, maxMs = 0, totalMs = 0;  //!< [ms], all 0 without samples
};

/** The summary of durations [ms]. */
TimingSummary summariseTimes(std::vector<double> milliseconds);

/** "mean 12.3 median 11.0 p95 20.1 max 31.4" [ms, one decimal]: how every
 *  program's console line shows a summary. */
std::string describeTimes(const TimingSummary& s);

/** Durations [ms] collected one at a time. */
class TimingSamples
{
   public:
	TimingSamples() = default;
	/** Samples collected before (a run resumed from its checkpoint). */
	explicit TimingSamples(std::vector<double> milliseconds) : m_samples(std::move(milliseconds)) {}

	void add(double milliseconds) { m_samples.push_back(milliseconds); }
	/** Sorts a copy of the samples: for the end of a run. */
	TimingSummary summary() const { return summariseTimes(m_samples); }
	/** [ms] The mean so far without sorting anything: for a live display. */
	double meanMs() const
	{
		const double totalMs = std::accumulate(m_samples.begin(), m_samples.end(), 0.0);
		return m_samples.empty() ? 0.0 : totalMs / double(m_samples.size());
	}
	const std::vector<double>& samples() const { return m_samples; }

   private:
	std::vector<double> m_samples;
};
}  // namespace avm::io
