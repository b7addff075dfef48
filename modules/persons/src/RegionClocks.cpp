#include "avm/persons/RegionClocks.h"

#include <algorithm>

namespace avm::persons
{
void RegionClocks::seen(std::uint32_t personId, double time, bool newRegion)
{
	auto& clock = m_clocks[personId];
	if (newRegion) clock = Clock{0, time};
	clock.unseenInViewSeconds = 0;
	clock.lastSeenTime = std::max(clock.lastSeenTime, time);
}

std::vector<std::uint32_t> RegionClocks::age(double time, bool follow, const std::vector<RegionInView>& regions,
	double endAfter, const std::function<bool(const mrpt::math::TBoundingBox&)>& inView)
{
	// A gap in the stream (a paused recording) is not time spent looking.
	constexpr double kMaxStep = 1.0;  // [s]
	const double from = m_lastImageTime ? std::max(*m_lastImageTime, time - kMaxStep) : time;
	m_lastImageTime = time;
	std::vector<std::uint32_t> ended;
	if (!follow || time <= from) return ended;
	for (const auto& r : regions)
	{
		if (!inView(r.box)) continue;
		auto& clock = m_clocks[r.personId];
		clock.unseenInViewSeconds += std::max(0.0, time - std::max(from, clock.lastSeenTime));
		if (clock.unseenInViewSeconds >= endAfter) ended.push_back(r.personId);
	}
	for (const auto id : ended) m_clocks.erase(id);
	return ended;
}

double RegionClocks::unseenInViewSeconds(std::uint32_t personId) const
{
	const auto it = m_clocks.find(personId);
	return it == m_clocks.end() ? 0.0 : it->second.unseenInViewSeconds;
}

void RegionClocks::writeClock(mrpt::serialization::CArchive& out, std::uint32_t personId) const
{
	const auto it = m_clocks.find(personId);
	const Clock clock = it == m_clocks.end() ? Clock{} : it->second;
	out << clock.unseenInViewSeconds << clock.lastSeenTime;
}

void RegionClocks::readClock(mrpt::serialization::CArchive& in, std::uint32_t personId)
{
	Clock clock;
	in >> clock.unseenInViewSeconds >> clock.lastSeenTime;
	m_clocks[personId] = clock;
}

void RegionClocks::writeImageTime(mrpt::serialization::CArchive& out) const
{
	out.WriteAs<uint8_t>(m_lastImageTime.has_value());
	out << m_lastImageTime.value_or(0.0);
}

void RegionClocks::readImageTime(mrpt::serialization::CArchive& in)
{
	const bool known = in.ReadAs<uint8_t>() != 0;
	double time = 0;
	in >> time;
	m_lastImageTime = known ? std::optional<double>(time) : std::nullopt;
}
}  // namespace avm::persons
