#include "RayIntegrator.h"

#include <algorithm>
#include <cmath>

namespace avm::detail
{
namespace
{
constexpr int kKeyOffset = 32768;  // octomap's tree_max_val for depth 16

inline int fastFloor(double v)
{
	const int i = static_cast<int>(v);
	return i - (v < i);
}

/** octomap's coordToKey (floor(coord / res) + 32768), packed; false when the
 *  point is outside the tree. */
inline bool packedKeyOf(double x, double y, double z, double inverseRes, std::uint64_t& out)
{
	const int kx = fastFloor(x * inverseRes) + kKeyOffset, ky = fastFloor(y * inverseRes) + kKeyOffset,
			  kz = fastFloor(z * inverseRes) + kKeyOffset;
	if ((static_cast<unsigned>(kx) | static_cast<unsigned>(ky) | static_cast<unsigned>(kz)) > 0xFFFFu)
		return false;
	out = ((std::uint64_t(kx) << 32) | (std::uint64_t(ky) << 16) | std::uint64_t(kz)) + 1;
	return true;
}

inline mrpt::math::TPoint3D centreOf(std::uint64_t packed, double res)
{
	const std::uint64_t v = packed - 1;
	auto c = [res](std::uint64_t k) { return (static_cast<double>(static_cast<int>(k) - kKeyOffset) + 0.5) * res; };
	return {c(v >> 32), c((v >> 16) & 0xFFFF), c(v & 0xFFFF)};
}

/** Parameter interval [t0, t1] within [0, 1] where o + t d lies in the box
 *  (slab method); false if none. */
inline bool clipToBox(
	const mrpt::math::TPoint3D& o, const mrpt::math::TPoint3D& d, const mrpt::math::TBoundingBox& b, double& t0,
	double& t1)
{
	t0 = 0;
	t1 = 1;
	for (int i = 0; i < 3; i++)
	{
		if (std::abs(d[i]) < 1e-12)
		{
			if (o[i] < b.min[i] || o[i] >= b.max[i]) return false;
			continue;
		}
		const double inv = 1.0 / d[i];
		double ta = (b.min[i] - o[i]) * inv, tb = (b.max[i] - o[i]) * inv;
		if (ta > tb) std::swap(ta, tb);
		t0 = std::max(t0, ta);
		t1 = std::min(t1, tb);
		if (t0 >= t1) return false;
	}
	return true;
}
}  // namespace

bool RayIntegrator::insideAnyRegion(double x, double y, double z) const
{
	for (const auto& r : *m_targets.regions)
		if (r.contains(x, y, z)) return true;
	return false;
}

void RayIntegrator::begin(const mrpt::math::TPoint3D& origin, const ScanTargets& targets)
{
	m_targets = targets;
	m_origin = origin;
	m_outsideGrid.set(targets.outside->getResolution());
	m_hasRegions = targets.regions && !targets.regions->empty() && targets.inside;
	if (m_hasRegions) m_insideGrid.set(targets.inside->getResolution());
	for (auto* s : {&m_outsideEnds, &m_insideEnds, &m_crossingEnds, &m_outsideFree, &m_outsideOccupied, &m_insideFree,
			 &m_insideOccupied})
		s->clear();
	m_lastOutsideKey = 0;
}

inline void RayIntegrator::addPoint(double x, double y, double z, bool nearRegion)
{
	if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) return;
	std::uint64_t key;
	if (nearRegion && m_hasRegions)
	{
		if (insideAnyRegion(x, y, z))
		{
			if (packedKeyOf(x, y, z, m_insideGrid.inverse, key)) m_insideEnds.insert(key);
			return;
		}
		const mrpt::math::TPoint3D d(x - m_origin.x, y - m_origin.y, z - m_origin.z);
		for (const auto& r : *m_targets.regions)
		{
			double t0, t1;
			if (!clipToBox(m_origin, d, r.box, t0, t1)) continue;
			if (packedKeyOf(x, y, z, m_insideGrid.inverse, key)) m_crossingEnds.insert(key);
			break;
		}
	}
	if (!packedKeyOf(x, y, z, m_outsideGrid.inverse, key)) return;
	// Neighbouring pixels mostly fall in the same coarse voxel.
	if (key == m_lastOutsideKey) return;
	m_lastOutsideKey = key;
	m_outsideEnds.insert(key);
}

