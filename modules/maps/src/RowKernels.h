// The per-row passes of the depth-image keying: small plain loops the
// compiler vectorizes. They are built twice, for AVX2 and for any x86-64, and
// the loader picks one (GCC target_clones); AVX2 without FMA gives the same
// floats, so the same map, on every machine. EndpointProjector::scanRows chains
// them row by row.
#pragma once

#include <mrpt/math/TBoundingBox.h>

#include <cstdint>
#include <cstring>

#include "OcTreeKeys.h"

namespace avm::detail::rows
{
/** The rays of one image row: pixel u at depth d is the point
 *  origin + d * (base + colFactor[u] * slope). */
struct RowRays
{
	float ox, oy, oz;
	float bx, by, bz;
	float sx, sy, sz;
	const float* colFactor;
};

/** The rays of one image row in doubles (the free-only test): pixel u at
 *  depth d is the point origin + d * (base + colFactor[u] * slope). */
struct RowRaysDouble
{
	double ox, oy, oz;
	double bx, by, bz;
	double sx, sy, sz;
	const double* colFactor;
};

/** Voxel keys of one image row, an array per axis; -1 marks "no voxel". */
struct RowKeys
{
	int *x, *y, *z;
};

/** The depth of each pixel of a row (range images: scaled to depth). */
void rowDepth(const std::uint16_t* row, const float* rangeScale, float units, int cols, float* depth);

/** Keys (octomap's floor(coord / res) + kKeyOffset, on floats as octomap) of
 *  the points of a row; -1 where there is no depth or below the tree. */
void pointRowKeys(const RowRays& r, const float* depth, float inverse, int cols, RowKeys out);

/** 1 / each component of the rays' directions, pixels [from, to) (a tiny
 *  offset keeps axis-parallel rays finite): the slab tests' divisions, done
 *  once a row for all the boxes. */
void rowInverseDirections(const RowRays& r, int from, int to, float* ix, float* iy, float* iz);

/** Slab method against one box, in depth units: inside[u] becomes 1 where
 *  the point lies in the box; crossTo[u] the depth where the ray leaves the
 *  box if the point lies beyond it (the farthest such box wins). `ix`, `iy`,
 *  `iz`: the row's rowInverseDirections. */
void classifyAgainstBox(const RowRays& r, const float* ix, const float* iy, const float* iz, const float* depth,
	const mrpt::math::TBoundingBox& box, int from, int to, float* inside, float* crossTo);

/** Inside keys of the classified pixels: of the point where it lies in a
 *  region, else of the voxel where its ray leaves the farthest region it
 *  crosses; -1 in x for neither. The category rides on the x key (above
 *  the tree's keys) so that a change of it is a change of voxel too. A
 *  point inside a region is no outside endpoint: its outside x becomes -1. */
void insideRowKeys(const RowRays& r, const float* depth, const float* inside, const float* crossTo, float inverse,
	int from, int to, RowKeys out, int* outsideX);

/** flags[u] = 1 where the voxel at u may be new to the scan: it differs
 *  from the voxels at u - 1, u - 2 and at u in the row above. Every key
 *  these arrays held before is already in the scan's set (or is -1), so
 *  the others need no lookup. */
void flagNewVoxels(const RowKeys& row, const RowKeys& above, int from, int to, std::uint8_t* flags);

/** The points of pixels [from, to) of a row, in doubles: depth
 *  raw * units (the float product, as rowDepth), for range images
 *  (`rangeIsDepth` false) divided by sqrt(1 + a^2 + b^2), a = colFactor[u]
 *  and b the row's (cy - v) / fy. */
void rowPointsDouble(const RowRaysDouble& r, const std::uint16_t* raw, float units, bool rangeIsDepth, double b,
	int from, int to, double* x, double* y, double* z);

/** inside[u] |= candidate[u] and the point (x, y, z)[u] lies in the box,
 *  bounds included (TBoundingBox::containsPoint), for u in [from, to). */
void markInBox(const double* x, const double* y, const double* z, const mrpt::math::TBoundingBox& box,
	const std::uint8_t* candidate, int from, int to, std::uint8_t* inside);

/** x[u] tagged free-only where freeOnly[u] is set and x[u] is a key (of
 *  any kind, or with `insideKeysOnly` one of a point in a region), u in
 *  [from, to). */
void tagFreeOnly(const std::uint8_t* freeOnly, bool insideKeysOnly, int from, int to, int* x);

/** x[u] = -1 ("no voxel") wherever reference[u] is no surface key: -1, or
 *  tagged free-only. */
void maskWhereNoSurface(const int* reference, int cols, int* x);

/** Calls `visit(u)` for every u in [from, to) whose byte in `flags` is 1.
 *  Most bytes are 0, so whole words are skipped at once; `flags` must be
 *  readable for 7 bytes past `to`. */
template <typename Visit>
inline void forEachFlagged(const std::uint8_t* flags, int from, int to, Visit&& visit)
{
	for (int base = from; base < to; base += 8)
	{
		std::uint64_t word;
		std::memcpy(&word, flags + base, sizeof word);
		while (word != 0)
		{
			const int u = base + __builtin_ctzll(word) / 8;
			word &= word - 1;  // each flag is the lowest bit of its byte
			if (u < to) visit(u);
		}
	}
}
}  // namespace avm::detail::rows
