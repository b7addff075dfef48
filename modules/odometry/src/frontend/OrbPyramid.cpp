#include "OrbPyramid.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace avm::odometry::detail
{
namespace
{
constexpr int kEdgeThreshold = 19, kPatchSize = 31, kHarrisBlock = 7;
constexpr float kHarrisK = 0.04f;

/** How many of `features` ORB gives each level: a share falling by 1/scale
 *  a level, the rounding left to the last (OpenCV 4.6, orb.cpp). */
std::vector<int> featuresPerLevel(int features, double scale, int levels)
{
	std::vector<int> perLevel(std::size_t(levels), 0);
	const float factor = float(1.0 / scale);
	float desired = float(features) * (1 - factor) / (1 - float(std::pow(double(factor), double(levels))));
	int sum = 0;
	for (int level = 0; level + 1 < levels; ++level)
	{
		perLevel[std::size_t(level)] = cvRound(desired);
		sum += perLevel[std::size_t(level)];
		desired *= factor;
	}
	perLevel.back() = std::max(features - sum, 0);
	return perLevel;
}

/** ORB's Harris score of the pixel (x, y): Sobel-like gradients summed over
 *  a 7x7 block, in integers, then ORB's float expression in its order. */
float harrisScore(const cv::Mat& image, int x, int y)
{
	constexpr int r = kHarrisBlock / 2;
	const int step = int(image.step);
	int a = 0, b = 0, c = 0;
	for (int i = 0; i < kHarrisBlock; ++i)
	{
		const std::uint8_t* row = image.ptr<std::uint8_t>(y - r + i) + (x - r);
		for (int j = 0; j < kHarrisBlock; ++j)
		{
			const std::uint8_t* p = row + j;
			const int Ix = (p[1] - p[-1]) * 2 + (p[-step + 1] - p[-step - 1]) + (p[step + 1] - p[step - 1]);
			const int Iy = (p[step] - p[-step]) * 2 + (p[step - 1] - p[-step - 1]) + (p[step + 1] - p[-step + 1]);
			a += Ix * Ix;
			b += Iy * Iy;
			c += Ix * Iy;
		}
	}
	const float scale = 1.f / ((1 << 2) * kHarrisBlock * 255.f);
	const float scale4 = scale * scale * scale * scale;
	return ((float)a * b - (float)c * c - kHarrisK * ((float)a + b) * ((float)a + b)) * scale4;
}

/** The half-width of ORB's circular patch at each row from its centre, made
 *  symmetric in rows and columns as ORB makes it. */
std::vector<int> patchRowEnds()
{
	constexpr int half = kPatchSize / 2;
	std::vector<int> end(half + 2, 0);
	const int vmax = cvFloor(half * std::sqrt(2.f) / 2 + 1);
	const int vmin = cvCeil(half * std::sqrt(2.f) / 2);
	for (int v = 0; v <= vmax; ++v) end[std::size_t(v)] = cvRound(std::sqrt(double(half) * half - v * v));
	for (int v = half, v0 = 0; v >= vmin; --v)
	{
		while (end[std::size_t(v0)] == end[std::size_t(v0) + 1]) ++v0;
		end[std::size_t(v)] = v0;
		++v0;
	}
	return end;
}
}  // namespace

OrbPyramid::OrbPyramid(int features, float scale, int levels, int fastThreshold)
	: m_fastThreshold(fastThreshold), m_patchRowEnd(patchRowEnds())
{
	// ORB keeps its scale factor as a double made from the float it is given.
	const double scaleFactor = scale;
	for (int level = 0; level < levels; ++level) m_levelScale.push_back(float(std::pow(scaleFactor, double(level))));
	m_levelFeatures = featuresPerLevel(features, scaleFactor, levels);
	// No edge threshold: a detected keypoint taken back to its level's pixels
	// can land a rounding inside the edge, and ORB would drop it there. The
	// descriptor's border (its rotated patch) does not depend on it.
	m_describer = cv::ORB::create(features, scale, 1, 0, 0, 2, cv::ORB::HARRIS_SCORE, kPatchSize, fastThreshold);
}

OrbPyramid::Levels OrbPyramid::build(const cv::Mat& grey, const cv::Mat& mask) const
{
	// As cv::ORB builds it: each level resized from the one before.
	Levels out;
	out.images.push_back(grey);
	for (std::size_t level = 1; level < m_levelScale.size(); ++level)
	{
		cv::Mat image;
		cv::resize(out.images.back(), image, levelSize(grey.size(), level), 0, 0, cv::INTER_LINEAR_EXACT);
		out.images.push_back(image);
	}
	return withMask(out, mask);
}

OrbPyramid::Levels OrbPyramid::withMask(const Levels& levels, const cv::Mat& mask) const
{
	// The mask's levels as cv::ORB makes them: kept only where they stay whole.
	Levels out{levels.images, {}};
	if (mask.empty()) return out;
	out.masks.push_back(mask);
	for (std::size_t level = 1; level < m_levelScale.size(); ++level)
	{
		cv::Mat levelMask;
		cv::resize(out.masks.back(), levelMask, levelSize(mask.size(), level), 0, 0, cv::INTER_LINEAR_EXACT);
		cv::threshold(levelMask, levelMask, 254, 0, cv::THRESH_TOZERO);
		out.masks.push_back(levelMask);
	}
	return out;
}

cv::Size OrbPyramid::levelSize(const cv::Size& full, std::size_t level) const
{
	const float scale = m_levelScale[level];
	return {cvRound(float(full.width) / scale), cvRound(float(full.height) / scale)};
}

std::vector<cv::KeyPoint> OrbPyramid::detect(const Levels& levels) const
{
	// ORB's detection of each level: FAST corners in the mask and away from
	// the edge; of the strongest twice the level's share, the share with the
	// best Harris score.
	std::vector<cv::KeyPoint> all, level;
	for (std::size_t l = 0; l < m_levelScale.size(); ++l)
	{
		const cv::Mat& image = levels.images[l];
		cv::FAST(image, level, m_fastThreshold, true, cv::FastFeatureDetector::TYPE_9_16);
		if (!levels.masks.empty()) cv::KeyPointsFilter::runByPixelsMask(level, levels.masks[l]);
		cv::KeyPointsFilter::runByImageBorder(level, image.size(), kEdgeThreshold);
		cv::KeyPointsFilter::retainBest(level, 2 * m_levelFeatures[l]);
		for (auto& kp : level) kp.response = harrisScore(image, cvRound(kp.pt.x), cvRound(kp.pt.y));
		cv::KeyPointsFilter::retainBest(level, m_levelFeatures[l]);
		const float scale = m_levelScale[l];
		for (auto& kp : level)
		{
			kp.octave = int(l);
			kp.size = float(kPatchSize) * scale;
			kp.pt *= scale;
		}
		all.insert(all.end(), level.begin(), level.end());
	}
	return all;
}

float OrbPyramid::orientation(const cv::Mat& image, int x, int y) const
{
	// The intensity centroid of the circular patch, two rows at a time.
	constexpr int half = kPatchSize / 2;
	const int step = int(image.step);
	const std::uint8_t* centre = image.ptr<std::uint8_t>(y) + x;
	int m01 = 0, m10 = 0;
	for (int u = -half; u <= half; ++u) m10 += u * centre[u];
	for (int v = 1; v <= half; ++v)
	{
		int rowSum = 0;
		const int d = m_patchRowEnd[std::size_t(v)];
		for (int u = -d; u <= d; ++u)
		{
			const int below = centre[u + v * step], above = centre[u - v * step];
			rowSum += below - above;
			m10 += u * (below + above);
		}
		m01 += v * rowSum;
	}
	return cv::fastAtan2(float(m01), float(m10));
}

cv::Mat OrbPyramid::describe(const Levels& levels, std::vector<cv::KeyPoint>& keypoints) const
{
	cv::Mat descriptors;
	std::vector<cv::KeyPoint> level;
	for (auto first = keypoints.begin(); first != keypoints.end();)
	{
		const int octave = first->octave;
		const auto last =
			std::find_if(first, keypoints.end(), [octave](const cv::KeyPoint& kp) { return kp.octave != octave; });
		const cv::Mat& image = levels.images[std::size_t(octave)];
		// The level's pixels as ORB's description computes them from the full
		// image's; its detection's were whole, which rounding gives back.
		const float toLevel = 1.f / m_levelScale[std::size_t(octave)];
		level.clear();
		for (auto kp = first; kp != last; ++kp)
		{
			cv::KeyPoint atLevel = *kp;
			atLevel.pt *= toLevel;
			atLevel.octave = 0;
			kp->angle = atLevel.angle = orientation(image, cvRound(atLevel.pt.x), cvRound(atLevel.pt.y));
			level.push_back(atLevel);
		}
		cv::Mat rows;
		m_describer->compute(image, level, rows);
		if (rows.rows != int(level.size()))
			throw std::logic_error("OrbPyramid::describe: ORB dropped a keypoint of its own detection");
		descriptors.push_back(rows);
		first = last;
	}
	return descriptors;
}
}  // namespace avm::odometry::detail
