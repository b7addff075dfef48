#include "EndpointProjector.h"

#include <cmath>

namespace avm::detail
{
EndpointProjector::PointPlace EndpointProjector::classifyPoint(const mrpt::math::TPoint3D& p) const
{
	for (const auto& r : m_regions->boxes)
		if (r.contains(p.x, p.y, p.z)) return PointPlace::InRegion;
	const mrpt::math::TPoint3D d = p - m_origin;
	for (const auto& r : m_regions->boxes)
	{
		double t0, t1;
		if (clipToBox(m_origin, d, r.box, t0, t1)) return PointPlace::BeyondRegion;
	}
	return PointPlace::Outside;
}

void EndpointProjector::begin(const mrpt::math::TPoint3D& origin, const ScanTargets& targets, EndpointSets& ends)
{
	m_origin = origin;
	m_regions = targets.regions;
	m_outsideGrid.set(targets.outside->getResolution());
	m_hasRegions = targets.regions && !targets.regions->empty() && targets.inside;
	if (m_hasRegions) m_insideGrid.set(targets.inside->getResolution());
	m_hasSketch = targets.sketch != nullptr;
	m_sketchBox = KeyRange::of(octomap::OcTreeKey(0, 0, 0));
	if (m_hasSketch)
	{
		m_sketchGrid.set(targets.sketchResolution);
		const double lowEdge = m_outsideGrid.resolution;
		const double reach = targets.outsideMaxRange + (0.5 * std::sqrt(3.0) + 1) * lowEdge;
		m_sketchBox = KeyRange::around(origin, reach, m_sketchGrid.inverse);
	}
	m_ends = &ends;
	m_ends->clear(m_sketchBox);
	m_lastOutsideKey = m_lastInsideKey = m_lastCrossingKey = 0;
}

inline void EndpointProjector::addPoint(double x, double y, double z)
{
	if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) return;
	std::uint64_t key;
	// Neighbouring points of a cloud mostly fall in the same voxel: a repeat
	// of the last key of a set needs no lookup.
	auto record = [&](KeySet& set, std::uint64_t& last)
	{
		if (key == last) return;
		last = key;
		set.insert(key);
	};
	const auto place = m_hasRegions ? classifyPoint({x, y, z}) : PointPlace::Outside;
	if (place != PointPlace::Outside && packedKeyOf(x, y, z, m_insideGrid.inverse, key))
	{
		if (place == PointPlace::InRegion)
			record(m_ends->inside, m_lastInsideKey);
		else
			record(m_ends->crossing, m_lastCrossingKey);
	}
	if (place == PointPlace::InRegion) return;
	if (m_hasSketch && packedKeyOf(x, y, z, m_sketchGrid.inverse, key)) m_ends->sketch.insert(key);
	if (packedKeyOf(x, y, z, m_outsideGrid.inverse, key)) record(m_ends->outside, m_lastOutsideKey);
}

void EndpointProjector::addWorldPoints(const float* xs, const float* ys, const float* zs, std::size_t n)
{
	for (std::size_t i = 0; i < n; i++) addPoint(xs[i], ys[i], zs[i]);
}

void EndpointProjector::addSensorPoints(
	const float* xs, const float* ys, const float* zs, std::size_t n, const mrpt::poses::CPose3D& sensorPose)
{
	for (std::size_t i = 0; i < n; i++)
	{
		const auto w = sensorPose.composePoint(mrpt::math::TPoint3D(xs[i], ys[i], zs[i]));
		addPoint(w.x, w.y, w.z);
	}
}
}  // namespace avm::detail
