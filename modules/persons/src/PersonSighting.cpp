#include "avm/persons/PersonSighting.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <sstream>

#include "avm/io/DepthCamera.h"
#include "avm/io/PoseTransform.h"
#include "avm/maps/OcTreeKeyLayout.h"
#include "avm/persons/PersonBand.h"

namespace avm::persons
{
namespace
{
// Head and torso: the part of a person's pixels the person almost fills.
constexpr double kCoreX0 = 0.25, kCoreX1 = 0.75, kCoreY0 = 0.10, kCoreY1 = 0.60;
// Below this many core samples all the pixels are used.
constexpr std::size_t kMinCoreSamples = 20;
// Pixels the depth and the box are estimated from, at most.
constexpr std::size_t kMaxSamples = 8000;

/** Column and row of the pixel of index i in an image `cols` wide. */
std::array<int, 2> pixelAt(std::uint32_t i, int cols)
{
	return {
		static_cast<int>(i % static_cast<std::uint32_t>(cols)), static_cast<int>(i / static_cast<std::uint32_t>(cols))};
}

/** Pixel (u, v) at depth d [m], in the world. */
class WorldPointOf
{
   public:
	WorldPointOf(const mrpt::poses::CPose3D& sensorPoseInWorld, const io::DepthCamera& camera)
		: m_sensor(sensorPoseInWorld), m_camera(camera)
	{
	}
	mrpt::math::TPoint3D operator()(int u, int v, float d) const
	{
		return m_sensor.compose(m_camera.unproject(u, v, d));
	}

