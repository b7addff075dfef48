// The trail a map keeps of people who walked through it: its occupied volume
// where a reference that never saw the people says the space is free. The
// references are built by octomap itself (insertPointCloud, discretize = true)
// from the same frames and ground-truth poses with the persons' pixels cut out
// of the depth image, at each resolution the maps use; each occupied voxel is
// judged at its own resolution. Two yardsticks, each a reference of its own:
// the person mask cuts only each labelled person's own pixels, those of their
// depth band as the person layer takes them (avm/persons/PersonBand.h), so
// the background a detector's box also shows is in the reference, as it is in
// the map; the boxes cut every labelled pixel (avm-detect --every 1 labels
// whole detector boxes), the yardstick the trail was first measured with, which
// never sees what lies behind a person and so counts a map that rightly maps
// it as trail. Single OctoMaps of all pixels are built beside them, so a map
// can be set against what plain OctoMap does (octomap #183, #411).
#pragma once

#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "avm/persons/PersonSighting.h"

namespace octomap
{
class OcTree;
}

namespace avm::evaluation
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
	/** How the person mask finds a person's depth band: the maps' own keys
	 *  (person_depth_band, min_person_pixels, ...). */
	persons::SightingOptions sighting;
};

/** Which pixels a reference cuts out of the depth image. */
enum class Yardstick
{
	PersonMask,  //!< each sighted person's own pixels (their depth band); a person with no sighting, all its pixels
	Boxes,       //!< every labelled pixel: whole detector boxes
	Count
};

std::string describe(Yardstick yardstick);

/** The pixels each yardstick cuts from one depth image, one byte per pixel
 *  (row * cols + col; empty: none). */
struct PersonCuts
{
	std::vector<std::uint8_t> personMask, boxes;
	const std::vector<std::uint8_t>& of(Yardstick y) const { return y == Yardstick::Boxes ? boxes : personMask; }
};

/** The cuts of `obs`'s `options.personLabel` labels, its depth sensor at
 *  `sensorPoseInWorld`: each person of the labels (personPixelsFromLabels)
 *  whose pixels give a sighting (estimateSighting, `options.sighting`) is cut
 *  by the person mask only where personBandPixels says it is the person; a
 *  pixel another person's band holds stays cut, and so does every pixel of a
 *  label that gives no sighting (the layer does not know which are the
 *  person's). */
PersonCuts personCuts(const mrpt::obs::CObservation3DRangeScan& obs, const mrpt::poses::CPose3D& sensorPoseInWorld,
	const TrailOptions& options);

struct TrailRow
{
	std::string map;
	double occupiedM3 = 0;
	/** Of it, the part each yardstick's reference says is free. */
	std::array<double, static_cast<std::size_t>(Yardstick::Count)> trailM3{};
	/** Of the trail, the part where the finer resolution's reference of the
	 *  same yardstick holds no occupied voxel inside the voxel either: a
	 *  0.20 m reference frees a voxel that rays pass through beside a surface
	 *  the 0.05 m one still holds. Equal to trailM3 where there is no finer
	 *  reference. */
	std::array<double, static_cast<std::size_t>(Yardstick::Count)> trailNoFineSurfaceM3{};
	double trail(Yardstick y) const { return trailM3[static_cast<std::size_t>(y)]; }
	double trailNoFineSurface(Yardstick y) const { return trailNoFineSurfaceM3[static_cast<std::size_t>(y)]; }
	double share(Yardstick y) const { return occupiedM3 > 0 ? trail(y) / occupiedM3 : 0; }
	double shareNoFineSurface(Yardstick y) const { return occupiedM3 > 0 ? trailNoFineSurface(y) / occupiedM3 : 0; }
	TrailRow& operator+=(const TrailRow& other);
};

/** One resolution's references, one per yardstick, and the single OctoMap
 *  of all pixels, built by octomap's insertPointCloud(discretize = true). */
class TrailReference
{
   public:
	TrailReference(double resolution, double maxRange);
	~TrailReference();
	TrailReference(const TrailReference&) = delete;
	TrailReference& operator=(const TrailReference&) = delete;

	/** The depth image at `robotPose` + obs.sensorPose; each reference does
	 *  not see the pixels its yardstick cuts at all. */
	void insert(
		const mrpt::obs::CObservation3DRangeScan& obs, const mrpt::poses::CPose3D& robotPose, const PersonCuts& cuts);
	/** `map`'s occupied volume (a tree of this resolution) and the part of it
	 *  each reference holds as free, each leaf judged at its own size. Throws
	 *  std::invalid_argument on a tree of another resolution. `finer`: the
	 *  references at a finer resolution (TrailRow::trailNoFineSurfaceM3). */
	TrailRow judge(const octomap::OcTree& map, const std::string& name, const TrailReference* finer = nullptr) const;
	const octomap::OcTree& single() const { return *m_single; }
	const octomap::OcTree& reference(Yardstick y) const { return *m_references[static_cast<std::size_t>(y)]; }

   private:
	std::array<std::unique_ptr<octomap::OcTree>, static_cast<std::size_t>(Yardstick::Count)> m_references;
	std::unique_ptr<octomap::OcTree> m_single;
	double m_maxRange;
};

/** The pixels of `obs`'s person labels (`label`, `label/k`), one byte per
 *  depth pixel (empty when it has none). */
std::vector<std::uint8_t> personPixelMask(const mrpt::obs::CObservation3DRangeScan& obs, const std::string& label);

struct TrailResult
{
	std::size_t frames = 0, framesWithPersons = 0;
	/** Depth pixels each yardstick cut, over all frames. */
	std::array<std::size_t, static_cast<std::size_t>(Yardstick::Count)> cutPixels{};
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
}  // namespace avm::evaluation
