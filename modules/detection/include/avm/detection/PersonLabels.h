// Persons stored in the observation itself (CObservation3DRangeScan::
// pixelLabels), so that a labelled rawlog drives the adaptive map in any MRPT
// application without running a detector.
//
// Each person gets a label of its own, named "person/1", "person/2", ...,
// holding its whole detector box: the map's sighting estimator
// (avm/persons/PersonSighting.h) finds the person's depth band inside it, the
// same estimator avm-map uses on detector boxes. A label named plain "person"
// is always written (empty unless a frame has more persons than free label
// bits, then it holds the rest), so "ran, found nobody" is told apart from
// "not labelled". The labels are read back by avm/persons/PersonLabels.h.
#pragma once

#include <mrpt/obs/CObservation3DRangeScan.h>

#include <opencv2/core/mat.hpp>

#include <vector>

#include "avm/detection/Detection.h"
#include "avm/persons/PersonLabels.h"

namespace avm::detection
{
/** The pixels of a detection's box (whole pixels covering it, clipped). */
persons::PixelSet personPixels(const Detection& person, cv::Size image);

/** Labels every detection whose className is "person" (others are ignored),
 *  clearing earlier person labels; other labels already in the observation
 *  are kept. Adds 8-bit pixelLabels of the depth image's size when there are
 *  none. Throws std::runtime_error if the observation has no depth image, or
 *  labels of another size or with no free bit. */
void writePersonLabels(mrpt::obs::CObservation3DRangeScan& obs, const std::vector<Detection>& persons);

/** All person pixels (every person label) as a CV_8U mask (255 = person) of
 *  the label matrix's size; empty Mat when the observation has no person
 *  label. */
cv::Mat personLabelMask(const mrpt::obs::CObservation3DRangeScan& obs);
}  // namespace avm::detection
