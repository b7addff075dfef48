// Algorithm 1 of Choi & Shin (2025), resolution switching, and the region
// policy that extends it. The paper switches the whole map once; the region
// policy switches only the space around people, so the rest of the scene
// keeps the cheap resolution.
#include "ResolutionPolicy.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace avm::detail
{
namespace
{
bool overlaps(const mrpt::math::TBoundingBox& a, const mrpt::math::TBoundingBox& b)
{
	// Strict: regions aligned to the grid that only share a face stay apart.
	return a.min.x < b.max.x && b.min.x < a.max.x && a.min.y < b.max.y && b.min.y < a.max.y &&
		   a.min.z < b.max.z && b.min.z < a.max.z;
}

/** Grown outwards to whole low voxels, so that a region is a union of low
 *  voxels: each low voxel is then entirely in or out, and the high voxels
 *  (whose edge divides the low one) tile the region exactly. */
mrpt::math::TBoundingBox alignedToGrid(const mrpt::math::TBoundingBox& b, double res)
{
	auto lo = [res](double v) { return std::floor(v / res + 1e-9) * res; };
	auto hi = [res](double v) { return std::ceil(v / res - 1e-9) * res; };
	mrpt::math::TBoundingBox out = b;
	out.min = {lo(b.min.x), lo(b.min.y), lo(b.min.z)};
	out.max = {hi(b.max.x), hi(b.max.y), hi(b.max.z)};
	for (int i = 0; i < 3; i++)
		if (out.max[i] <= out.min[i]) out.max[i] = out.min[i] + res;
	return out;
}
}  // namespace

ResolutionPolicy::ResolutionPolicy(SwitchPolicy policy, double lowResolution)
	: m_policy(policy), m_lowResolution(lowResolution)
{
}

void ResolutionPolicy::markSwitched(std::size_t insertionIndex)
{
	if (!m_switchIndex) m_switchIndex = insertionIndex;
}

void ResolutionPolicy::trigger(std::size_t insertionIndex)
{
	if (m_policy == SwitchPolicy::Region)
		throw std::logic_error(
			"CAdaptiveOctoMap: switchToHighResolution() needs switch_policy = paper; with the region "
			"policy give the space to map finely with addHighResolutionRegion()");
	markSwitched(insertionIndex);
}

void ResolutionPolicy::addRegion(const mrpt::math::TBoundingBox& box, std::size_t insertionIndex)
{
	for (int i = 0; i < 3; i++)
		if (!std::isfinite(box.min[i]) || !std::isfinite(box.max[i]) || box.max[i] <= box.min[i])
			throw std::invalid_argument(
				"CAdaptiveOctoMap::addHighResolutionRegion: empty or non-finite box " + box.asString());
	if (m_policy == SwitchPolicy::Paper)
	{
		markSwitched(insertionIndex);
		return;
	}
	Region merged{alignedToGrid(box, m_lowResolution), insertionIndex};
	// Merge until no region overlaps: a merged box can reach further ones.
	for (bool again = true; again;)
	{
		again = false;
		for (auto it = m_regions.begin(); it != m_regions.end(); ++it)
		{
			if (!overlaps(it->box, merged.box)) continue;
			merged.box = merged.box.unionWith(it->box);
			m_regions.erase(it);
			again = true;
			break;
		}
	}
	m_regions.push_back(merged);
	m_grown.push_back(merged.box);
	markSwitched(insertionIndex);
}

void ResolutionPolicy::beforeIntegration(
	std::size_t index, const CAdaptiveOctoMap::TInsertionOptions& opts, std::size_t expectedFrames)
{
	if (m_policy == SwitchPolicy::Paper && !m_switchIndex)
	{
		if (opts.switchAtFrame >= 0 && index >= static_cast<std::size_t>(opts.switchAtFrame))
			markSwitched(index);
		if (opts.switchAtFraction >= 0)
		{
			if (expectedFrames == 0)
				throw std::runtime_error(
					"CAdaptiveOctoMap: insertOpts switch_at_fraction is set but the run's frame count is "
					"unknown: set insertOpts expected_frame_count or call setExpectedFrameCount()");
			if (static_cast<double>(index) >= opts.switchAtFraction * static_cast<double>(expectedFrames))
				markSwitched(index);
		}
	}
	if (m_policy == SwitchPolicy::Region && opts.regionExpiryFrames > 0)
	{
		auto expired = [&](const Region& r) { return index - r.refreshedAt > opts.regionExpiryFrames; };
		for (const auto& r : m_regions)
			if (expired(r)) m_expired.push_back(r.box);
		m_regions.erase(std::remove_if(m_regions.begin(), m_regions.end(), expired), m_regions.end());
	}
}

bool ResolutionPolicy::highActive() const
{
	return m_policy == SwitchPolicy::Paper ? m_switchIndex.has_value() : !m_regions.empty();
}

const Region* ResolutionPolicy::regionContaining(const mrpt::math::TPoint3D& p) const
{
	for (const auto& r : m_regions)
		if (r.contains(p.x, p.y, p.z)) return &r;
	return nullptr;
}

std::vector<mrpt::math::TBoundingBox> ResolutionPolicy::takeGrownRegions()
{
	return std::exchange(m_grown, {});
}
std::vector<mrpt::math::TBoundingBox> ResolutionPolicy::takeExpiredRegions()
{
	return std::exchange(m_expired, {});
}

void ResolutionPolicy::serializeTo(mrpt::serialization::CArchive& out) const
{
	out.WriteAs<uint8_t>(m_switchIndex.has_value());
	out.WriteAs<uint64_t>(m_switchIndex.value_or(0));
	out.WriteAs<uint32_t>(m_regions.size());
	for (const auto& r : m_regions)
		out << r.box.min.x << r.box.min.y << r.box.min.z << r.box.max.x << r.box.max.y << r.box.max.z
			<< static_cast<uint64_t>(r.refreshedAt);
}

void ResolutionPolicy::serializeFrom(mrpt::serialization::CArchive& in)
{
	const bool switched = in.ReadAs<uint8_t>() != 0;
	const auto index = in.ReadAs<uint64_t>();
	m_switchIndex = switched ? std::optional<std::size_t>(index) : std::nullopt;
	m_regions.resize(in.ReadAs<uint32_t>());
	for (auto& r : m_regions)
	{
		uint64_t refreshed = 0;
		in >> r.box.min.x >> r.box.min.y >> r.box.min.z >> r.box.max.x >> r.box.max.y >> r.box.max.z >>
			refreshed;
		r.refreshedAt = refreshed;
	}
	m_grown.clear();
	m_expired.clear();
}
}  // namespace avm::detail