void RayIntegrator::castSegment(bool inside, double a, double b, bool extendStart, bool extendEnd, double length)
{
	const double maxRange = inside ? m_targets.insideMaxRange : m_targets.outsideMaxRange;
	const double maxT = maxRange / length;
	if (b > maxT)
	{
		b = maxT;
		extendEnd = false;
	}
	if (a >= b) return;
	// Segments that meet at a region face overlap by half a voxel so that
	// the voxel on the face is not lost to rounding; applyUpdates() drops
	// what falls on the wrong side.
	const double eps = 0.5 * (inside ? m_insideGrid.resolution : m_outsideGrid.resolution) / length;
	if (extendStart) a = std::max(0.0, a - eps);
	if (extendEnd) b = std::min(1.0, b + eps);
	const mrpt::math::TPoint3D& o = m_origin;
	auto at = [&](double t) {
		return octomap::point3d(
			static_cast<float>(o.x + t * m_rayDir.x), static_cast<float>(o.y + t * m_rayDir.y),
			static_cast<float>(o.z + t * m_rayDir.z));
	};
	auto& tree = inside ? *m_targets.inside : *m_targets.outside;
	auto& freeKeys = inside ? m_insideFree : m_outsideFree;
	if (!tree.computeRayKeys(at(a), at(b), m_ray)) return;
	for (const auto& k : m_ray) freeKeys.insert(packKey(k));
}

void RayIntegrator::castRay(
	const mrpt::math::TPoint3D& end, std::uint64_t endKey, Endpoint endpoint, bool castOutside, bool castInside)
{
	m_rayDir = end - m_origin;
	const double length = m_rayDir.norm();
	if (length <= 0) return;
	m_intervals.clear();
	if (m_hasRegions)
	{
		for (const auto& r : *m_targets.regions)
		{
			double t0, t1;
			if (clipToBox(m_origin, m_rayDir, r.box, t0, t1)) m_intervals.emplace_back(t0, t1);
		}
		std::sort(m_intervals.begin(), m_intervals.end());
	}
	double cursor = 0;
	for (const auto& [t0, t1] : m_intervals)
	{
		if (castOutside && t0 > cursor) castSegment(false, cursor, t0, cursor > 0, true, length);
		if (castInside) castSegment(true, t0, t1, t0 > 0, t1 < 1, length);
		cursor = t1;
	}
	if (castOutside && cursor < 1) castSegment(false, cursor, 1, cursor > 0, false, length);

	if (endpoint == Endpoint::Outside && length <= m_targets.outsideMaxRange) m_outsideOccupied.insert(endKey);
	if (endpoint == Endpoint::Inside && length <= m_targets.insideMaxRange) m_insideOccupied.insert(endKey);
}

void RayIntegrator::applyUpdates(
	octomap::OcTree& tree, const Grid& grid, const KeySet& freeKeys, const KeySet& occupiedKeys,
	bool keepInsideRegions)
{
	// A voxel belongs to exactly one tree: region space to the high tree,
	// the rest to the low tree.
	auto belongs = [&](std::uint64_t k) {
		if (!m_hasRegions) return true;
		const auto c = centreOf(k, grid.resolution);
		return insideAnyRegion(c.x, c.y, c.z) == keepInsideRegions;
	};
	for (const auto k : freeKeys.keys())
		if (!occupiedKeys.contains(k) && belongs(k)) tree.updateNode(unpackKey(k), false);
	for (const auto k : occupiedKeys.keys())
		if (belongs(k)) tree.updateNode(unpackKey(k), true);
}

void RayIntegrator::finish()
{
	for (const auto k : m_outsideEnds.keys())
	{
		const auto c = centreOf(k, m_outsideGrid.resolution);
		if (m_targets.overlapFilter &&
			m_targets.overlapFilter->search(static_cast<double>(c.x), static_cast<double>(c.y), static_cast<double>(c.z)))
			continue;
		castRay(c, k, Endpoint::Outside, true, false);
	}
	if (m_hasRegions)
	{
		for (const auto k : m_insideEnds.keys())
			castRay(centreOf(k, m_insideGrid.resolution), k, Endpoint::Inside, true, true);
		for (const auto k : m_crossingEnds.keys())
			castRay(centreOf(k, m_insideGrid.resolution), k, Endpoint::None, false, true);
	}
	applyUpdates(*m_targets.outside, m_outsideGrid, m_outsideFree, m_outsideOccupied, false);
	if (m_hasRegions) applyUpdates(*m_targets.inside, m_insideGrid, m_insideFree, m_insideOccupied, true);
}

