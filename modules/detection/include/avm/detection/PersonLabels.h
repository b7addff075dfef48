// Person masks stored in the observation itself (CObservation3DRangeScan::
// pixelLabels, label name "person"), so that a labelled rawlog drives the
// adaptive map in any MRPT application without running a detector.
#pragma once

#include <mrpt/obs/CObservation3DRangeScan.h>

#include <opencv2/core/mat.hpp>

#include <vector>

#include "avm/detection/Detection.h"
#include "avm/detection/TDetectorOptions.h"

namespace avm::detection
{
/** The label name the map looks for. */
inline constexpr const char* kPersonLabel = "person";

/** Sets the "person" label on the pixels of personMask() for every detection
 *  whose className is "person" (others are ignored), clearing earlier
 *  "person" pixels; other labels already in the observation are kept. Adds
 *  8-bit pixelLabels of the depth image's size when there are none. Writes the
 *  (empty) label also for frames without persons, so "ran, found nobody" is
 *  told apart from "not labelled". Throws std::runtime_error if the
 *  observation has no depth image, or labels of another size or with no free
 *  bit. */
void writePersonLabels(
	mrpt::obs::CObservation3DRangeScan& obs, const std::vector<Detection>& persons,
	const TDetectorOptions& options = {});

/** The "person" pixels as a CV_8U mask (255 = person) of the label matrix's
 *  size; empty Mat when the observation has no "person" label. */
cv::Mat personLabelMask(const mrpt::obs::CObservation3DRangeScan& obs);
}  // namespace avm::detection
