#include "avm/detection/PersonRegion.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "avm/io/RgbdFrame.h"

namespace avm::detection
{
namespace
{
// Head and torso: the part of a person's box the person almost fills.
constexpr double kCoreX0 = 0.25, kCoreX1 = 0.75, kCoreY0 = 0.10, kCoreY1 = 0.60;
// Below this many core samples the whole box is used.
constexpr std::size_t kMinCoreSamples = 20;

bool valid(float d) { return std::isfinite(d) && d > 0; }

void collect(const cv::Mat& depth, const cv::Rect& r, std::vector<float>& out)
{
	for (int y = r.y; y < r.y + r.height; ++y)
	{
		const float* row = depth.ptr<float>(y);
		for (int x = r.x; x < r.x + r.width; ++x)
			if (valid(row[x])) out.push_back(row[x]);
	}
}

void requireDepth(const cv::Mat& depth)
{
	if (depth.empty() || depth.type() != CV_32F) throw std::invalid_argument("depth image must be a non-empty CV_32F image in metres");
}

struct BandStats
{
	std::optional<float> depth;
	double validFraction = 0;
	std::size_t inBand = 0;
};

BandStats bandStats(const cv::Mat& depth, const cv::Rect& box, double band)
{
	BandStats s;
	if (box.empty()) return s;
	std::vector<float> all;
	collect(depth, box, all);
	s.validFraction = double(all.size()) / box.area();
	s.depth = robustPersonDepth(depth, box, band);
	if (s.depth)
		s.inBand = static_cast<std::size_t>(std::count_if(
			all.begin(), all.end(), [&](float d) { return std::abs(d - *s.depth) <= band; }));
	return s;
}

bool enoughDepth(const BandStats& s, const TDetectorOptions& o)
{
	return s.depth && s.validFraction >= o.min_valid_depth_fraction &&
		   s.inBand >= static_cast<std::size_t>(o.min_region_points);
}
}  // namespace

cv::Rect pixelBox(const cv::Rect2f& box, cv::Size image)
{
	const int x0 = static_cast<int>(std::floor(box.x)), y0 = static_cast<int>(std::floor(box.y));
	const int x1 = static_cast<int>(std::ceil(box.x + box.width)), y1 = static_cast<int>(std::ceil(box.y + box.height));
	return cv::Rect(cv::Point(x0, y0), cv::Point(x1, y1)) & cv::Rect(cv::Point(0, 0), image);
}

std::optional<float> robustPersonDepth(const cv::Mat& depth, const cv::Rect& box, double band)
{
	requireDepth(depth);
	const cv::Rect r = box & cv::Rect(cv::Point(0, 0), depth.size());
	if (r.empty()) return std::nullopt;
	const cv::Rect core(
		cv::Point(r.x + int(r.width * kCoreX0), r.y + int(r.height * kCoreY0)),
		cv::Point(r.x + int(std::ceil(r.width * kCoreX1)), r.y + int(std::ceil(r.height * kCoreY1))));
	std::vector<float> d;
	collect(depth, core & r, d);
	if (d.size() < kMinCoreSamples)
	{
		d.clear();
		collect(depth, r, d);
	}
	if (d.empty()) return std::nullopt;
	std::sort(d.begin(), d.end());
	// Densest window [d[i], d[i] + band]: the depth most of the core shows.
	std::size_t bestBegin = 0, bestEnd = 0;
	for (std::size_t i = 0, j = 0; i < d.size(); ++i)
	{
		while (j < d.size() && d[j] - d[i] <= band) ++j;
		if (j - i > bestEnd - bestBegin) bestBegin = i, bestEnd = j;
	}
	return d[bestBegin + (bestEnd - bestBegin) / 2];
}

RegionEstimate estimatePersonRegion(
	const Detection& person, const cv::Mat& depth, const mrpt::img::TCamera& K,
	const mrpt::poses::CPose3D& cameraPoseOptical, const TDetectorOptions& o)
{
	requireDepth(depth);
	RegionEstimate est;
	const cv::Rect box = pixelBox(person.box, depth.size());
	if (box.empty())
	{
		est.skipReason = "box is outside the depth image";
		return est;
	}
	if (!io::isFinite(cameraPoseOptical))
	{
		est.skipReason = "camera pose is not finite";
		return est;
	}
	const double band = o.person_depth_band;
	const BandStats s = bandStats(depth, box, band);
	est.validDepthFraction = s.validFraction;
	est.points = s.inBand;
	if (s.depth) est.depth = *s.depth;
	if (!enoughDepth(s, o))
	{
		std::ostringstream why;
		why.precision(2);
		if (s.validFraction < o.min_valid_depth_fraction)
			why << "only " << 100 * s.validFraction << " % of the box has depth (min_valid_depth_fraction "
				<< o.min_valid_depth_fraction << ")";
		else
			why << "only " << s.inBand << " depth pixels within " << band << " m of the person's depth (min_region_points "
				<< o.min_region_points << ")";
		est.skipReason = why.str();
		return est;
	}
	const double fx = K.fx(), fy = K.fy(), cx = K.cx(), cy = K.cy();
	auto region = mrpt::math::TBoundingBox::PlusMinusInfinity();  // grown by updateWithPoint()
	for (int v = box.y; v < box.y + box.height; ++v)
	{
		const float* row = depth.ptr<float>(v);
		for (int u = box.x; u < box.x + box.width; ++u)
		{
			const float d = row[u];
			if (!valid(d) || std::abs(d - est.depth) > band) continue;
			mrpt::math::TPoint3D world;
			cameraPoseOptical.composePoint({(u - cx) * d / fx, (v - cy) * d / fy, double(d)}, world);
			region.updateWithPoint(world);
		}
	}
	const mrpt::math::TPoint3D margin(o.region_margin, o.region_margin, o.region_margin);
	region.min -= margin;
	region.max += margin;
	est.box = region;
	return est;
}

std::optional<mrpt::math::TBoundingBox> personRegion(
	const Detection& person, const mrpt::obs::CObservation3DRangeScan& obs,
	const mrpt::poses::CPose3D& cameraPoseOptical, const TDetectorOptions& options)
{
	return estimatePersonRegion(person, io::depthInMetres(obs), obs.cameraParams, cameraPoseOptical, options).box;
}

cv::Mat personMask(const Detection& person, const cv::Mat& depth, const TDetectorOptions& o)
{
	requireDepth(depth);
	cv::Mat mask(depth.size(), CV_8U, cv::Scalar(0));
	const cv::Rect box = pixelBox(person.box, depth.size());
	if (box.empty()) return mask;
	const BandStats s = bandStats(depth, box, o.person_depth_band);
	if (!enoughDepth(s, o))
	{
		mask(box).setTo(255);
		return mask;
	}
	const float lo = *s.depth - float(o.person_depth_band), hi = *s.depth + float(o.person_depth_band);
	cv::Mat inBand;
	cv::inRange(depth(box), lo, hi, inBand);
	inBand.copyTo(mask(box));
	return mask;
}
}  // namespace avm::detection