   private:
	io::PoseTransform m_sensor;
	const io::DepthCamera& m_camera;
};

/** The value at fraction q of the sorted order (nearest rank). */
double percentile(std::vector<double>& v, double q)
{
	const auto k = static_cast<std::size_t>(std::lround(q * static_cast<double>(v.size() - 1)));
	std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
	return v[k];
}

/** The middle of the densest window [d, d + band] of the sorted depths. */
float densestWindowDepth(std::vector<float>& d, double band)
{
	std::sort(d.begin(), d.end());
	std::size_t bestBegin = 0, bestEnd = 0;
	for (std::size_t i = 0, j = 0; i < d.size(); ++i)
	{
		while (j < d.size() && d[j] - d[i] <= band) ++j;
		if (j - i > bestEnd - bestBegin) bestBegin = i, bestEnd = j;
	}
	return d[bestBegin + (bestEnd - bestBegin) / 2];
}

/** The person's depth: the middle of the densest depth band of a sample of
 *  the pixels (every step-th) in the core of their extent (u0, v0, u1, v1),
 *  or of all the sample when the core has too few. */
template <typename MetresAt>
float personDepth(const PixelSet& pixels, std::size_t step, int cols, const MetresAt& metresAt,
	const std::array<int, 4>& extent, double depthBand)
{
	const auto [u0, v0, u1, v1] = extent;
	const double w = u1 - u0 + 1, h = v1 - v0 + 1;
	const double cu0 = u0 + w * kCoreX0, cu1 = u0 + w * kCoreX1, cv0 = v0 + h * kCoreY0, cv1 = v0 + h * kCoreY1;
	std::vector<float> core, all;
	all.reserve(pixels.size() / step + 1);
	for (std::size_t k = 0; k < pixels.size(); k += step)
	{
		const auto [u, v] = pixelAt(pixels[k], cols);
		const float d = metresAt(u, v);
		if (!(d > 0)) continue;
		all.push_back(d);
		if (u >= cu0 && u < cu1 && v >= cv0 && v < cv1) core.push_back(d);
	}
	return densestWindowDepth(core.size() >= kMinCoreSamples ? core : all, depthBand);
}

std::string format(const char* what, double value, const char* key, double limit)
{
	std::ostringstream s;
	s.precision(3);
	s << what << value << " (" << key << " " << limit << ")";
	return s.str();
}
}  // namespace

SightingEstimate estimateSighting(const mrpt::obs::CObservation3DRangeScan& obs,
	const mrpt::poses::CPose3D& sensorPoseInWorld, const PixelSet& pixels, const SightingOptions& o, BandPoints keep)
{
	SightingEstimate est;
	if (pixels.empty() || !obs.hasRangeImage || obs.rangeImage.cols() == 0)
	{
		est.skipReason = "no pixels with a depth image";
		return est;
	}
	const auto camera = io::DepthCamera::of(obs);
	const int cols = camera.width;
	const auto& img = obs.rangeImage;
	const double units = obs.rangeUnits;
	auto metresAt = [&](int u, int v) { return static_cast<float>(img(v, u) * units); };

	int u0 = cols, u1 = -1, v0 = camera.height, v1 = -1;
	std::size_t withDepth = 0;
	for (const auto i : pixels)
	{
		const auto [u, v] = pixelAt(i, cols);
		u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
		if (metresAt(u, v) > 0) ++withDepth;
	}
	const double fraction = double(withDepth) / double(pixels.size());
	if (fraction < o.minDepthFraction)
	{
		est.skipReason = format(
			"only a share of ", fraction, "of the pixels has depth, min_person_depth_fraction", o.minDepthFraction);
		return est;
	}
	// A detector's box holds tens of thousands of pixels: the statistics
	// come from a regular sample of at most kMaxSamples of them (every
	// step-th pixel, the same ones for the same input).
	const std::size_t step = std::max<std::size_t>(1, (pixels.size() + kMaxSamples - 1) / kMaxSamples);

	const float depth = personDepth(pixels, step, cols, metresAt, {u0, v0, u1, v1}, o.depthBand);

	// The person's points, each pixel within the band unprojected once: the
	// statistics take the regular sample of them, the extent all of them, and
	// personShape all of them where the caller keeps them.
	auto& band = est.bandPoints;
	std::vector<double> xs, ys, zs;
	const auto take = [&](const mrpt::math::TPoint3D& p) { xs.push_back(p.x), ys.push_back(p.y), zs.push_back(p.z); };
	const WorldPointOf pointOf(sensorPoseInWorld, camera);
	// Reserved up front: grown a push at a time, these vectors (tens of
	// thousands of points a person a frame) were copied at every doubling.
	if (keep == BandPoints::Keep) band.reserve(pixels.size());
	for (auto* v : {&xs, &ys, &zs}) v->reserve(pixels.size() / step + 1);
	auto extent = mrpt::math::TBoundingBox::PlusMinusInfinity();
	std::size_t inBand = 0;
	// k % step == 0 without a division a pixel: the sample's pixels are
	// every step-th from the first.
	for (std::size_t k = 0, toNextSample = 0; k < pixels.size();
		 ++k, toNextSample = toNextSample ? toNextSample - 1 : step - 1)
	{
		const auto [u, v] = pixelAt(pixels[k], cols);
		const float d = metresAt(u, v);
		if (!inPersonBand(d, depth, o)) continue;
		++inBand;
		const auto p = pointOf(u, v, d);
		extent.updateWithPoint(p);
		if (keep == BandPoints::Keep) band.push_back(p);
		if (toNextSample == 0) take(p);
	}
	if (inBand < o.minPixels)
	{
		band.clear();
		est.skipReason =
			format("depth pixels within the person's band: ", double(inBand), "min_person_pixels", double(o.minPixels));
		return est;
	}
	// A sample that missed a sparse band: all of them then (rare: unprojected
	// again rather than kept for it).
	if (xs.size() < kMinCoreSamples)
	{
		xs.clear(), ys.clear(), zs.clear();
		for (const auto i : pixels)
		{
			const auto [u, v] = pixelAt(i, cols);
			if (const float d = metresAt(u, v); inPersonBand(d, depth, o)) take(pointOf(u, v, d));
		}
	}
	PersonSighting s;
	s.points = inBand;
	s.depth = depth;
	const double q = o.percentile;
	s.box.min = {percentile(xs, q), percentile(ys, q), percentile(zs, q)};
	s.box.max = {percentile(xs, 1 - q), percentile(ys, 1 - q), percentile(zs, 1 - q)};
	s.bandExtent = extent;
	s.position = {percentile(xs, 0.5), percentile(ys, 0.5), percentile(zs, 0.5)};
	est.sighting = s;
	return est;
}

std::vector<mrpt::math::TPoint3Df> personShape(
	const std::vector<mrpt::math::TPoint3D>& bandPoints, double resolution, const mrpt::math::TBoundingBox& within)
{
	std::vector<mrpt::math::TPoint3Df> shape;
	if (!(resolution > 0)) return shape;
	// The voxels of a tree of this resolution, by octomap's keys packed in
	// one word (avm/maps/OcTreeKeyLayout.h), which sort as the keys do and
	// compare in one instruction where triples took three. A point beyond
	// the tree has no voxel in the map either.
	const double perMetre = 1.0 / resolution;
	using Key = std::uint64_t;
	std::vector<Key> keys;
	// Neighbouring pixels of a row mostly fall in one voxel (a 0.05 m voxel is
	// about ten pixels wide at 2.5 m): skipping a repeat of the last key keeps
	// the set and leaves a tenth as many keys to sort.
	std::optional<Key> last;
	for (const auto& p : bandPoints)
	{
		const int x = keyOf(p.x, perMetre), y = keyOf(p.y, perMetre), z = keyOf(p.z, perMetre);
		if (!keyInTree(x) || !keyInTree(y) || !keyInTree(z)) continue;
		const Key k = packKey(x, y, z);
		if (k == last) continue;
		last = k;
		if (within.containsPoint(centreOf(k, resolution))) keys.push_back(k);
	}
	std::sort(keys.begin(), keys.end());
	keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
	shape.reserve(keys.size());
	for (const auto& k : keys)
	{
		const auto c = centreOf(k, resolution);
		shape.emplace_back(static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z));
	}
	return shape;
}

PixelSet pixelsOfBox(int u0, int v0, int u1, int v1, int cols, int rows)
{
	PixelSet out;
	u0 = std::max(u0, 0), v0 = std::max(v0, 0), u1 = std::min(u1, cols), v1 = std::min(v1, rows);
	for (int v = v0; v < v1; ++v)
		for (int u = u0; u < u1; ++u) out.push_back(static_cast<std::uint32_t>(v * cols + u));
	return out;
}
}  // namespace avm::persons
