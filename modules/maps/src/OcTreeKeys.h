// Octree keys as the map's hot paths use them: octomap's depth-16 keys
// (avm/maps/OcTreeKeyLayout.h), packed three into one word, their Morton
// codes, the row passes' tags, and boxes of keys.
#pragma once

#include <mrpt/math/TPoint3D.h>
#include <octomap/OcTreeKey.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "avm/maps/OcTreeKeyLayout.h"

namespace avm::detail
{
/** One axis of a packed key. */
constexpr std::uint64_t kKeyMask = (std::uint64_t(1) << kKeyBits) - 1;
/** What a packed key changes by for one voxel along x, y and z. */
constexpr std::uint64_t kPackedUnit[3] = {std::uint64_t(1) << (2 * kKeyBits), std::uint64_t(1) << kKeyBits, 1};

/** avm::packKey of an octomap key. */
inline std::uint64_t packKey(const octomap::OcTreeKey& k) { return avm::packKey(k[0], k[1], k[2]); }
inline octomap::OcTreeKey unpackKey(std::uint64_t packed)
{
	return octomap::OcTreeKey(static_cast<octomap::key_type>(unpackAxis(packed, 0)),
		static_cast<octomap::key_type>(unpackAxis(packed, 1)), static_cast<octomap::key_type>(unpackAxis(packed, 2)));
}

/** What adding to a packed key moves it by `step` (-1, 0 or 1) voxels along
 *  `axis`: the wrapped negative of a step back subtracts. */
inline std::uint64_t packedStep(int axis, int step) { return step * kPackedUnit[axis]; }

/** octomap's coordToKey, packed; false when the point is outside the tree.
 *  Shifted by the offset first, the value is non-negative inside the tree, so
 *  truncation is the floor. */
inline bool packedKeyOf(double x, double y, double z, double inverseResolution, std::uint64_t& out)
{
	const double fx = x * inverseResolution + kKeyOffset, fy = y * inverseResolution + kKeyOffset,
				 fz = z * inverseResolution + kKeyOffset;
	constexpr double kEnd = kKeyEnd;
	if (!(fx >= 0 && fx < kEnd && fy >= 0 && fy < kEnd && fz >= 0 && fz < kEnd)) return false;
	out = packKey(octomap::OcTreeKey(
		static_cast<octomap::key_type>(fx), static_cast<octomap::key_type>(fy), static_cast<octomap::key_type>(fz)));
	return true;
}

/** @name The row passes' keys
 *  One axis of a key in an int, -1 for "no voxel"; the x key may carry tags
 *  above the key bits, so that a change of category is a change of voxel too.
 *  @{ */
/** On the inside x key of a point that lies in a region (not on a crossing
 *  key: the voxel where a ray leaves a region). */
constexpr int kInsideTag = 1 << kKeyBits;
/** On the x key of a free-only endpoint (outside keys and inside keys of
 *  points in a region; not crossing keys, whose rays end elsewhere). */
constexpr int kFreeOnlyTag = 1 << (kKeyBits + 1);

/** `key` tagged inside where `inside` is 1 (0: as it is); arithmetic, not a
 *  branch, so that the row passes stay vectorized. */
inline int withInsideTag(int key, int inside) { return key + inside * kInsideTag; }
inline int withFreeOnlyTag(int key) { return key + kFreeOnlyTag; }
/** A key, tagged or not (not -1). */
inline bool hasKey(int tagged) { return tagged >= 0; }
/** Tagged free-only: the free-only tag lies above the inside tag. */
inline bool hasFreeOnlyTag(int tagged) { return tagged >= kFreeOnlyTag; }
/** Tagged inside, perhaps free-only too; not a crossing key. Inside keys
 *  only ever get the free-only tag on top of the inside tag. */
inline bool hasInsideTag(int tagged) { return tagged >= kInsideTag; }
/** A key with no tag: a surface endpoint (not -1, not free-only). */
inline bool isUntaggedKey(int tagged) { return static_cast<unsigned>(tagged) <= kKeyMask; }

/** The key part of a tagged x key (-1 stays -1). */
inline int untagged(int tagged) { return tagged < 0 ? -1 : static_cast<int>(tagged & kKeyMask); }

/** packKey() of a row pass's untagged key components, or 0 (no key, as in
 *  the KeySets) where one is -1 ("no voxel") or beyond the tree. */
inline std::uint64_t packedOrNone(int x, int y, int z)
{
	if ((static_cast<unsigned>(x) | static_cast<unsigned>(y) | static_cast<unsigned>(z)) > kKeyMask) return 0;
	return packKey(octomap::OcTreeKey(
		static_cast<octomap::key_type>(x), static_cast<octomap::key_type>(y), static_cast<octomap::key_type>(z)));
}
/** @} */

/** The key of a coordinate that lies on a voxel border (a grid-aligned box's
 *  face), robust to its rounding. */
inline long gridKeyOf(double alignedCoordinate, double resolution)
{
	return std::lround(alignedCoordinate / resolution) + kKeyOffset;
}

/** @name Keys of grids `ratio` times finer and coarser than each other
 *  Both grids put coordinate 0 on a voxel border.
 * @{ */
/** On one axis: the first of the `ratio` finer keys in coarse key `coarse`,
 *  (coarse - offset) * ratio + offset. */
inline unsigned firstFinerKey(unsigned coarse, unsigned ratio)
{
	return (coarse - unsigned(kKeyOffset)) * ratio + unsigned(kKeyOffset);
}

/** On one axis: where fine key `fine` lies among the `ratio` finer keys of
 *  its coarse key, 0 .. ratio - 1: (fine - offset) mod ratio, biased by a
 *  multiple of `ratio` to stay non-negative. */
inline unsigned placeInCoarser(unsigned fine, unsigned ratio)
{
	return (fine + static_cast<unsigned>(kKeyOffset) * (ratio - 1)) % ratio;
}

/** The packed key of the voxel holding `packed` in a grid `ratio` times
 *  coarser. Both grids put coordinate 0 on a voxel border, so on each axis it
 *  is floor((k - offset) / ratio) + offset. */
inline std::uint64_t coarserKeyOf(std::uint64_t packed, unsigned ratio)
{
	const auto k = unpackKey(packed);
	// Biased by a multiple of `ratio` to stay non-negative for the division;
	// a power of two (the usual ratio) shifts instead.
	const unsigned bias = static_cast<unsigned>(kKeyOffset) * (ratio - 1);
	const bool pow2 = (ratio & (ratio - 1)) == 0;
	const unsigned shift = static_cast<unsigned>(__builtin_ctz(ratio));
	auto coarse = [&](unsigned v)
	{ return static_cast<octomap::key_type>(pow2 ? (v + bias) >> shift : (v + bias) / ratio); };
	return packKey(octomap::OcTreeKey(coarse(k[0]), coarse(k[1]), coarse(k[2])));
}
/** @} */

/** @name Morton codes: a key's three axes interleaved bit by bit, so that
 *  sorted codes visit the tree depth first (BatchUpdate)
 * @{ */
constexpr unsigned kMortonBits = 3 * kKeyBits;
static_assert(kKeyBits == 16, "spreadBits3 and compactBits3 interleave 16-bit axes");

/** Spreads the 16 bits of v to every third bit. */
inline std::uint64_t spreadBits3(std::uint64_t v)
{
	v &= kKeyMask;
	v = (v | (v << 16)) & 0x0000FF0000FFull;
	v = (v | (v << 8)) & 0x00F00F00F00Full;
	v = (v | (v << 4)) & 0x0C30C30C30C3ull;
	v = (v | (v << 2)) & 0x249249249249ull;
	return v;
}

/** Inverse of spreadBits3: every third bit, from bit 0, packed into 16 bits. */
inline std::uint64_t compactBits3(std::uint64_t v)
{
	v &= 0x249249249249ull;
	v = (v | (v >> 2)) & 0x0C30C30C30C3ull;
	v = (v | (v >> 4)) & 0x00F00F00F00Full;
	v = (v | (v >> 8)) & 0x0000FF0000FFull;
	v = (v | (v >> 16)) & kKeyMask;
	return v;
}

/** Bits of level b of the three key components form octomap's child index
 *  (k0 -> 1, k1 -> 2, k2 -> 4) in group b, most significant level first. */
inline std::uint64_t mortonOf(const octomap::OcTreeKey& k)
{
	return spreadBits3(k[0]) | (spreadBits3(k[1]) << 1) | (spreadBits3(k[2]) << 2);
}

inline octomap::OcTreeKey keyOfMorton(std::uint64_t morton)
{
	return octomap::OcTreeKey(static_cast<octomap::key_type>(compactBits3(morton)),
		static_cast<octomap::key_type>(compactBits3(morton >> 1)),
		static_cast<octomap::key_type>(compactBits3(morton >> 2)));
}

/** Child index at `depth` (root = 0) of the key with this Morton code. */
inline unsigned childAt(std::uint64_t morton, unsigned depth)
{
	return static_cast<unsigned>((morton >> (3 * (kKeyBits - 1 - depth))) & 7u);
}

/** Deepest depth whose node both keys pass through. */
inline unsigned sharedDepth(std::uint64_t a, std::uint64_t b)
{
	const std::uint64_t x = a ^ b;
	if (x == 0) return kKeyBits;
	const unsigned highest = 63u - static_cast<unsigned>(__builtin_clzll(x));
	return kKeyBits - 1 - highest / 3;
}
/** @} */

/** A box of finest-level keys, half-open: [lo, hi) on each axis. */
struct KeyRange
{
	unsigned lo[3], hi[3];

