// The trail a map keeps of people who walked through it: its occupied volume
// where a reference that never saw the people says the space is free. The
// reference is built by octomap itself (insertPointCloud, discretize = true)
// from the same frames and ground-truth poses with every labelled person's
// pixels cut out of the depth image (avm-detect --every 1 labels whole
// detector boxes), at each resolution the maps use; each occupied voxel is
// judged at its own resolution. Single OctoMaps of all pixels are built beside
// it, so a map can be set against what plain OctoMap does (octomap #183, #411).
#pragma once

#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace octomap
{
class OcTree;
}

namespace avm::maps
{
struct TrailOptions
{
	/** Labelled rawlog with ground truth; its images folder set by the program. */
	std::filesystem::path rawlog;
	/** avm-map output folders (map_low.bt, map_high.bt), built from the same
	 *  frames with ground-truth poses. */
	std::vector<std::filesystem::path> avmMaps;
	double highResolution = 0.05, lowResolution = 0.20;  //!< [m] of the maps and references
	double maxRange = 5.0;                               //!< [m] of the references and single maps
	std::size_t maxFrames = 0;                           //!< 0 = all frames with ground truth
	std::string personLabel = "person";                  //!< pixel label of persons (person/<k> too)
};

struct TrailRow
{
	std::string map;
	double occupiedM3 = 0, trailM3 = 0;  //!< occupied volume; the part the reference says is free
	double share() const { return occupiedM3 > 0 ? trailM3 / occupiedM3 : 0; }
};

/** One resolution's yardsticks: the reference without the persons' pixels
 *  and the single OctoMap of all pixels, built by octomap's
 *  insertPointCloud(discretize = true). */
class TrailReference
{
   public:
	TrailReference(double resolution, double maxRange);
	~TrailReference();
	TrailReference(const TrailReference&) = delete;
	TrailReference& operator=(const TrailReference&) = delete;

	/** The depth image at `robotPose` + obs.sensorPose; `cut` (one byte per
	 *  pixel, row * cols + col; empty: none) marks the persons' pixels, which
	 *  the reference does not see at all. */
	void insert(const mrpt::obs::CObservation3DRangeScan& obs, const mrpt::poses::CPose3D& robotPose,
		const std::vector<std::uint8_t>& cut);
	/** `map`'s occupied volume (a tree of this resolution) and the part of it
	 *  the reference holds as free, each leaf judged at its own size. Throws
	 *  std::invalid_argument on a tree of another resolution. */
	TrailRow judge(const octomap::OcTree& map, const std::string& name) const;
	const octomap::OcTree& single() const { return *m_single; }
	const octomap::OcTree& reference() const { return *m_reference; }

   private:
	std::unique_ptr<octomap::OcTree> m_reference, m_single;
	double m_maxRange;
};

/** The pixels of `obs`'s person labels (`label`, `label/k`), one byte per
 *  depth pixel (empty when it has none). */
std::vector<std::uint8_t> personPixelMask(const mrpt::obs::CObservation3DRangeScan& obs, const std::string& label);

struct TrailResult
{
	std::size_t frames = 0, framesWithPersons = 0;
	std::vector<TrailRow> rows;
};

/** Builds the references and single maps over the rawlog and measures each
 *  map; `inspect`, if given, is shown the built references (high, low) before
 *  they go. Throws std::runtime_error naming the file on a missing or
 *  unreadable map, or a map of another resolution. */
TrailResult measureTrails(const TrailOptions& options,
	const std::function<void(std::size_t done, std::size_t total)>& progress = {},
	const std::function<void(const TrailReference& high, const TrailReference& low)>& inspect = {});

std::string toMarkdown(const TrailResult& result);
}  // namespace avm::maps
