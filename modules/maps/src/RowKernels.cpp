#include "RowKernels.h"

#include <algorithm>
#include <cmath>

namespace avm::detail::rows
{
// The row passes below are plain loops the compiler vectorizes; they are
// built twice, for AVX2 and for any x86-64, and the loader picks one. AVX2
// without FMA gives the same floats, so the same map, on every machine.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define AVM_ROW_PASS [[gnu::target_clones("avx2", "default")]]
#else
#define AVM_ROW_PASS
#endif

/** The depth of each pixel of a row (range images: scaled to depth). */
AVM_ROW_PASS void rowDepth(const std::uint16_t* row, const float* rangeScale, float units, int cols, float* depth)
{
	if (rangeScale)
		for (int u = 0; u < cols; u++) depth[u] = row[u] * units * rangeScale[u];
	else
		for (int u = 0; u < cols; u++) depth[u] = row[u] * units;
}

/** Keys (octomap's floor(coord / res) + kKeyOffset, on floats as octomap) of
 *  the points of a row; -1 where there is no depth or below the tree. */
AVM_ROW_PASS void pointRowKeys(const RowRays& r, const float* depth, float inverse, int cols, RowKeys out)
{
	const float offset = kKeyOffset;
	int* const __restrict kx = out.x;
	int* const __restrict ky = out.y;
	int* const __restrict kz = out.z;
	for (int u = 0; u < cols; u++)
	{
		const float a = r.colFactor[u], d = depth[u];
		const float x = (r.ox + d * (r.bx + r.sx * a)) * inverse + offset;
		const float y = (r.oy + d * (r.by + r.sy * a)) * inverse + offset;
		const float z = (r.oz + d * (r.bz + r.sz * a)) * inverse + offset;
		kx[u] = (x < 0) | (d <= 0) ? -1 : static_cast<int>(x);
		ky[u] = y < 0 ? -1 : static_cast<int>(y);
		kz[u] = z < 0 ? -1 : static_cast<int>(z);
	}
}

/** 1 / each component of the rays' directions, pixels [from, to) (a tiny
 *  offset keeps axis-parallel rays finite): the slab tests' divisions, done
 *  once a row for all the boxes. */
AVM_ROW_PASS void rowInverseDirections(const RowRays& r, int from, int to, float* ix, float* iy, float* iz)
{
	for (int u = from; u < to; u++)
	{
		const float a = r.colFactor[u];
		ix[u] = 1.0f / (r.bx + r.sx * a + 1e-12f);
		iy[u] = 1.0f / (r.by + r.sy * a + 1e-12f);
		iz[u] = 1.0f / (r.bz + r.sz * a + 1e-12f);
	}
}

/** Slab method against one box, in depth units: inside[u] becomes 1 where
 *  the point lies in the box; crossTo[u] the depth where the ray leaves the
 *  box if the point lies beyond it (the farthest such box wins). `ix`, `iy`,
 *  `iz`: the row's rowInverseDirections. */
AVM_ROW_PASS void classifyAgainstBox(const RowRays& r, const float* ix, const float* iy, const float* iz,
	const float* depth, const mrpt::math::TBoundingBox& box, int from, int to, float* inside, float* crossTo)
{
	auto relative = [](double bound, float origin) { return static_cast<float>(bound) - origin; };
	const float minx = relative(box.min.x, r.ox), miny = relative(box.min.y, r.oy), minz = relative(box.min.z, r.oz);
	const float maxx = relative(box.max.x, r.ox), maxy = relative(box.max.y, r.oy), maxz = relative(box.max.z, r.oz);
	for (int u = from; u < to; u++)
	{
		const float x0 = minx * ix[u], x1 = maxx * ix[u];
		const float y0 = miny * iy[u], y1 = maxy * iy[u];
		const float z0 = minz * iz[u], z1 = maxz * iz[u];
		const float e = std::max(std::max(std::min(x0, x1), std::min(y0, y1)), std::max(std::min(z0, z1), 0.0f));
		const float x = std::min(std::min(std::max(x0, x1), std::max(y0, y1)), std::max(z0, z1));
		const float d = depth[u];
		const float in = static_cast<float>((e < x) & (d >= e) & (d < x) & (d > 0));
		const float through = static_cast<float>((e < x) & (d >= x));
		inside[u] = std::max(inside[u], in);
		crossTo[u] = std::max(crossTo[u], through * (x + 1) - 1);
	}
}

/** Inside keys of the classified pixels: of the point where it lies in a
 *  region, else of the voxel where its ray leaves the farthest region it
 *  crosses; -1 in x for neither. The category rides on the x key (above
 *  the tree's keys) so that a change of it is a change of voxel too. A
 *  point inside a region is no outside endpoint: its outside x becomes -1. */
AVM_ROW_PASS void insideRowKeys(const RowRays& r, const float* depth, const float* inside, const float* crossTo,
	float inverse, int from, int to, RowKeys out, int* outsideX)
{
	const float offset = kKeyOffset;
	int* const __restrict kx = out.x;
	int* const __restrict ky = out.y;
	int* const __restrict kz = out.z;
	for (int u = from; u < to; u++)
	{
		const float a = r.colFactor[u];
		const float ts = inside[u] * depth[u] + (1 - inside[u]) * crossTo[u] * (1 - 1e-5f);
		const float x = (r.ox + ts * (r.bx + r.sx * a)) * inverse + offset;
		const float y = (r.oy + ts * (r.by + r.sy * a)) * inverse + offset;
		const float z = (r.oz + ts * (r.bz + r.sz * a)) * inverse + offset;
		const bool none = std::max(inside[u], crossTo[u]) <= 0;
		kx[u] = (x < 0) | (x >= static_cast<float>(kKeyEnd)) | none
					? -1
					: withInsideTag(static_cast<int>(x), static_cast<int>(inside[u]));
		ky[u] = y < 0 ? -1 : static_cast<int>(y);
		kz[u] = z < 0 ? -1 : static_cast<int>(z);
	}
	for (int u = from; u < to; u++) outsideX[u] = inside[u] > 0 ? -1 : outsideX[u];
}

/** flags[u] = 1 where the voxel at u may be new to the scan: it differs
 *  from the voxels at u - 1, u - 2 and at u in the row above. Every key
 *  these arrays held before is already in the scan's set (or is -1), so
 *  the others need no lookup: on the Bonn frames one pixel in 80 (outside)
 *  or 30 (inside) is looked up, a quarter of the pixels where the voxel
 *  changes along the row. */
AVM_ROW_PASS void flagNewVoxels(const RowKeys& row, const RowKeys& above, int from, int to, std::uint8_t* flags)
{
	const int* const __restrict x = row.x, * const __restrict y = row.y, * const __restrict z = row.z;
	const int* const __restrict ax = above.x, * const __restrict ay = above.y, * const __restrict az = above.z;
	auto differs = [&](int u, const int* ox, const int* oy, const int* oz, int w)
	{ return (x[u] != ox[w]) | (y[u] != oy[w]) | (z[u] != oz[w]); };
	if (from < to) flags[from] = differs(from, ax, ay, az, from);
	if (from + 1 < to) flags[from + 1] = differs(from + 1, ax, ay, az, from + 1) & differs(from + 1, x, y, z, from);
	for (int u = from + 2; u < to; u++)
		flags[u] = static_cast<std::uint8_t>(
			differs(u, ax, ay, az, u) & differs(u, x, y, z, u - 1) & differs(u, x, y, z, u - 2));
}

/** The points of pixels [from, to) of a row, in doubles: depth
 *  raw * units (the float product, as rowDepth), for range images
 *  (`rangeIsDepth` false) divided by sqrt(1 + a^2 + b^2), a = colFactor[u]
 *  and b the row's (cy - v) / fy. */
AVM_ROW_PASS void rowPointsDouble(const RowRaysDouble& r, const std::uint16_t* raw, float units, bool rangeIsDepth,
	double b, int from, int to, double* x, double* y, double* z)
{
	double* const __restrict px = x;
	double* const __restrict py = y;
	double* const __restrict pz = z;
	for (int u = from; u < to; u++)
	{
		const double a = r.colFactor[u];
		double d = static_cast<double>(raw[u] * units);
		if (!rangeIsDepth) d /= std::sqrt(1 + a * a + b * b);
		px[u] = r.ox + (r.bx + r.sx * a) * d;
		py[u] = r.oy + (r.by + r.sy * a) * d;
		pz[u] = r.oz + (r.bz + r.sz * a) * d;
	}
}

/** inside[u] |= candidate[u] and the point (x, y, z)[u] lies in the box,
 *  bounds included (TBoundingBox::containsPoint), for u in [from, to). */
AVM_ROW_PASS void markInBox(const double* x, const double* y, const double* z, const mrpt::math::TBoundingBox& box,
	const std::uint8_t* candidate, int from, int to, std::uint8_t* inside)
{
	const double minx = box.min.x, miny = box.min.y, minz = box.min.z;
	const double maxx = box.max.x, maxy = box.max.y, maxz = box.max.z;
	for (int u = from; u < to; u++)
	{
		const bool in = (x[u] >= minx) & (y[u] >= miny) & (z[u] >= minz) & (x[u] <= maxx) & (y[u] <= maxy) &
						(z[u] <= maxz) & (candidate[u] != 0);
		inside[u] = static_cast<std::uint8_t>(inside[u] | in);
	}
}

/** x[u] tagged free-only where freeOnly[u] is set and x[u] is a key (of
 *  any kind, or with `insideKeysOnly` one of a point in a region), u in
 *  [from, to). */
AVM_ROW_PASS void tagFreeOnly(const std::uint8_t* freeOnly, bool insideKeysOnly, int from, int to, int* x)
{
	if (insideKeysOnly)
		for (int u = from; u < to; u++) x[u] = (freeOnly[u] != 0) & hasInsideTag(x[u]) ? withFreeOnlyTag(x[u]) : x[u];
	else
		for (int u = from; u < to; u++) x[u] = (freeOnly[u] != 0) & hasKey(x[u]) ? withFreeOnlyTag(x[u]) : x[u];
}

/** x[u] = -1 ("no voxel") wherever reference[u] is no surface key: -1, or
 *  tagged free-only. */
AVM_ROW_PASS void maskWhereNoSurface(const int* reference, int cols, int* x)
{
	for (int u = 0; u < cols; u++) x[u] = isUntaggedKey(reference[u]) ? x[u] : -1;
}
}  // namespace avm::detail::rows
