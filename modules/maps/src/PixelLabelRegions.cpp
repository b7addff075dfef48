// Pixel labels -> 3D regions: how a labelled rawlog drives the map in any MRPT
// app. A person mask from a 2D detector bleeds onto the background behind the
// person, so the box comes from points near the mask's median depth, and from
// percentiles rather than extremes.
#include <mrpt/math/CMatrixDynamic.h>
#include <mrpt/obs/TPixelLabelInfo.h>

#include <algorithm>
#include <cmath>

#include "ResolutionPolicy.h"

namespace avm::detail
{
namespace
{
/** Rows x cols of the label matrix, whatever its bit width. */
std::pair<int, int> labelImageSize(const mrpt::obs::TPixelLabelInfoBase& labels)
{
	using namespace mrpt::obs;
	if (auto* l = dynamic_cast<const TPixelLabelInfo<1>*>(&labels))
		return {l->pixelLabels.rows(), l->pixelLabels.cols()};
	if (auto* l = dynamic_cast<const TPixelLabelInfo<2>*>(&labels))
		return {l->pixelLabels.rows(), l->pixelLabels.cols()};
	if (auto* l = dynamic_cast<const TPixelLabelInfo<4>*>(&labels))
		return {l->pixelLabels.rows(), l->pixelLabels.cols()};
	if (auto* l = dynamic_cast<const TPixelLabelInfo<8>*>(&labels))
		return {l->pixelLabels.rows(), l->pixelLabels.cols()};
	return {0, 0};
}

double percentile(std::vector<double>& v, double q)
{
	const auto k = static_cast<std::size_t>(std::lround(q * static_cast<double>(v.size() - 1)));
	std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
	return v[k];
}
}  // namespace

std::vector<mrpt::math::TBoundingBox> regionsFromPixelLabels(
	const mrpt::obs::CObservation3DRangeScan& obs, const mrpt::poses::CPose3D& sensorPoseInWorld,
	const CAdaptiveOctoMap::TInsertionOptions& opts)
{
	std::vector<mrpt::math::TBoundingBox> boxes;
	if (!obs.hasPixelLabels() || !obs.hasRangeImage) return boxes;
	const auto& labels = *obs.pixelLabels;
	const int rows = static_cast<int>(obs.rangeImage.rows()), cols = static_cast<int>(obs.rangeImage.cols());
	if (labelImageSize(labels) != std::make_pair(rows, cols)) return boxes;

	const auto& K = obs.cameraParams;
	const double units = obs.rangeUnits;
	for (const auto& [labelIndex, name] : labels.pixelLabelNames)
	{
		if (name != opts.personLabel) continue;
		// Sensor frame: X forward (depth), Y left, Z up.
		std::vector<mrpt::math::TPoint3D> pts;
		std::vector<double> depths;
		for (int r = 0; r < rows; r++)
			for (int c = 0; c < cols; c++)
			{
				const auto raw = obs.rangeImage(r, c);
				if (raw == 0 || !labels.checkLabel(r, c, static_cast<uint8_t>(labelIndex))) continue;
				const double d = raw * units;
				mrpt::math::TPoint3D p(d, (K.cx() - c) * d / K.fx(), (K.cy() - r) * d / K.fy());
				if (!obs.range_is_depth) p *= d / p.norm();
				pts.push_back(p);
				depths.push_back(p.x);
			}
		if (pts.size() < opts.minLabelPixels) continue;
		const double median = percentile(depths, 0.5);
		std::vector<double> xs, ys, zs;
		for (const auto& p : pts)
		{
			if (std::abs(p.x - median) > opts.labelDepthBand) continue;
			const auto w = sensorPoseInWorld.composePoint(p);
			xs.push_back(w.x);
			ys.push_back(w.y);
			zs.push_back(w.z);
		}
		if (xs.size() < opts.minLabelPixels) continue;
		const double q = opts.labelPercentile, m = opts.regionMargin;
		mrpt::math::TBoundingBox box;
		box.min = {percentile(xs, q) - m, percentile(ys, q) - m, percentile(zs, q) - m};
		box.max = {percentile(xs, 1 - q) + m, percentile(ys, 1 - q) + m, percentile(zs, 1 - q) + m};
		boxes.push_back(box);
	}
	return boxes;
}
}  // namespace avm::detail
