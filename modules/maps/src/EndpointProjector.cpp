#include "EndpointProjector.h"

#include <cmath>

namespace avm::detail
{
bool EndpointProjector::insideAnyRegion(double x, double y, double z) const
{
	for (const auto& r : m_regions->boxes)
		if (r.contains(x, y, z)) return true;
	return false;
}

void EndpointProjector::begin(const mrpt::math::TPoint3D& origin, const ScanTargets& targets, EndpointSets& ends)
{
	m_origin = origin;
	m_regions = targets.regions;
	m_outsideGrid.set(targets.outside->getResolution());
	m_hasRegions = targets.regions && !targets.regions->empty() && targets.inside;
	if (m_hasRegions) m_insideGrid.set(targets.inside->getResolution());
	m_hasSketch = targets.sketch != nullptr;
	if (m_hasSketch) m_sketchGrid.set(targets.sketchResolution);
	m_ends = &ends;
	m_ends->clear();
	m_lastOutsideKey = m_lastInsideKey = m_lastCrossingKey = 0;
}

inline void EndpointProjector::addPoint(double x, double y, double z)
{
	if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) return;
	std::uint64_t key;
	if (m_hasRegions)
	{
		if (insideAnyRegion(x, y, z))
		{
			if (packedKeyOf(x, y, z, m_insideGrid.inverse, key) && key != m_lastInsideKey)
			{
				m_lastInsideKey = key;
				m_ends->inside.insert(key);
			}
			return;
		}
		const mrpt::math::TPoint3D d(x - m_origin.x, y - m_origin.y, z - m_origin.z);
		for (const auto& r : m_regions->boxes)
		{
			double t0, t1;
			if (!clipToBox(m_origin, d, r.box, t0, t1)) continue;
			if (packedKeyOf(x, y, z, m_insideGrid.inverse, key) && key != m_lastCrossingKey)
			{
				m_lastCrossingKey = key;
				m_ends->crossing.insert(key);
			}
			break;
		}
	}
	if (m_hasSketch && packedKeyOf(x, y, z, m_sketchGrid.inverse, key)) m_ends->sketch.insert(key);
	if (!packedKeyOf(x, y, z, m_outsideGrid.inverse, key)) return;
	// Neighbouring points mostly fall in the same outside voxel.
	if (key == m_lastOutsideKey) return;
	m_lastOutsideKey = key;
	m_ends->outside.insert(key);
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