	octomap::OcTreeKey first() const { return octomap::OcTreeKey(lo[0], lo[1], lo[2]); }
	octomap::OcTreeKey last() const { return octomap::OcTreeKey(hi[0] - 1, hi[1] - 1, hi[2] - 1); }
	bool contains(const octomap::OcTreeKey& k) const
	{
		return k[0] >= lo[0] && k[0] < hi[0] && k[1] >= lo[1] && k[1] < hi[1] && k[2] >= lo[2] && k[2] < hi[2];
	}
	/** The cube of `span` keys per axis starting at `k` lies inside. */
	bool containsCube(const octomap::OcTreeKey& k, unsigned span) const
	{
		for (int i = 0; i < 3; i++)
			if (k[i] < lo[i] || k[i] + span > hi[i]) return false;
		return true;
	}
	bool empty() const { return lo[0] >= hi[0] || lo[1] >= hi[1] || lo[2] >= hi[2]; }
	/** Calls `visit(key)` for every key inside, in x, y, z order. */
	template <typename Visit>
	void forEachKey(Visit&& visit) const
	{
		for (unsigned x = lo[0]; x < hi[0]; x++)
			for (unsigned y = lo[1]; y < hi[1]; y++)
				for (unsigned z = lo[2]; z < hi[2]; z++) visit(octomap::OcTreeKey(x, y, z));
	}
	/** Calls `visit(key)` for every key of the cube of `span` keys per axis
	 *  starting at `k` that lies inside, in x, y, z order: the part of a
	 *  pruned leaf inside the range, without walking the rest of it. */
	template <typename Visit>
	void forEachKeyOfCube(const octomap::OcTreeKey& k, unsigned span, Visit&& visit) const
	{
		KeyRange part;
		for (int i = 0; i < 3; i++)
		{
			part.lo[i] = std::max<unsigned>(k[i], lo[i]);
			part.hi[i] = std::min<unsigned>(k[i] + span, hi[i]);
		}
		if (!part.empty()) part.forEachKey(visit);
	}
	/** The keys of the voxels of a grid (edge 1 / `inverseResolution`) that
	 *  the cube of half edge `reach` around `centre` touches, clamped to the tree. */
	static KeyRange around(const mrpt::math::TPoint3D& centre, double reach, double inverseResolution)
	{
		// In doubles until clamped: a huge cube gives keys beyond an int.
		auto key = [&](double c)
		{
			const double k = std::floor(c * inverseResolution) + kKeyOffset;
			return static_cast<unsigned>(std::clamp(k, 0.0, double(kKeyEnd - 1)));
		};
		KeyRange r{};
		for (int i = 0; i < 3; i++)
		{
			r.lo[i] = key(centre[i] - reach);
			r.hi[i] = key(centre[i] + reach) + 1;
		}
		return r;
	}
	/** The single voxel `k`. */
	static KeyRange of(const octomap::OcTreeKey& k)
	{
		return KeyRange{{k[0], k[1], k[2]}, {k[0] + 1u, k[1] + 1u, k[2] + 1u}};
	}
	/** The keys of a grid `ratio` times finer inside coarse voxel `k`. */
	static KeyRange finerKeysOf(const octomap::OcTreeKey& k, unsigned ratio)
	{
		KeyRange r{};
		for (int i = 0; i < 3; i++)
		{
			r.lo[i] = firstFinerKey(k[i], ratio);
			r.hi[i] = r.lo[i] + ratio;
		}
		return r;
	}
};
}  // namespace avm::detail
