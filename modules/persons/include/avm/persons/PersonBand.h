// A person's own pixels among the pixels given for them (a detector's box, a
// label blob): those whose depth lies in the person's depth band, the sighting's
// robust depth +- SightingOptions::depthBand (PersonSighting.h). The sighting
// counts these pixels, its box and personShape come from them; the others are
// the background, floor or another person that the box also shows. A trail
// reference that never sees the persons cuts these pixels and keeps the rest.
#pragma once

#include <mrpt/obs/CObservation3DRangeScan.h>

#include "avm/persons/PersonSighting.h"

namespace avm::persons
{
/** Whether a pixel of depth `metres` (0: none) is the person's whose robust
 *  depth is `personDepth` (PersonSighting::depth). */
bool inPersonBand(float metres, float personDepth, const SightingOptions& options);

/** The pixels of `pixels` in `obs`'s depth image that are `sighting`'s
 *  person's (inPersonBand), in their order. */
PixelSet personBandPixels(const mrpt::obs::CObservation3DRangeScan& obs, const PixelSet& pixels,
	const PersonSighting& sighting, const SightingOptions& options);

/** Whether depth pixel (u, v) of `obs` lies on a depth discontinuity
 *  (io::onDepthEdge, the rule visual odometry drops features by with
 *  depth_edge_ratio): on a person's silhouette such a pixel is often a mixed
 *  one, its depth between the person's and the background's. */
bool onDepthEdge(const mrpt::obs::CObservation3DRangeScan& obs, int u, int v, double ratio);
}  // namespace avm::persons
