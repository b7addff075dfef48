// How much occupied space two avm-map runs share: for a map built over
// several sessions against one run of the same frames, or any two runs of one
// place. Each run's occupied space is read from its two trees (map_low.bt,
// map_high.bt) as voxels at the high resolution, a low voxel standing for the
// high voxels it covers, so maps that put the same space in different trees
// still agree.
#pragma once

#include <cstddef>
#include <filesystem>

namespace avm::evaluation
{
struct MapComparison
{
	double lowResolution = 0, highResolution = 0;  //!< [m] of both runs (they must agree)
	/** Occupied voxels of each tree and the intersection over union of the two
	 *  runs' sets, tree by tree at its own resolution. */
	std::size_t lowA = 0, lowB = 0, highA = 0, highB = 0;
	double lowIoU = 0, highIoU = 0;
	/** Both trees' occupied space at the high resolution: voxels of each run
	 *  and their intersection over union. */
	std::size_t spaceA = 0, spaceB = 0;
	double spaceIoU = 0;
};

/** Compares the occupied space of two avm-map output folders. Throws
 *  std::runtime_error naming the file that is missing or unreadable, or
 *  the folder whose resolutions differ from the other's. */
MapComparison compareOccupiedSpace(const std::filesystem::path& runA, const std::filesystem::path& runB);
}  // namespace avm::evaluation