void RayIntegrator::integrateDepthImage(
	const mrpt::obs::CObservation3DRangeScan& obs, const mrpt::poses::CPose3D& sensorPose,
	const ScanTargets& targets)
{
	begin(sensorPose.translation(), targets);
	const auto& img = obs.rangeImage;
	const int rows = static_cast<int>(img.rows()), cols = static_cast<int>(img.cols());
	const auto& K = obs.cameraParams;
	const double fx = K.fx(), fy = K.fy(), cx = K.cx(), cy = K.cy(), units = obs.rangeUnits;
	const auto R = sensorPose.getRotationMatrix();
	const auto& t = m_origin;

	// Pixels whose ray can reach a region: the box's projection (all pixels
	// when a corner is behind the camera).
	m_regionRects.clear();
	if (m_hasRegions)
	{
		for (const auto& r : *targets.regions)
		{
			PixelRect rect{cols, -1, rows, -1};
			bool whole = false;
			for (int corner = 0; corner < 8 && !whole; corner++)
			{
				const mrpt::math::TPoint3D w(
					corner & 1 ? r.box.max.x : r.box.min.x, corner & 2 ? r.box.max.y : r.box.min.y,
					corner & 4 ? r.box.max.z : r.box.min.z);
				const auto s = sensorPose.inverseComposePoint(w);
				if (s.x <= 1e-3)
				{
					whole = true;
					break;
				}
				const double u = cx - fx * s.y / s.x, v = cy - fy * s.z / s.x;
				rect.u0 = std::min(rect.u0, static_cast<int>(std::floor(u)) - 1);
				rect.u1 = std::max(rect.u1, static_cast<int>(std::ceil(u)) + 1);
				rect.v0 = std::min(rect.v0, static_cast<int>(std::floor(v)) - 1);
				rect.v1 = std::max(rect.v1, static_cast<int>(std::ceil(v)) + 1);
			}
			if (whole) rect = PixelRect{0, cols - 1, 0, rows - 1};
			m_regionRects.push_back(rect);
		}
	}

	// Sensor frame: X forward, Y left, Z up; pixel (u, v) with depth d is
	// d * (1, (cx - u)/fx, (cy - v)/fy), so world = t + d * (R0 + a_u R1 + b_v R2).
	m_columnFactor.resize(cols);
	for (int u = 0; u < cols; u++) m_columnFactor[u] = (cx - u) / fx;
	const double r00 = R(0, 0), r10 = R(1, 0), r20 = R(2, 0), r01 = R(0, 1), r11 = R(1, 1), r21 = R(2, 1);
	for (int v = 0; v < rows; v++)
	{
		const double b = (cy - v) / fy;
		const double bx = r00 + R(0, 2) * b, by = r10 + R(1, 2) * b, bz = r20 + R(2, 2) * b;
		bool rowNear = false;
		for (const auto& rect : m_regionRects) rowNear |= (v >= rect.v0 && v <= rect.v1);
		const uint16_t* row = &img(v, 0);
		for (int u = 0; u < cols; u++)
		{
			if (row[u] == 0) continue;
			double d = row[u] * units;
			const double a = m_columnFactor[u];
			if (!obs.range_is_depth) d /= std::sqrt(1 + a * a + b * b);
			const double dx = bx + r01 * a, dy = by + r11 * a, dz = bz + r21 * a;
			bool near = false;
			if (rowNear)
				for (const auto& rect : m_regionRects) near |= (u >= rect.u0 && u <= rect.u1 && v >= rect.v0 && v <= rect.v1);
			addPoint(t.x + d * dx, t.y + d * dy, t.z + d * dz, near);
		}
	}
	finish();
}

void RayIntegrator::integrateWorldPoints(
	const float* xs, const float* ys, const float* zs, std::size_t n, const mrpt::math::TPoint3D& origin,
	const ScanTargets& targets)
{
	begin(origin, targets);
	for (std::size_t i = 0; i < n; i++) addPoint(xs[i], ys[i], zs[i], true);
	finish();
}

void RayIntegrator::integrateSensorPoints(
	const float* xs, const float* ys, const float* zs, std::size_t n, const mrpt::poses::CPose3D& sensorPose,
	const ScanTargets& targets)
{
	begin(sensorPose.translation(), targets);
	for (std::size_t i = 0; i < n; i++)
	{
		const auto w = sensorPose.composePoint(mrpt::math::TPoint3D(xs[i], ys[i], zs[i]));
		addPoint(w.x, w.y, w.z, true);
	}
	finish();
}
}  // namespace avm::detail
