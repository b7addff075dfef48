#include "avm/persons/PersonBand.h"

#include <cmath>

namespace avm::persons
{
bool inPersonBand(float metres, float personDepth, const SightingOptions& options)
{
	return metres > 0 && std::abs(metres - personDepth) <= options.depthBand;
}

PixelSet personBandPixels(const mrpt::obs::CObservation3DRangeScan& obs, const PixelSet& pixels,
	const PersonSighting& sighting, const SightingOptions& options)
{
	PixelSet out;
	if (!obs.hasRangeImage) return out;
	const auto cols = static_cast<std::uint32_t>(obs.rangeImage.cols());
	const double units = obs.rangeUnits;
	for (const auto i : pixels)
	{
		// Rounded as estimateSighting rounds a pixel's depth, so that the
		// pixels here are the ones its sighting counted.
		const auto metres = static_cast<float>(obs.rangeImage(i / cols, i % cols) * units);
		if (inPersonBand(metres, sighting.depth, options)) out.push_back(i);
	}
	return out;
}
}  // namespace avm::persons
