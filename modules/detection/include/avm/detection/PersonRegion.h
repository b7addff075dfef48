// From a person's 2-D box and the registered depth image to the person's depth,
// pixel mask and world-frame 3-D box.
//
// Robust depth: the box also shows the background (and the floor), so its
// median depth is not the person's. The person fills the middle of the box
// (central half of the width, 10..60 % of the height: head and torso), so the
// depth is the median of the densest `person_depth_band` wide window of
// depths there. The person's pixels are the box pixels within
// +-person_depth_band of it.
#pragma once

#include <mrpt/img/TCamera.h>
#include <mrpt/math/TBoundingBox.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <opencv2/core/mat.hpp>

#include <cstddef>
#include <optional>
#include <string>

#include "avm/detection/Detection.h"
#include "avm/detection/TDetectorOptions.h"

namespace avm::detection
{
struct RegionEstimate
{
	/** World-frame axis-aligned box of the person's depth pixels, grown by
	 *  region_margin on every side; empty when skipped (see skipReason). */
	std::optional<mrpt::math::TBoundingBox> box;
	float depth = 0;                  //!< [m] robust depth of the person (0 = none)
	double validDepthFraction = 0;    //!< share of box pixels with a depth
	std::size_t points = 0;           //!< box pixels within the person's depth band
	std::string skipReason;           //!< why there is no box ("" when there is)
};

/** The box in whole pixels, clipped to an image of this size. */
cv::Rect pixelBox(const cv::Rect2f& box, cv::Size image);

/** The robust depth [m] of the person in `box` of a CV_32F depth image
 *  (metres, 0 = none); nothing when the box has no depth at all. */
std::optional<float> robustPersonDepth(const cv::Mat& depthMetres, const cv::Rect& box, double band);

/** Depth, depth band pixel count and, given the optical pose of the camera
 *  in the world (z forward, x right, y down) and the registered intrinsics,
 *  the world box. Skipped (with the reason) when under
 *  min_valid_depth_fraction of the box has depth or fewer than
 *  min_region_points pixels lie in the band. */
RegionEstimate estimatePersonRegion(
	const Detection& person, const cv::Mat& depthMetres, const mrpt::img::TCamera& intrinsics,
	const mrpt::poses::CPose3D& cameraPoseOptical, const TDetectorOptions& options);

/** estimatePersonRegion() on an observation (its depth and cameraParams). */
std::optional<mrpt::math::TBoundingBox> personRegion(
	const Detection& person, const mrpt::obs::CObservation3DRangeScan& obs,
	const mrpt::poses::CPose3D& cameraPoseOptical, const TDetectorOptions& options);

/** The person's pixels as a CV_8U mask (255 = person) of the depth image's
 *  size: the box pixels within the depth band when the region estimate has
 *  enough depth, else the whole box (a person without depth still blocks the
 *  view; the map simply gets no points from those pixels). */
cv::Mat personMask(const Detection& person, const cv::Mat& depthMetres, const TDetectorOptions& options);
}  // namespace avm::detection
