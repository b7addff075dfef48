#include "RayIntegrator.h"

#include "OverlapFilter.h"
#include "avm/io/DepthCamera.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace avm::detail
{
namespace
{
/** octomap's computeRayKeys (same voxels, same order), calling `visit` for
 *  each packed key instead of filling a KeyRay. The key moves by adding to
 *  the packed word, and the axis of each step is chosen without branches:
 *  which axis comes next is a coin toss on most rays. */
template <typename Visit>
bool forEachRayKey(
	const octomap::OcTree& tree, const octomap::point3d& origin, const octomap::point3d& end, Visit&& visit)
{
	octomap::OcTreeKey first, last;
	if (!tree.coordToKeyChecked(origin, first) || !tree.coordToKeyChecked(end, last)) return false;
	if (first == last) return true;
	std::uint64_t current = packKey(first);
	const std::uint64_t stop = packKey(last);
	visit(current);
	octomap::point3d direction = end - origin;
	const float length = static_cast<float>(direction.norm());
	direction /= length;
	const double res = tree.getResolution();
	std::uint64_t move[3];
	double tMax[3], tDelta[3];
	for (unsigned i = 0; i < 3; ++i)
	{
		const int step = direction(i) > 0.0 ? 1 : (direction(i) < 0.0 ? -1 : 0);
		move[i] = packedStep(static_cast<int>(i), step);
		if (step != 0)
		{
			double border = tree.keyToCoord(first[i]);
			border += static_cast<float>(step * res * 0.5);
			tMax[i] = (border - origin(i)) / direction(i);
			tDelta[i] = res / std::fabs(direction(i));
		}
		else
			tMax[i] = tDelta[i] = std::numeric_limits<double>::max();
	}
	// In scalars, not the arrays: the loop's state then stays in registers
	// instead of going through memory at every step.
	double tx = tMax[0], ty = tMax[1], tz = tMax[2];
	const double dx = tDelta[0], dy = tDelta[1], dz = tDelta[2];
	const std::uint64_t mx = move[0], my = move[1], mz = move[2];
	for (;;)
	{
		// octomap's choice, ties included: x if before y and z, else y if
		// before z, else z.
		const bool xFirst = tx < ty;
		const bool zStep = !((xFirst ? tx : ty) < tz);
		const bool xStep = xFirst && !zStep, yStep = !xFirst && !zStep;
		current += xStep ? mx : (yStep ? my : mz);
		tx = xStep ? tx + dx : tx;
		ty = yStep ? ty + dy : ty;
		tz = zStep ? tz + dz : tz;
		if (current == stop) return true;
		if (std::min(std::min(tx, ty), tz) > length) return true;
		visit(current);
	}
}
}  // namespace

void RayIntegrator::begin(const mrpt::math::TPoint3D& origin, const ScanTargets& targets)
{
	m_targets = targets;
	m_origin = origin;
	m_outsideGrid.set(targets.outside->getResolution());
	m_hasRegions = targets.regions && !targets.regions->empty() && targets.inside;
	if (m_hasRegions) m_insideGrid.set(targets.inside->getResolution());
	if (targets.sketch) m_sketchGrid.set(targets.sketchResolution);
	m_projector.begin(origin, targets, m_ends);
	// Every key a ray maps outside the regions lies within the tree's max
	// range of the origin (castSegment clips there; half a voxel farther
	// where a segment meets a region face, one voxel where the traversal's
	// rounding steps past a segment's end): a dense box of them, three
	// voxels wider than that range.
	const double reach = targets.outsideMaxRange + 3 * m_outsideGrid.resolution;
	const auto inReach = KeyRange::around(origin, reach, m_outsideGrid.inverse);
	m_outsideFree.reset(inReach.first(), inReach.last());
	m_outsideOccupied.reset(inReach.first(), inReach.last());
	if (m_hasRegions)
	{
		// Inside keys only matter inside the regions: a dense box of them.
		mrpt::math::TBoundingBox all = targets.regions->boxes.front().box;
		for (const auto& r : targets.regions->boxes) all = all.unionWith(r.box);
		const auto lo = targets.inside->coordToKey(all.min.x, all.min.y, all.min.z);
		const auto hi = targets.inside->coordToKey(all.max.x, all.max.y, all.max.z);
		m_insideFree.reset(lo, hi);
		m_insideOccupied.reset(lo, hi);
	}
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
	auto at = [&](double t)
	{
		return octomap::point3d(static_cast<float>(o.x + t * m_rayDir.x), static_cast<float>(o.y + t * m_rayDir.y),
			static_cast<float>(o.z + t * m_rayDir.z));
	};
	auto& tree = inside ? *m_targets.inside : *m_targets.outside;
	if (inside)
		forEachRayKey(tree, at(a), at(b), [this](std::uint64_t k) { m_insideFree.insert(k); });
	else
		forEachRayKey(tree, at(a), at(b), [this](std::uint64_t k) { m_outsideFree.insert(k); });
}

void RayIntegrator::castRay(const mrpt::math::TPoint3D& end, std::uint64_t endKey, Endpoint endpoint, RayPart part)
{
	const bool castOutside = part == RayPart::OutsideRegions, castInside = part == RayPart::InsideRegions;
	m_rayDir = end - m_origin;
	const double length = m_rayDir.norm();
	if (length <= 0) return;
	m_intervals.clear();
	if (m_hasRegions)
	{
		for (const auto& r : m_targets.regions->boxes)
		{
			double t0, t1;
			if (clipToBox(m_origin, m_rayDir, r.box, t0, t1)) m_intervals.emplace_back(t0, t1);
		}
		std::sort(m_intervals.begin(), m_intervals.end());
		// Regions may overlap: walk their union.
		std::size_t kept = 0;
		for (std::size_t i = 1; i < m_intervals.size(); i++)
		{
			if (m_intervals[i].first <= m_intervals[kept].second)
				m_intervals[kept].second = std::max(m_intervals[kept].second, m_intervals[i].second);
			else
				m_intervals[++kept] = m_intervals[i];
		}
		if (!m_intervals.empty()) m_intervals.resize(kept + 1);
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

void RayIntegrator::applyUpdates(octomap::OcTree& tree, const KeyGrid& grid, const BoxKeySet& freeKeys,
	BoxKeySet& occupiedKeys, const KeySet& freeOnlyEnds, bool keepInsideRegions)
{
	// A voxel belongs to exactly one tree: region space to the high tree,
	// the rest to the low tree.
	const unsigned ratio =
		m_hasRegions ? static_cast<unsigned>(std::lround(m_outsideGrid.resolution / grid.resolution)) : 1;
	auto belongs = [&](std::uint64_t packed)
	{ return !m_hasRegions || m_targets.regions->covers(packed, ratio) == keepInsideRegions; };
	m_batch.clear();
	// A free-only endpoint voxel is not freed by the scan's other rays
	// either, as octomap's computeUpdate keeps every endpoint voxel of a scan
	// out of its free set: something is there (a person passing, perhaps in
	// front of a surface in the same voxel), and a ray grazing past it does
	// not show it empty. The free-only endpoints join the occupied ones after
	// them, so one lookup keeps both out of the free set, and only the first
	// (keys() keeps the order of insertion) are marked occupied.
	const std::size_t occupiedCount = occupiedKeys.keys().size();
	for (const auto k : freeOnlyEnds.keys()) occupiedKeys.insert(k);
	for (const auto k : freeKeys.keys())
		if (!occupiedKeys.contains(k) && belongs(k)) m_batch.add(k, false);
	const auto& occupied = occupiedKeys.keys();
	for (std::size_t i = 0; i < occupiedCount; i++)
		if (belongs(occupied[i])) m_batch.add(occupied[i], true);
	m_batch.applyTo(tree);
}

void RayIntegrator::finish()
{
	for (const auto* ends : {&m_ends.outside, &m_ends.freeOnlyOutside})
	{
		const bool surface = ends == &m_ends.outside;
		for (const auto k : ends->keys())
		{
			if (!surface && m_ends.outside.contains(k)) continue;
			const auto c = centreOf(k, m_outsideGrid.resolution);
			if (m_targets.overlapFilter && !overlapFilterAdmits(*m_targets.overlapFilter, c)) continue;
			castRay(c, k, surface ? Endpoint::Outside : Endpoint::None, RayPart::OutsideRegions);
		}
	}
	if (m_hasRegions)
	{
		// Outside the regions a ray maps voxels of the outside grid, so, as in
		// an OctoMap at that resolution, one ray per outside endpoint voxel
		// carries that part, not one per inside endpoint.
		m_insideEndsOutsideGrid.clear();
		for (const auto* ends : {&m_ends.inside, &m_ends.freeOnlyInside})
		{
			const bool surface = ends == &m_ends.inside;
			for (const auto k : ends->keys())
			{
				if (!surface && m_ends.inside.contains(k)) continue;
				const auto c = centreOf(k, m_insideGrid.resolution);
				castRay(c, k, surface ? Endpoint::Inside : Endpoint::None, RayPart::InsideRegions);
				std::uint64_t outsideKey;
				if (packedKeyOf(c.x, c.y, c.z, m_outsideGrid.inverse, outsideKey))
					m_insideEndsOutsideGrid.insert(outsideKey);
			}
		}
		for (const auto k : m_insideEndsOutsideGrid.keys())
			castRay(centreOf(k, m_outsideGrid.resolution), k, Endpoint::None, RayPart::OutsideRegions);
		for (const auto k : m_ends.crossing.keys())
		{
			// Through the crossing voxel (a depth row's: where the ray leaves
			// the region; a cloud's: the point's own, EndpointProjector.h says
			// why) and one inside voxel beyond its centre.
			const auto c = centreOf(k, m_insideGrid.resolution);
			const auto dir = c - m_origin;
			const double n = dir.norm();
			if (n > 0) castRay(c + dir * (m_insideGrid.resolution / n), k, Endpoint::None, RayPart::InsideRegions);
		}
	}
	if (m_targets.sketch)
	{
		m_sketchSurface.clear();
		m_sketchSeen.clear();
		for (const auto k : m_ends.sketch.keys())
		{
			// The low tree takes an endpoint within range by its low voxel's
			// centre, the sketch by the high voxel's: a low voxel hit at the
			// edge of the range may hold no surface within it, and is then
			// known to the sketch without bits, so that it does not enter a
			// region as a solid block.
			const auto lowKey = m_targets.sketch->lowKeyOf(k);
			if ((centreOf(k, m_sketchGrid.resolution) - m_origin).norm() <= m_targets.outsideMaxRange)
				m_sketchSurface.push_back(k);
			else if ((centreOf(lowKey, m_outsideGrid.resolution) - m_origin).norm() <= m_targets.outsideMaxRange)
				m_sketchSeen.push_back(lowKey);
		}
		m_targets.sketch->markScan(m_sketchSurface, m_sketchSeen);
	}
	applyUpdates(*m_targets.outside, m_outsideGrid, m_outsideFree, m_outsideOccupied, m_ends.freeOnlyOutside, false);
	if (m_hasRegions)
		applyUpdates(*m_targets.inside, m_insideGrid, m_insideFree, m_insideOccupied, m_ends.freeOnlyInside, true);
}

void RayIntegrator::integrateDepthImage(const mrpt::obs::CObservation3DRangeScan& obs,
	const mrpt::poses::CPose3D& sensorPose, const ScanTargets& targets,
	const std::vector<mrpt::math::TBoundingBox>& freeOnlyBoxes)
{
	begin(sensorPose.translation(), targets);
	const auto camera = io::DepthCamera::of(obs);
	m_projector.addDepthImage(obs, sensorPose, camera, freeOnlyBoxes);
	if (m_targets.sketch) forgetSketchSeenThrough(obs, sensorPose, camera);
	finish();
}

void RayIntegrator::integrateWorldPoints(const float* xs, const float* ys, const float* zs, std::size_t n,
	const mrpt::math::TPoint3D& origin, const ScanTargets& targets)
{
	begin(origin, targets);
	m_projector.addWorldPoints(xs, ys, zs, n);
	finish();
}

void RayIntegrator::integrateSensorPoints(const float* xs, const float* ys, const float* zs, std::size_t n,
	const mrpt::poses::CPose3D& sensorPose, const ScanTargets& targets)
{
	begin(sensorPose.translation(), targets);
	m_projector.addSensorPoints(xs, ys, zs, n, sensorPose);
	finish();
}
}  // namespace avm::detail
