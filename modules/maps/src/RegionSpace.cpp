#include "RegionSpace.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "OcTreeKeys.h"
#include "TreeOps.h"

namespace avm::detail
{
namespace
{
/** [log-odds] above the occupancy threshold: occupied, as weakly as octomap can tell. */
constexpr float kJustOccupied = 0.01f;

unsigned ratioOf(const octomap::OcTree& low, const octomap::OcTree& high)
{
	return static_cast<unsigned>(std::lround(low.getResolution() / high.getResolution()));
}

/** `logOdds` from a tree where it meant `occupied`, made to mean the same in
 *  `target` (its occupancy threshold may differ) and clamped to its limits. */
float carried(float logOdds, bool occupied, const octomap::OcTree& target)
{
	// octomap: occupied is log-odds >= the threshold.
	const float threshold = target.getOccupancyThresLog();
	constexpr float kStep = 1e-3f;
	if (occupied && logOdds < threshold) logOdds = threshold;
	if (!occupied && logOdds >= threshold) logOdds = threshold - kStep;
	return std::clamp(logOdds, target.getClampingThresMinLog(), target.getClampingThresMaxLog());
}
}  // namespace

void refineIntoHighTree(octomap::OcTree& low, octomap::OcTree& high, std::uint64_t lowKey, SurfaceSketch* sketch)
{
	const auto key = unpackKey(lowKey);
	const auto surface = sketch ? sketch->take(lowKey) : std::nullopt;
	const auto* node = low.search(key);
	if (!node) return;
	const bool occupied = low.isNodeOccupied(node);
	const float value = carried(node->getLogOdds(), occupied, high);
	// A sketch bit says a surface was seen there and not seen through since,
	// not how often: in an occupied low voxel it comes back as a voxel hit
	// once, which rays through it at high resolution free as they would in a
	// single high-resolution map. In a free low voxel (a chair's edge in a voxel of mostly air)
	// the bit has had more rays around it: just occupied, and the voxel's
	// other high voxels come back free.
	const float surfaceValue =
		occupied ? std::min(value, high.getProbHitLog()) : high.getOccupancyThresLog() + kJustOccupied;
	const auto range = KeyRange::finerKeysOf(key, sketch ? sketch->ratio() : ratioOf(low, high));
	unsigned bit = 0;
	std::vector<octomap::OcTreeKey> sketched, others;
	for (unsigned x = range.lo[0]; x < range.hi[0]; x++)
		for (unsigned y = range.lo[1]; y < range.hi[1]; y++)
			for (unsigned z = range.lo[2]; z < range.hi[2]; z++, bit++)
			{
				const octomap::OcTreeKey k(x, y, z);
				if (high.search(k)) continue;
				if (surface && (*surface >> bit & 1u))
					sketched.push_back(k);
				else if (!(occupied && surface))
					others.push_back(k);
			}
	setNodeValues(high, others, value);
	setNodeValues(high, sketched, surfaceValue);
	eraseKeyRange(low, KeyRange::of(key));
}

void coarsenIntoLowTree(octomap::OcTree& high, octomap::OcTree& low, std::uint64_t lowKey, SurfaceSketch& sketch)
{
	if (high.size() == 0) return;
	const auto key = unpackKey(lowKey);
	const auto range = KeyRange::finerKeysOf(key, sketch.ratio());
	float maxLogOdds = -std::numeric_limits<float>::infinity();
	bool known = false, occupied = false;
	std::uint64_t surface = 0;
	for (auto it = high.begin_leafs_bbx(range.first(), range.last()), end = high.end_leafs_bbx(); it != end; ++it)
	{
		known = true;
		maxLogOdds = std::max(maxLogOdds, it->getLogOdds());
		if (!high.isNodeOccupied(*it)) continue;
		occupied = true;
		if (!sketch.usable()) continue;
		// Every high voxel of the occupied leaf in the low voxel (pruned
		// leaves span several, a pruned leaf may span many low voxels).
		const unsigned span = keySpanAtDepth(it.getDepth());
		range.forEachKeyOfCube(it.getIndexKey(), span,
			[&](const octomap::OcTreeKey& k) { surface |= std::uint64_t(1) << sketch.bitOf(packKey(k)); });
	}
	if (!known) return;
	low.setNodeValue(key, carried(maxLogOdds, occupied, low));
	if (sketch.usable()) sketch.set(lowKey, surface);
	eraseKeyRange(high, range);
}
}  // namespace avm::detail
