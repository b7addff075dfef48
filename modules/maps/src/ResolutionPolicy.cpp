// Algorithm 1 of Choi & Shin (2025), resolution switching, and the region
// policy that extends it. The paper switches the whole map once; the region
// policy switches only the space around each person, so the rest of the scene
// keeps the cheap resolution.
#include "ResolutionPolicy.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <utility>

#include "OcTreeKeys.h"
#include "avm/io/PointArchive.h"

namespace avm::detail
{
namespace
{
// 2^24 low voxels: a 50 x 50 x 10 m building at 0.2 m is 3.1 million.
constexpr double kMaxRegionVoxels = 16777216.0;

bool contains(const mrpt::math::TBoundingBox& outer, const mrpt::math::TBoundingBox& inner)
{
	for (int i = 0; i < 3; i++)
		if (inner.min[i] < outer.min[i] || inner.max[i] > outer.max[i]) return false;
	return true;
}

/** The bounding box of a and b, when it covers nothing else: equal extents on
 *  two axes, touching or overlapping on the third. */
std::optional<mrpt::math::TBoundingBox> exactUnion(const mrpt::math::TBoundingBox& a, const mrpt::math::TBoundingBox& b)
{
	int differing = -1;
	for (int i = 0; i < 3; i++)
	{
		if (a.min[i] == b.min[i] && a.max[i] == b.max[i]) continue;
		if (differing >= 0) return std::nullopt;
		differing = i;
	}
	if (differing >= 0 && (a.max[differing] < b.min[differing] || b.max[differing] < a.min[differing]))
		return std::nullopt;
	return a.unionWith(b);
}
}  // namespace

ResolutionPolicy::ResolutionPolicy(SwitchPolicy policy, double lowResolution)
	: m_policy(policy), m_lowResolution(lowResolution)
{
}

/** Grown outwards to whole low voxels, so that a region is a union of low
 *  voxels: each low voxel is then entirely in or out, and the high voxels
 *  (whose edge divides the low one) tile the region exactly. */
mrpt::math::TBoundingBox ResolutionPolicy::alignedToGrid(const mrpt::math::TBoundingBox& b) const
{
	const double res = m_lowResolution;
	auto lo = [res](double v) { return std::floor(v / res + 1e-9) * res; };
	auto hi = [res](double v) { return std::ceil(v / res - 1e-9) * res; };
	mrpt::math::TBoundingBox out = b;
	out.min = {lo(b.min.x), lo(b.min.y), lo(b.min.z)};
	out.max = {hi(b.max.x), hi(b.max.y), hi(b.max.z)};
	for (int i = 0; i < 3; i++)
		if (out.max[i] <= out.min[i]) out.max[i] = out.min[i] + res;
	return out;
}

void ResolutionPolicy::requireValid(const mrpt::math::TBoundingBox& box) const
{
	for (int i = 0; i < 3; i++)
		if (!std::isfinite(box.min[i]) || !std::isfinite(box.max[i]) || box.max[i] <= box.min[i])
			throw std::invalid_argument("CAdaptiveOctoMap: empty or non-finite region box " + box.asString());
	// Region space is kept as a set of low voxels: bound it.
	double voxels = 1;
	for (int i = 0; i < 3; i++) voxels *= std::ceil((box.max[i] - box.min[i]) / m_lowResolution) + 1;
	if (voxels > kMaxRegionVoxels)
		throw std::invalid_argument("CAdaptiveOctoMap: region box " + box.asString() + " spans more than " +
									std::to_string(static_cast<long>(kMaxRegionVoxels)) + " low voxels");
}

void ResolutionPolicy::markSwitched(std::size_t insertionIndex)
{
	if (!m_switchIndex) m_switchIndex = insertionIndex;
}

void ResolutionPolicy::switchToHighResolution(std::size_t insertionIndex)
{
	if (m_policy == SwitchPolicy::Region)
		throw std::logic_error(
			"CAdaptiveOctoMap: switchToHighResolution() needs switch_policy = paper; with the region "
			"policy give the space to map finely with addHighResolutionRegion()");
	markSwitched(insertionIndex);
}

void ResolutionPolicy::addFixedRegion(const mrpt::math::TBoundingBox& box, std::size_t insertionIndex)
{
	requireValid(box);
	markSwitched(insertionIndex);
	if (m_policy == SwitchPolicy::Paper) return;
	THighResolutionRegion r;
	r.boxes.push_back(alignedToGrid(box));
	m_regions.push_back(r);
	regionsChanged();
}

void ResolutionPolicy::placeRegion(
	std::uint32_t regionId, const mrpt::math::TBoundingBox& box, RegionLifetime lifetime, std::size_t insertionIndex)
{
	requireValid(box);
	markSwitched(insertionIndex);
	if (m_policy == SwitchPolicy::Paper) return;
	const auto aligned = alignedToGrid(box);
	auto it = std::find_if(
		m_regions.begin(), m_regions.end(), [&](const THighResolutionRegion& r) { return r.regionId == regionId; });
	if (it == m_regions.end())
	{
		m_regions.push_back(THighResolutionRegion{regionId, {}});
		it = std::prev(m_regions.end());
	}
	auto& region = *it;
	if (lifetime == RegionLifetime::Follow)
	{
		if (region.boxes.size() == 1 && contains(region.boxes.front(), aligned) &&
			contains(aligned, region.boxes.front()))
			return;
		region.boxes.assign(1, aligned);
	}
	else
	{
		// Every place the person has been: boxes already covered add nothing,
		// and boxes that extend one another exactly become one, which keeps
		// the integrator's per-box tests few for a person standing still.
		for (const auto& b : region.boxes)
			if (contains(b, aligned)) return;
		auto joined = aligned;
		for (bool merged = true; merged;)
		{
			merged = false;
			for (auto b = region.boxes.begin(); b != region.boxes.end(); ++b)
				if (contains(joined, *b) || exactUnion(joined, *b))
				{
					joined = joined.unionWith(*b);
					region.boxes.erase(b);
					merged = true;
					break;
				}
		}
		region.boxes.push_back(joined);
	}
	regionsChanged();
}

bool ResolutionPolicy::endRegion(std::uint32_t regionId)
{
	const auto it = std::find_if(
		m_regions.begin(), m_regions.end(), [&](const THighResolutionRegion& r) { return r.regionId == regionId; });
	if (regionId == 0 || it == m_regions.end()) return false;
	m_regions.erase(it);
	regionsChanged();
	return true;
}

void ResolutionPolicy::beforeIntegration(
	std::size_t index, std::int64_t switchAtInsertion, double switchAtFraction, std::size_t expectedFrames)
{
	if (m_policy != SwitchPolicy::Paper || m_switchIndex) return;
	if (switchAtInsertion >= 0 && index >= static_cast<std::size_t>(switchAtInsertion)) markSwitched(index);
	if (switchAtFraction >= 0)
	{
		if (expectedFrames == 0)
			throw std::runtime_error(
				"CAdaptiveOctoMap: insertOpts switch_at_fraction is set but the run's frame count is "
				"unknown: set insertOpts expected_frame_count or call setExpectedFrameCount()");
		if (static_cast<double>(index) >= switchAtFraction * static_cast<double>(expectedFrames)) markSwitched(index);
	}
}

bool ResolutionPolicy::hasSwitched() const
{
	return m_policy == SwitchPolicy::Paper ? m_switchIndex.has_value() : !m_regions.empty();
}

bool ResolutionPolicy::inHighResolutionSpace(const mrpt::math::TPoint3D& p) const
{
	for (const auto& b : m_space.boxes)
		if (b.contains(p.x, p.y, p.z)) return true;
	return false;
}

const RegionBoxes& ResolutionPolicy::boxes()
{
	updateCovered();
	return m_space;
}

void ResolutionPolicy::regionsChanged()
{
	m_space.boxes.clear();
	for (const auto& r : m_regions)
		for (const auto& box : r.boxes) m_space.boxes.push_back({box});
	m_coveredStale = true;
	m_treesCaughtUp = false;
}

void ResolutionPolicy::updateCovered()
{
	if (!m_coveredStale) return;
	m_coveredStale = false;
	std::vector<KeyRange> spans;
	constexpr unsigned kEnd = kKeyEnd;
	// Beyond the tree nothing can be mapped: nothing to cover.
	auto key = [this](double v)
	{ return static_cast<unsigned>(std::clamp<long>(gridKeyOf(v, m_lowResolution), 0, kEnd)); };
	KeyRange all{{kEnd, kEnd, kEnd}, {0, 0, 0}};
	for (const auto& b : m_space.boxes)
	{
		KeyRange s;
		for (int i = 0; i < 3; i++)
		{
			s.lo[i] = key(b.box.min[i]);
			s.hi[i] = key(b.box.max[i]);
			all.lo[i] = std::min(all.lo[i], s.lo[i]);
			all.hi[i] = std::max(all.hi[i], s.hi[i]);
		}
		spans.push_back(s);
	}
	auto& covered = m_space.covered;
	if (all.empty())
		covered.reset(octomap::OcTreeKey(0, 0, 0), octomap::OcTreeKey(0, 0, 0));
	else
		covered.reset(all.first(), all.last());
	// The set drops the voxels that overlapping boxes share.
	for (const auto& s : spans) s.forEachKey([&](const octomap::OcTreeKey& k) { covered.insert(packKey(k)); });
}

std::vector<std::uint64_t> ResolutionPolicy::coveredInKeyOrder()
{
	updateCovered();
	const auto& keys = m_space.covered.keys();
	std::vector<std::uint64_t> sorted(keys.begin(), keys.end());
	// One box's voxels come in key order already.
	if (m_space.boxes.size() > 1) std::sort(sorted.begin(), sorted.end());
	return sorted;
}

SpaceChange ResolutionPolicy::takeSpaceChange()
{
	SpaceChange c;
	if (m_treesCaughtUp) return c;
	auto covered = coveredInKeyOrder();
	std::set_difference(covered.begin(), covered.end(), m_coveredApplied.begin(), m_coveredApplied.end(),
		std::back_inserter(c.entered));
	std::set_difference(
		m_coveredApplied.begin(), m_coveredApplied.end(), covered.begin(), covered.end(), std::back_inserter(c.left));
	m_coveredApplied = std::move(covered);
	m_treesCaughtUp = true;
	return c;
}

void ResolutionPolicy::serializeTo(mrpt::serialization::CArchive& out, const RegionRecord& record) const
{
	out.WriteAs<uint8_t>(m_switchIndex.has_value());
	out.WriteAs<uint64_t>(m_switchIndex.value_or(0));
	out.WriteAs<uint32_t>(m_regions.size());
	for (const auto& r : m_regions)
	{
		out << r.regionId;
		if (record) record(out, r.regionId);
		out.WriteAs<uint32_t>(r.boxes.size());
		for (const auto& b : r.boxes) io::writeBox(out, b);
	}
}

void ResolutionPolicy::serializeFrom(mrpt::serialization::CArchive& in, const RegionRecord& record)
{
	const bool switched = in.ReadAs<uint8_t>() != 0;
	const auto index = in.ReadAs<uint64_t>();
	m_switchIndex = switched ? std::optional<std::size_t>(index) : std::nullopt;
	m_regions.resize(in.ReadAs<uint32_t>());
	for (auto& r : m_regions)
	{
		in >> r.regionId;
		if (record) record(in, r.regionId);
		r.boxes.resize(in.ReadAs<uint32_t>());
		for (auto& b : r.boxes)
		{
			io::readBox(in, b);
			requireValid(b);
		}
	}
	regionsChanged();
	// The serialized trees already hold the space as it is.
	m_coveredApplied = coveredInKeyOrder();
	m_treesCaughtUp = true;
}
}  // namespace avm::detail
