// What the pixels that ended in a map's trail voxels were: each
// pixel a yardstick cuts is put in one class by its depth against its
// person's (the sighting's robust depth and band, as the person layer takes
// them): the person's own (in the band), a mixed pixel on the silhouette (a
// depth edge next to a band pixel: its depth lies between the person and what
// is behind), the background behind or in front of the person, or a label
// that gives no sighting. A diagnostic, beside TrailCauses: it says whether a
// yardstick's trail is the person moving (own and mixed pixels) or correct
// surface the yardstick never saw (the background in a detector's box).
#pragma once

#include <array>
#include <cstdint>
#include <vector>
#include <cstddef>
#include <filesystem>
#include <string>

#include "avm/evaluation/TrailShare.h"

namespace avm::evaluation
{
enum class TrailPixelClass
{
	Band,        //!< the person's own: in their depth band
	Mixed,       //!< not in the band, on a depth edge, next to a band pixel
	Behind,      //!< deeper than the band, not mixed
	InFront,     //!< nearer than the band, not mixed
	NoSighting,  //!< a label with no sighting (the layer cannot tell)
	Other,       //!< a pixel the yardstick does not cut
	Count
};

std::string describe(TrailPixelClass c);

struct TrailPixelCount
{
	std::size_t voxels = 0;
	double m3 = 0;
	double otherPixelsM3 = 0;      //!< of m3: uncut pixels ended there too
	double personMaskTrailM3 = 0;  //!< of m3: trail against the person mask's reference too
};

struct TrailPixels
{
	std::string map;
	Yardstick yardstick = Yardstick::Boxes;
	double edgeRatio = 0;
	/** Voxels by the first class (in TrailPixelClass's order) of the pixels
	 *  that ended in them. */
	std::array<TrailPixelCount, static_cast<std::size_t>(TrailPixelClass::Count)> byFirst{};
	/** Voxels by the class most of their pixels had. */
	std::array<TrailPixelCount, static_cast<std::size_t>(TrailPixelClass::Count)> byMost{};
	/** Pixels that ended in trail voxels, by class (a pixel in voxels of
	 *  both trees counts once a tree). */
	std::array<std::size_t, static_cast<std::size_t>(TrailPixelClass::Count)> pixels{};
	/** Behind pixels that ended in trail voxels, by how far past the band
	 *  [m]: (0, 0.25], (0.25, 0.5], (0.5, 1], beyond 1. */
	std::array<std::size_t, 4> behindPastBand{};
	/** One line per trail voxel (tree, centre, size, pixels by class, the
	 *  behind pixels' mean distance past the band, frames that cut / did not
	 *  cut pixels there, trail against the person mask too): CSV with a
	 *  header. */
	std::string voxelsCsv;
};

/** Each pixel's class (TrailPixelClass, row * cols + col) in `obs`'s depth
 *  image, its sensor at `sensorPose`: Other where `cut` (one yardstick's
 *  PersonCuts) cuts nothing; a cut pixel is judged against the nearest
 *  sighted person whose pixels hold it (`options`' label and sighting keys),
 *  NoSighting when none does. `personDepth` gets that person's robust depth
 *  per pixel (0: none). */
std::vector<std::uint8_t> trailPixelClasses(const mrpt::obs::CObservation3DRangeScan& obs,
	const mrpt::poses::CPose3D& sensorPose, const TrailOptions& options, const std::vector<std::uint8_t>& cut,
	double edgeRatio, std::vector<float>& personDepth);

/** The trail of the avm-map output `avmDir` against `yardstick`'s references
 *  (`high`, `low`), by the classes of the pixels that ended in each trail
 *  voxel over the frames of `options`; `edgeRatio` the depth-edge rule's
 *  fraction (persons::onDepthEdge). */
TrailPixels classifyTrailPixels(const TrailOptions& options, const std::filesystem::path& avmDir,
	const TrailReference& high, const TrailReference& low, Yardstick yardstick, double edgeRatio);

std::string toMarkdown(const TrailPixels& t);
}  // namespace avm::evaluation
