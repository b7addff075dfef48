// A tree's occupied space as the set of its finest-depth keys, and the
// intersection over union of two such sets: how a map is compared with a
// reference map voxel by voxel (avm-map's reference_maps, the tests), each
// voxel judged at its own tree's finest resolution whether or not its leaf
// was pruned.
#pragma once

#include <functional>
#include <set>
#include <tuple>

namespace octomap
{
class OcTree;
}

namespace avm
{
/** A finest-depth key (x, y, z) of one tree. */
using FinestKey = std::tuple<int, int, int>;

/** The finest-depth keys of `tree`'s occupied leaves (a pruned leaf gives
 *  every key it covers) whose voxel centre [m] `keep(x, y, z)` accepts. */
std::set<FinestKey> occupiedFinestKeys(
	const octomap::OcTree& tree, const std::function<bool(double, double, double)>& keep);

/** |a and b| / |a or b|; 1 for two empty sets. */
double intersectionOverUnion(const std::set<FinestKey>& a, const std::set<FinestKey>& b);
}  // namespace avm
