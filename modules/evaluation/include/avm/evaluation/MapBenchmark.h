// Insertion speed and map size of avm::CAdaptiveOctoMap against plain
// octomap::OcTree::insertPointCloud, side by side on the same frames in one
// run (used by app/avm-bench-map; numbers go to doc/benchmark-map.md).
#pragma once

#include <mrpt/math/TBoundingBox.h>

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace avm::evaluation
{
struct MapBenchmarkOptions
{
	std::filesystem::path rawlog;                //!< its images folder set by the program (io::useImagesFolderOf)
	std::size_t maxFrames = 0;                   //!< 0 = all frames with ground truth
	double maxRange = 5.0;                       //!< [m] for every map
	double regionLow = 0.20, regionHigh = 0.05;  //!< [m] region-policy resolutions
	double paperLow = 1.5, paperHigh = 0.5;      //!< [m] the paper's resolutions
	double paperSwitchFraction = 0.5;            //!< paper policy: switch at this fraction of the run
	/** Region for the region policy when the rawlog has no person labels
	 *  (world frame); by default a 1.2 x 1.2 x 2.0 m box (a person with
	 *  margin) centred on the surface seen at the first frame's centre. */
	std::optional<mrpt::math::TBoundingBox> region;
	/** > 1: also time the region policy with this many insertion threads
	 *  (a separate row; the other contenders use one thread). */
	unsigned regionThreads = 1;
	/** Frames each map inserts before the next map's turn. 1: every map
	 *  gets each frame in turn, so each insertion starts with caches full of
	 *  the other maps' data (as in avm-map, where odometry and detection run
	 *  between insertions). Larger: each map's data stays in the caches
	 *  within its turn, as when a process only maps. */
	std::size_t framesPerTurn = 1;
	/** Also time insertPointCloud at regionHigh without discretize (slow). */
	bool withPlainOctomap = false;
};

struct MapBenchmarkRow
{
	std::string name;
	std::size_t frames = 0;
	double meanMs = 0, medianMs = 0, p95Ms = 0;  //!< wall time per frame
	double meanCpuMs = 0;                        //!< CPU time of the inserting thread per frame
	std::size_t occupiedLeaves = 0, freeLeaves = 0, memoryBytes = 0, binaryBytes = 0;
};

struct MapBenchmarkResult
{
	std::size_t frames = 0;
	double meanPointsPerFrame = 0;
	std::string regionSource;  //!< "pixel labels" or the box used
	std::vector<MapBenchmarkRow> rows;
};

MapBenchmarkResult runMapBenchmark(
	const MapBenchmarkOptions& opts, const std::function<void(std::size_t done, std::size_t total)>& progress = {});

/** A markdown table of the result. */
std::string toMarkdown(const MapBenchmarkResult& r);
}  // namespace avm::evaluation
