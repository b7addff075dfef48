// The depth image's row passes: each row's endpoint keys (RowKernels), and
// the surface sketch forgetting what the image saw through. RayIntegrator.cpp joins them into one scan.
#include "RayIntegrator.h"

#include "RowKernels.h"
#include "avm/io/DepthCamera.h"

#include <algorithm>
#include <cmath>

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

void RayIntegrator::forgetSketchSeenThrough(const mrpt::obs::CObservation3DRangeScan& obs,
	const mrpt::poses::CPose3D& sensorPose, const io::DepthCamera& camera)
{
	// A single high-resolution map frees the voxels its rays cross, so a person who walked
	// through leaves nothing there once the wall behind is seen again. The low
	// tree's rays are too coarse to say which high voxels they crossed; the
	// depth image says it for the few the sketch holds: a voxel whose pixel
	// sees a surface more than a voxel beyond it has been seen through. The
	// endpoints of this image are marked after (finish()), so a surface seen
	// again stays.
	const double highEdge = m_sketchGrid.resolution;
	const double lowHalfDiagonal = 0.5 * std::sqrt(3.0) * highEdge * m_targets.sketch->ratio();
	const double maxRange = m_targets.outsideMaxRange;
	const auto& img = obs.rangeImage;
	const auto units = obs.rangeUnits;
	// The image's four side planes, through the sensor, normals inwards: a low
	// voxel wholly outside one of them has no high voxel that projects into
	// the image, and most of the sketch lies there.
	const double W = camera.width, H = camera.height;
	std::array<mrpt::math::TPoint3D, 4> sides{mrpt::math::TPoint3D(camera.cx, -camera.fx, 0),
		mrpt::math::TPoint3D(W - camera.cx, camera.fx, 0), mrpt::math::TPoint3D(camera.cy, 0, -camera.fy),
		mrpt::math::TPoint3D(H - camera.cy, 0, camera.fy)};
	for (auto& n : sides) n *= 1.0 / n.norm();
	const double outsideBy = lowHalfDiagonal + 1e-6;
	const auto outsideTheImage = [&](const mrpt::math::TPoint3D& c)
	{
		return std::any_of(
			sides.begin(), sides.end(), [&](const auto& n) { return n.x * c.x + n.y * c.y + n.z * c.z < -outsideBy; });
	};
	// A high voxel's centre is its low voxel's plus a fixed offset per bit:
	// the offsets turned into the sensor frame once per image.
	const unsigned ratio = m_targets.sketch->ratio();
	const auto& R = sensorPose.getRotationMatrix();
	std::vector<mrpt::math::TPoint3D> offsets(ratio * ratio * ratio);
	for (unsigned bit = 0; bit < offsets.size(); ++bit)
	{
		const unsigned o[3] = {bit / (ratio * ratio), (bit / ratio) % ratio, bit % ratio};
		double w[3];
		for (int i = 0; i < 3; ++i) w[i] = (o[i] + 0.5) * highEdge - 0.5 * highEdge * ratio;
		offsets[bit] = {R(0, 0) * w[0] + R(1, 0) * w[1] + R(2, 0) * w[2],
			R(0, 1) * w[0] + R(1, 1) * w[1] + R(2, 1) * w[2], R(0, 2) * w[0] + R(1, 2) * w[1] + R(2, 2) * w[2]};
	}
	m_targets.sketch->updateBits(
		[&](std::uint64_t lowKey, std::uint64_t bits)
		{
			if (bits == 0) return bits;
			const auto lowCentre = sensorPose.inverseComposePoint(centreOf(lowKey, highEdge * ratio));
			if (lowCentre.x <= -lowHalfDiagonal || lowCentre.norm() > maxRange + lowHalfDiagonal) return bits;
			if (outsideTheImage(lowCentre)) return bits;
			for (std::uint64_t rest = bits; rest != 0; rest &= rest - 1)
			{
				const auto bit = static_cast<unsigned>(__builtin_ctzll(rest));
				const auto p = lowCentre + offsets[bit];
				const double distance = p.norm();
				if (distance > maxRange) continue;
				const auto pixel = camera.project(p);
				if (!pixel) continue;
				const auto u = static_cast<int>(std::lround(pixel->x)), v = static_cast<int>(std::lround(pixel->y));
				if (u >= camera.width || v >= camera.height) continue;
				const std::uint16_t raw = img(v, u);
				if (raw == 0) continue;
				const double measured = raw * units, along = camera.rangeIsDepth ? p.x : distance;
				if (measured > along + highEdge) bits &= ~(std::uint64_t(1) << bit);
			}
			return bits;
		});
}

std::pair<int, int> RayIntegrator::markFreeOnlyPixels(const RowSetup& rs, int v, PixelBand& band) const
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
	for (const auto& box : m_freeOnlyBoxes) markInBox(x, y, z, box, candidate, from, to, freeOnly);
	return {from, to};
}

void RayIntegrator::scanRows(const RowSetup& rs, int v0, int v1, PixelBand& band) const
{
	using namespace rows;
	const int cols = rs.cols;
	const auto& R = rs.R;
	const float outsideInverse = static_cast<float>(m_outsideGrid.inverse);
	const float insideInverse = static_cast<float>(m_insideGrid.inverse);
	const float sketchInverse = static_cast<float>(m_sketchGrid.inverse);
	const std::size_t n = static_cast<std::size_t>(cols);
	// Two rows of outside, inside and sketch keys: this one and the one above,
	// which starts as "no voxel".
	band.keys.assign(18 * n, -1);
	band.near.resize(3 * n);
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
	float* const insideF = depth + n;    // 1: the point lies in a region
	float* const crossTo = insideF + n;  // >= 0: depth where its ray leaves the farthest region it crosses
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
			std::fill(insideF + nearFrom, insideF + nearEnd, 0.0f);
			std::fill(crossTo + nearFrom, crossTo + nearEnd, -1.0f);
			// Each region only over the columns its box projects to.
			for (std::size_t r = 0; r < rs.regions->size(); r++)
			{
				const auto& rect = m_regionRects[r];
				if (v < rect.v0 || v > rect.v1) continue;
				const int from = std::max(nearFrom, rect.u0), to = std::min(nearEnd, rect.u1 + 1);
				if (from < to) classifyAgainstBox(rays, depth, (*rs.regions)[r].box, from, to, insideF, crossTo);
			}
			insideRowKeys(rays, depth, insideF, crossTo, insideInverse, nearFrom, nearEnd, inside, outside.x);
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
		if (m_targets.sketch)
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
