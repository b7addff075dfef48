// A depth image's endpoint records, row by row: each row's keys from the row
// kernels (RowKernels), classified against the regions and the free-only
// boxes, in bands of rows on threads whose records are merged after.
#include "EndpointProjector.h"

#include <algorithm>
#include <cmath>
#include <thread>

#include "RowKernels.h"

namespace avm::detail
{
namespace
{
/** The columns [from, to) of row v that the rectangles cover, clamped to the
 *  image (from >= to: none). */
std::pair<int, int> columnsOnRow(const std::vector<io::PixelRect>& rects, int v, int cols)
{
	int from = cols, to = 0;
	for (const auto& rect : rects)
		if (v >= rect.v0 && v <= rect.v1)
		{
			from = std::min(from, std::max(rect.u0, 0));
			to = std::max(to, std::min(rect.u1, cols - 1) + 1);
		}
	return {from, to};
}
}  // namespace

void EndpointProjector::addDepthImage(const mrpt::obs::CObservation3DRangeScan& obs,
	const mrpt::poses::CPose3D& sensorPose, const io::DepthCamera& camera,
	const std::vector<mrpt::math::TBoundingBox>& freeOnlyBoxes)
{
	const auto& img = obs.rangeImage;
	const int rows = static_cast<int>(img.rows()), cols = static_cast<int>(img.cols());
	const double fx = camera.fx, fy = camera.fy, cx = camera.cx, cy = camera.cy, units = obs.rangeUnits;
	const auto R = sensorPose.getRotationMatrix();

	m_regionRects.clear();
	if (m_hasRegions)
		for (const auto& r : m_regions->boxes) m_regionRects.push_back(io::pixelRectOf(r.box, sensorPose, camera));
	m_freeOnlyBoxes.clear();
	m_freeOnlyRects.clear();
	for (const auto& box : freeOnlyBoxes)
		if (const auto rect = io::pixelRectOf(box, sensorPose, camera); !rect.empty())
		{
			m_freeOnlyBoxes.push_back(box);
			m_freeOnlyRects.push_back(rect);
		}

	// DepthCamera::unproject, factored for the row passes: pixel (u, v) with
	// depth d is d * (1, (cx - u)/fx, (cy - v)/fy) in the sensor frame, so
	// world = t + d * (R0 + a_u R1 + b_v R2).
	m_columnFactor.resize(cols);
	m_columnFactorDouble.resize(cols);
	for (int u = 0; u < cols; u++)
	{
		m_columnFactorDouble[u] = (cx - u) / fx;
		m_columnFactor[u] = static_cast<float>(m_columnFactorDouble[u]);
	}
	// Range (not depth) images: the per-pixel factor from range to depth.
	m_rangeToDepth.clear();
	if (!obs.range_is_depth)
		for (int v = 0; v < rows; v++)
			for (int u = 0; u < cols; u++)
			{
				const double a = (cx - u) / fx, b = (cy - v) / fy;
				m_rangeToDepth.push_back(static_cast<float>(1.0 / std::sqrt(1 + a * a + b * b)));
			}
	RowSetup rs;
	rs.image = &img;
	rs.cols = cols;
	rs.cy = cy;
	rs.fy = fy;
	rs.R = R;
	rs.unitsF = static_cast<float>(units);
	rs.colFactor = m_columnFactor.data();
	rs.rangeToDepth = m_rangeToDepth.empty() ? nullptr : m_rangeToDepth.data();
	rs.regions = m_hasRegions ? &m_regions->boxes : nullptr;
	rs.colFactorDouble = m_columnFactorDouble.data();
	rs.rangeIsDepth = obs.range_is_depth;
	rs.freeOnlyBoxes = &m_freeOnlyBoxes;

	scanBands(rs, rows);
}

/** Scans rows [0, rows) in bands, one per thread: the first band feeds the
 *  scan's endpoint sets directly, the others their own, merged after the join. */
void EndpointProjector::scanBands(const RowSetup& rs, int rows)
{
	m_bands.resize(m_threads);
	for (std::size_t i = 0; i < m_bands.size(); i++)
	{
		auto& band = m_bands[i];
		band.ends = i == 0 ? m_ends : &band.own;
		band.ends->clear(m_sketchBox);
	}
	if (m_bands.size() == 1)
		scanRows(rs, 0, rows, m_bands[0]);
	else
	{
		std::vector<std::thread> helpers;
		const int per = (rows + static_cast<int>(m_bands.size()) - 1) / static_cast<int>(m_bands.size());
		for (std::size_t i = 1; i < m_bands.size(); i++)
			helpers.emplace_back(
				[&, i] {
					scanRows(rs, static_cast<int>(i) * per, std::min(rows, static_cast<int>(i + 1) * per), m_bands[i]);
				});
		scanRows(rs, 0, std::min(rows, per), m_bands[0]);
		for (auto& h : helpers) h.join();
		for (std::size_t i = 1; i < m_bands.size(); i++) m_ends->merge(m_bands[i].own);
	}
}

std::pair<int, int> EndpointProjector::markFreeOnlyPixels(const RowSetup& rs, int v, PixelBand& band) const
{
	using namespace rows;
	// A pixel with depth, in the rectangle of a free-only box in view, whose
	// point lies in one of these boxes: tested in doubles, so that a point on
	// a box's face is in or out as TBoundingBox::containsPoint says.
	const auto [from, to] = columnsOnRow(m_freeOnlyRects, v, rs.cols);
	if (from >= to) return {0, 0};
	const std::uint16_t* const raw = &(*rs.image)(v, 0);
	std::uint8_t* const candidate = band.candidate.data();
	std::uint8_t* const freeOnly = band.freeOnly.data();
	std::fill(candidate + from, candidate + to, 0);
	std::fill(freeOnly + from, freeOnly + to, 0);
	for (const auto& rect : m_freeOnlyRects)
		if (v >= rect.v0 && v <= rect.v1)
			std::transform(raw + rect.u0, raw + rect.u1 + 1, candidate + rect.u0, [](auto r) { return r != 0; });
	const auto& R = rs.R;
	const double b = (rs.cy - v) / rs.fy;
	const RowRaysDouble rays{m_origin.x, m_origin.y, m_origin.z, R(0, 0) + R(0, 2) * b, R(1, 0) + R(1, 2) * b,
		R(2, 0) + R(2, 2) * b, R(0, 1), R(1, 1), R(2, 1), rs.colFactorDouble};
	double* const x = band.points.data();
	double* const y = x + rs.cols;
	double* const z = y + rs.cols;
	rowPointsDouble(rays, raw, rs.unitsF, rs.rangeIsDepth, b, from, to, x, y, z);
	// A point in a box projects into the box's rectangle (the corners'
	// projections with a pixel's margin), so each box is tested only there.
	for (std::size_t i = 0; i < m_freeOnlyBoxes.size(); i++)
	{
		const auto& rect = m_freeOnlyRects[i];
		if (v >= rect.v0 && v <= rect.v1)
			markInBox(x, y, z, m_freeOnlyBoxes[i], candidate, rect.u0, rect.u1 + 1, freeOnly);
	}
	return {from, to};
}

void EndpointProjector::classifyRow(const RowSetup& rs, const rows::RowRays& rays, int v, int from, int to,
	PixelBand& band, rows::RowKeys inside, int* outsideX) const
{
	using namespace rows;
	const std::size_t n = static_cast<std::size_t>(rs.cols);
	const float* const depth = band.near.data();
	float* const inRegion = band.near.data() + n;  // 1: the point lies in a region
	float* const crossTo = inRegion + n;           // >= 0: depth where its ray leaves the farthest region it crosses
	float* const ix = crossTo + n;                 // 1 / the rays' direction, per axis
	float* const iy = ix + n;
	float* const iz = iy + n;
	std::fill(inRegion + from, inRegion + to, 0.0f);
	std::fill(crossTo + from, crossTo + to, -1.0f);
	rowInverseDirections(rays, from, to, ix, iy, iz);
	// Each region only over the columns its box projects to.
	for (std::size_t r = 0; r < rs.regions->size(); r++)
	{
		const auto& rect = m_regionRects[r];
		if (v < rect.v0 || v > rect.v1) continue;
		const int boxFrom = std::max(from, rect.u0), boxTo = std::min(to, rect.u1 + 1);
		if (boxFrom < boxTo)
			classifyAgainstBox(rays, ix, iy, iz, depth, (*rs.regions)[r].box, boxFrom, boxTo, inRegion, crossTo);
	}
	insideRowKeys(rays, depth, inRegion, crossTo, static_cast<float>(m_insideGrid.inverse), from, to, inside, outsideX);
}

void EndpointProjector::scanRows(const RowSetup& rs, int v0, int v1, PixelBand& band) const
{
	using namespace rows;
	const int cols = rs.cols;
	const auto& R = rs.R;
	const float outsideInverse = static_cast<float>(m_outsideGrid.inverse);
	const float sketchInverse = static_cast<float>(m_sketchGrid.inverse);
	const std::size_t n = static_cast<std::size_t>(cols);
	// Two rows of outside, inside and sketch keys: this one and the one above,
	// which starts as "no voxel".
	band.keys.assign(18 * n, -1);
	band.near.resize(6 * n);
	band.flags.assign(n + 8, 0);  // forEachFlagged reads whole words
	band.candidate.resize(n);
	band.freeOnly.resize(n);
	band.points.resize(3 * n);
	auto rowKeys = [&](int row, int set)
	{
		int* const base = band.keys.data() + (static_cast<std::size_t>(row & 1) * 9 + set * 3) * n;
		return RowKeys{base, base + n, base + 2 * n};
	};
	float* const depth = band.near.data();
	std::uint8_t* const flags = band.flags.data();
	EndpointSets& ends = *band.ends;

	for (int v = v0; v < v1; v++)
	{
		const double b = (rs.cy - v) / rs.fy;
		const RowRays rays{static_cast<float>(m_origin.x), static_cast<float>(m_origin.y),
			static_cast<float>(m_origin.z), static_cast<float>(R(0, 0) + R(0, 2) * b),
			static_cast<float>(R(1, 0) + R(1, 2) * b), static_cast<float>(R(2, 0) + R(2, 2) * b),
			static_cast<float>(R(0, 1)), static_cast<float>(R(1, 1)), static_cast<float>(R(2, 1)), rs.colFactor};
		const RowKeys outside = rowKeys(v, 0), outsideAbove = rowKeys(v + 1, 0);
		// Inside keys of near pixels; outside this row's near columns they
		// keep older rows' keys, all in the scan's sets already.
		const RowKeys inside = rowKeys(v, 1), insideAbove = rowKeys(v + 1, 1);
		rowDepth(&(*rs.image)(v, 0), rs.rangeToDepth ? rs.rangeToDepth + static_cast<std::size_t>(v) * n : nullptr,
			rs.unitsF, cols, depth);
		pointRowKeys(rays, depth, outsideInverse, cols, outside);
		// Free-only pixels are keyed as any other, their keys tagged.
		const auto [freeFrom, freeTo] = markFreeOnlyPixels(rs, v, band);
		if (freeFrom < freeTo) tagFreeOnly(band.freeOnly.data(), false, freeFrom, freeTo, outside.x);

		// Columns of this row whose rays can reach a region (empty: none).
		const auto [nearFrom, nearEnd] = columnsOnRow(m_regionRects, v, cols);
		if (nearEnd > nearFrom)
		{
			classifyRow(rs, rays, v, nearFrom, nearEnd, band, inside, outside.x);
			if (std::max(nearFrom, freeFrom) < std::min(nearEnd, freeTo))
				tagFreeOnly(
					band.freeOnly.data(), true, std::max(nearFrom, freeFrom), std::min(nearEnd, freeTo), inside.x);
			flagNewVoxels(inside, insideAbove, nearFrom, nearEnd, flags);
			forEachFlagged(flags, nearFrom, nearEnd,
				[&](int u)
				{
					const int tagged = inside.x[u];
					KeySet& set = hasFreeOnlyTag(tagged) ? ends.freeOnlyInside
														 : (hasInsideTag(tagged) ? ends.inside : ends.crossing);
					if (const auto key = packedOrNone(untagged(tagged), inside.y[u], inside.z[u])) set.insert(key);
				});
			std::fill(flags + nearFrom, flags + nearEnd, 0);
		}

		flagNewVoxels(outside, outsideAbove, 0, cols, flags);
		forEachFlagged(flags, 0, cols,
			[&](int u)
			{
				const int tagged = outside.x[u];
				if (const auto key = packedOrNone(untagged(tagged), outside.y[u], outside.z[u]))
					(hasFreeOnlyTag(tagged) ? ends.freeOnlyOutside : ends.outside).insert(key);
			});
		if (m_hasSketch)
		{
			// The high voxels of the surface points in low-tree space (no
			// surface outside key: no depth, inside a region, or free-only).
			const RowKeys sketch = rowKeys(v, 2), sketchAbove = rowKeys(v + 1, 2);
			pointRowKeys(rays, depth, sketchInverse, cols, sketch);
			maskWhereNoSurface(outside.x, cols, sketch.x);
			flagNewVoxels(sketch, sketchAbove, 0, cols, flags);
			forEachFlagged(flags, 0, cols,
				[&](int u)
				{
					if (const auto key = packedOrNone(sketch.x[u], sketch.y[u], sketch.z[u])) ends.sketch.insert(key);
				});
		}
	}
}
}  // namespace avm::detail
