// A frame as a camera whose lens is covered sees it: the same observation
// with a uniform grey image and no depth. The odometry's tests and the
// pipeline's use it to make a tracking loss on real data.
#pragma once

#include <mrpt/img/CImage.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <opencv2/core.hpp>

#include "avm/io/RgbdFrame.h"

namespace avm::test
{
/** Replaces the images in place (loading them first when they are external):
 *  the colour image becomes embedded grey, the range image embedded zeros. */
inline void coverLens(mrpt::obs::CObservation3DRangeScan& obs)
{
	obs.load();
	const cv::Mat grey(io::colourImage(obs).size(), CV_8UC3, cv::Scalar(128, 128, 128));
	obs.intensityImage = mrpt::img::CImage(grey, mrpt::img::DEEP_COPY);
	if (obs.rangeImage_isExternallyStored()) obs.rangeImage_forceResetExternalStorage();
	obs.rangeImage.setZero();
}
}  // namespace avm::test
