#include "avm/persons/PersonBand.h"

#include <cmath>

#include "avm/io/DepthEdge.h"

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

bool onDepthEdge(const mrpt::obs::CObservation3DRangeScan& obs, int u, int v, double ratio)
{
	// In raw units: the rule compares two depths of the same image.
	const auto& img = obs.rangeImage;
	return io::onDepthEdge([&](int x, int y) { return img(y, x); }, u, v, int(img.cols()), int(img.rows()), ratio);
}
}  // namespace avm::persons
