// One person seen in one RGB-D frame, in the world frame: the single path from
// "these pixels are a person" to a position and a box. Detector boxes (avm-map)
// and pixel labels (a labelled rawlog in any MRPT app) both come here.
//
// The pixels given for a person also show what lies behind it (a detector's
// box holds background and floor; a segmentation mask bleeds at the edges), so
// the person's depth is the densest `depthBand`-wide window of depths in the
// core of the pixels (the central half of their width, 10..60 % of their
// height: head and torso, which a person almost fills), and only the pixels
// within +-depthBand of it are the person. The box spans the [p, 1-p]
// percentiles of those points on each world axis, so a few stray pixels do not
// stretch it.
#pragma once

#include <mrpt/math/TBoundingBox.h>
#include <mrpt/math/TPoint3D.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace avm::persons
{
/** A person's pixels in a depth image, as indices row * cols + col. */
using PixelSet = std::vector<std::uint32_t>;

/** How pixels become a sighting. Loaded by the map from its `_insertOpts`
 *  (person_depth_band, person_percentile, min_person_pixels,
 *  min_person_depth_fraction). */
struct SightingOptions
{
	/** [m] Half-width of the person's depth band: a person is 0.3-0.5 m
	 *  deep, and a wider band lets the floor and furniture behind them in. */
	double depthBand = 0.3;
	/** The box spans the [p, 1-p] percentiles, p in [0, 0.5): its edges then
	 *  follow the body, not the stray background pixels of a detector's box. */
	double percentile = 0.08;
	std::size_t minPixels = 200;    //!< depth pixels in the band needed for a sighting
	double minDepthFraction = 0.2;  //!< [0..1] share of the pixels that must have depth
};

struct PersonSighting
{
	/** World frame: the per-axis median of the person's points. */
	mrpt::math::TPoint3D position;
	/** World frame, the person's own extent (no margin): the [p, 1-p]
	 *  percentiles of their points, so stray pixels do not stretch it. */
	mrpt::math::TBoundingBox box;
	/** World frame: the box of all of the person's points, every pixel the
	 *  sighting counts as the person, strays and limbs included. What must
	 *  not become a wall while they move (PersonLayer::movingPersonBoxes). */
	mrpt::math::TBoundingBox bandExtent;
	std::size_t points = 0;  //!< depth pixels in the person's band
	float depth = 0;         //!< [m] the person's robust depth
	/** World frame: the person's shape (see personShape); empty until the
	 *  person layer takes it. */
	std::vector<mrpt::math::TPoint3Df> shape;
};

struct SightingEstimate
{
	std::optional<PersonSighting> sighting;
	std::string skipReason;  //!< why there is none ("" when there is)
	/** World frame: the points of the pixels within the person's depth band,
	 *  in the pixels' order, when asked for (BandPoints::Keep); empty without
	 *  a sighting. personShape's input. */
	std::vector<mrpt::math::TPoint3D> bandPoints;
};

/** Whether estimateSighting keeps the person's points (SightingEstimate::
 *  bandPoints): only a caller that makes their shape needs them. */
enum class BandPoints
{
	Drop,
	Keep
};

/** The sighting of the person whose pixels are `pixels` in `obs`'s depth
 *  image, with the depth sensor at `sensorPoseInWorld`. */
SightingEstimate estimateSighting(const mrpt::obs::CObservation3DRangeScan& obs,
	const mrpt::poses::CPose3D& sensorPoseInWorld, const PixelSet& pixels, const SightingOptions& options,
	BandPoints keep = BandPoints::Drop);

/** A sighting's person (its `bandPoints`), one point per voxel of edge
 *  `resolution` [m] on octomap's grid (voxel k spans [k, k+1) * resolution
 *  on each axis), given as the voxel's centre, where that centre lies in
 *  `within`: the person's endpoints at their region's resolution, as the
 *  region's tree would hold them. Sorted (x, y, z), so the same points give
 *  the same shape. */
std::vector<mrpt::math::TPoint3Df> personShape(
	const std::vector<mrpt::math::TPoint3D>& bandPoints, double resolution, const mrpt::math::TBoundingBox& within);

/** The pixels of an axis-aligned pixel box [u0, u1) x [v0, v1), clipped to
 *  the image: a detector's box. */
PixelSet pixelsOfBox(int u0, int v0, int u1, int v1, int cols, int rows);
}  // namespace avm::persons
