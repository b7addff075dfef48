// Pixel labels -> 3D regions: how a labelled rawlog drives the map in any MRPT
// app. A person mask from a 2D detector bleeds onto the background behind the
// person, so the box comes from points near the mask's median depth, and from
// percentiles rather than extremes.
#include <mrpt/math/CMatrixDynamic.h>
#include <mrpt/obs/TPixelLabelInfo.h>

#include <algorithm>
#include <cmath>
#include <optional>

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

/** The box of one person's pixels: points near the median depth only (the
 *  mask bleeds onto the background), percentiles on each world axis, grown
 *  by the margin. */
template <typename SensorPoint>
std::optional<mrpt::math::TBoundingBox> personBox(const std::vector<std::pair<int, int>>& pixels,
	const SensorPoint& sensorPoint, const mrpt::poses::CPose3D& sensorPoseInWorld,
	const CAdaptiveOctoMap::TInsertionOptions& opts)
{
	std::vector<mrpt::math::TPoint3D> pts;
	std::vector<double> depths;
	pts.reserve(pixels.size());
	for (const auto& [r, c] : pixels)
	{
		pts.push_back(sensorPoint(r, c));
		depths.push_back(pts.back().x);
	}
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
	if (xs.size() < opts.minLabelPixels) return std::nullopt;
	const double q = opts.labelPercentile, m = opts.regionMargin;
	mrpt::math::TBoundingBox box;
	box.min = {percentile(xs, q) - m, percentile(ys, q) - m, percentile(zs, q) - m};
	box.max = {percentile(xs, 1 - q) + m, percentile(ys, 1 - q) + m, percentile(zs, 1 - q) + m};
	return box;
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
	auto sensorPoint = [&](int r, int c) {
		const double d = obs.rangeImage(r, c) * units;
		// Sensor frame: X forward (depth), Y left, Z up.
		mrpt::math::TPoint3D p(d, (K.cx() - c) * d / K.fx(), (K.cy() - r) * d / K.fy());
		if (!obs.range_is_depth) p *= d / p.norm();
		return p;
	};
	for (const auto& [labelIndex, name] : labels.pixelLabelNames)
	{
		if (name != opts.personLabel) continue;
		const auto bit = static_cast<uint8_t>(labelIndex);
		// One label may hold several people (a detector writes all its
		// persons under one name): each 4-connected blob of labelled pixels
		// with depth is one person.
		std::vector<int> component(static_cast<std::size_t>(rows) * cols, -1);
		auto usable = [&](int r, int c) { return obs.rangeImage(r, c) != 0 && labels.checkLabel(r, c, bit); };
		std::vector<std::pair<int, int>> stack, pixels;
		int next = 0;
		for (int r0 = 0; r0 < rows; r0++)
			for (int c0 = 0; c0 < cols; c0++)
			{
				if (component[r0 * cols + c0] >= 0 || !usable(r0, c0)) continue;
				pixels.clear();
				stack.assign(1, {r0, c0});
				component[r0 * cols + c0] = next;
				while (!stack.empty())
				{
					const auto [r, c] = stack.back();
					stack.pop_back();
					pixels.emplace_back(r, c);
					const int nb[4][2] = {{r - 1, c}, {r + 1, c}, {r, c - 1}, {r, c + 1}};
					for (const auto& [nr, nc] : nb)
					{
						if (nr < 0 || nc < 0 || nr >= rows || nc >= cols) continue;
						int& slot = component[nr * cols + nc];
						if (slot >= 0 || !usable(nr, nc)) continue;
						slot = next;
						stack.emplace_back(nr, nc);
					}
				}
				next++;
				if (pixels.size() < opts.minLabelPixels) continue;
				if (auto box = personBox(pixels, sensorPoint, sensorPoseInWorld, opts)) boxes.push_back(*box);
			}
	}
	return boxes;
}
}  // namespace avm::detail
