#include "avm/persons/PersonBand.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

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
	const auto& img = obs.rangeImage;
	if (u < 1 || v < 1 || u >= img.cols() - 1 || v >= img.rows() - 1) return true;
	const std::uint16_t d = img(v, u);
	std::uint16_t lo = d, hi = d;
	for (int dv = -1; dv <= 1; ++dv)
		for (int du = -1; du <= 1; ++du)
		{
			const std::uint16_t n = img(v + dv, u + du);
			lo = std::min(lo, n);
			hi = std::max(hi, n);
		}
	// In raw units: the ratio compares two depths of the same image.
	return lo == 0 || double(hi - lo) > ratio * double(d);
}
}  // namespace avm::persons
