// Persons in an observation's pixel labels (CObservation3DRangeScan::
// pixelLabels): the one reader of what avm-detect writes
// (avm/detection/PersonLabels.h) and of any labeller's "person" class.
//
// A label named `label + "/" + k` (avm-detect writes "person/1",
// "person/2", ...) is one person, whatever its shape, so touching people stay
// apart; a label named `label` may hold any number of people (a segmentation's
// class), and each 4-connected blob of it is one person.
#pragma once

#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/TPixelLabelInfo.h>

#include <cstddef>
#include <string>
#include <vector>

#include "avm/persons/PersonSighting.h"

namespace avm::persons
{
/** The label name the map looks for by default (insertOpts person_label). */
inline constexpr const char* kPersonLabel = "person";

/** Whether a pixel label named `name` holds persons of `label`: `label`
 *  itself or `label/k`. */
bool isPersonLabel(const std::string& name, const std::string& label = kPersonLabel);

struct LabelImageSize
{
	int rows = 0, cols = 0;
};
/** The label matrix's size, which MRPT's base class does not tell. Throws
 *  std::runtime_error on a label type of an unknown width. */
LabelImageSize labelImageSize(const mrpt::obs::TPixelLabelInfoBase& labels);

/** One person label of an observation and all its pixels, depth or not, as
 *  indices row * cols + col of the label image. */
struct LabelPixels
{
	bool onePerson = false;  //!< `label/k`; else the plain `label`, any number of persons
	PixelSet pixels;
};

/** The `label` labels of `obs`, in the order of their bits, read in one pass
 *  over its label image (empty: no such label). */
std::vector<LabelPixels> readPersonLabels(
	const mrpt::obs::CObservation3DRangeScan& obs, const std::string& label = kPersonLabel);

/** The persons that `obs`'s `label` labels show (see the top of this file),
 *  each as all its labelled pixels, with depth or not, so that the sighting
 *  estimator judges the share with depth as for a detector's box; a person
 *  needs at least `minPixels` of them with depth. None when the labels are
 *  not of the depth image's size. */
std::vector<PixelSet> personPixelsFromLabels(
	const mrpt::obs::CObservation3DRangeScan& obs, const std::string& label, std::size_t minPixels);
}  // namespace avm::persons
