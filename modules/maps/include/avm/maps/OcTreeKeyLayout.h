// The octree key layout the map's two trees share with octomap: depth-16
// trees whose key on each axis is floor(coordinate / resolution) + kKeyOffset.
// The one place that says so: the map's hot paths build their packed keys,
// tags and Morton codes on it (src/OcTreeKeys.h), the person layer snaps its
// shapes to the trees' voxels and sorts them by packed key with it, and the
// reference maps split pruned leaves with it. No octomap types here, so it
// costs its users nothing.
#pragma once

#include <mrpt/math/TPoint3D.h>

#include <cmath>
#include <cstdint>

namespace avm
{
/** Bits of one axis of a key: octomap's tree depth, 16. */
constexpr unsigned kKeyBits = 16;
/** octomap's key of coordinate 0 (tree_max_val). */
constexpr int kKeyOffset = 1 << (kKeyBits - 1);
/** Keys per axis: a key lies in [0, kKeyEnd). */
constexpr int kKeyEnd = 2 * kKeyOffset;

/** octomap's coordToKey on one axis, unchecked: a coordinate beyond the
 *  tree's half extent gives a key outside [0, kKeyEnd). */
inline int keyOf(double coordinate, double inverseResolution)
{
	return static_cast<int>(std::floor(coordinate * inverseResolution)) + kKeyOffset;
}

/** The key lies in the tree: [0, kKeyEnd). */
constexpr bool keyInTree(int key) { return key >= 0 && key < kKeyEnd; }

/** Three keys of the tree (keyInTree) in one word, x in the highest bits,
 *  then y, then z, so that packed keys sort as (x, y, z) triples do; plus
 *  one, so that 0 can mark "no key". */
constexpr std::uint64_t packKey(unsigned x, unsigned y, unsigned z)
{
	return ((std::uint64_t(x) << (2 * kKeyBits)) | (std::uint64_t(y) << kKeyBits) | std::uint64_t(z)) + 1;
}
/** Axis `axis` (0 x, 1 y, 2 z) of a packed key. */
constexpr unsigned unpackAxis(std::uint64_t packed, int axis)
{
	return static_cast<unsigned>(((packed - 1) >> ((2 - axis) * kKeyBits)) & ((std::uint64_t(1) << kKeyBits) - 1));
}

/** The centre of key `key`'s voxel on one axis [m]. */
inline double keyCentre(int key, double resolution)
{
	return (static_cast<double>(key - kKeyOffset) + 0.5) * resolution;
}

/** The centre of the voxel of a packed key (packKey) [m]. */
inline mrpt::math::TPoint3D centreOf(std::uint64_t packed, double resolution)
{
	return {keyCentre(int(unpackAxis(packed, 0)), resolution), keyCentre(int(unpackAxis(packed, 1)), resolution),
		keyCentre(int(unpackAxis(packed, 2)), resolution)};
}

/** Finest keys along each axis of a node at `depth` (root 0, leaves
 *  kKeyBits). */
inline unsigned keySpanAtDepth(unsigned depth) { return 1u << (kKeyBits - depth); }

/** Half the edge of a tree of this resolution [m]: it spans +-that around
 *  the origin on each axis. */
constexpr double treeHalfExtent(double resolution) { return resolution * kKeyOffset; }
}  // namespace avm
