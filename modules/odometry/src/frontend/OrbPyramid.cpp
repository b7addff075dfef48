#include "OrbPyramid.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace avm::odometry::detail
{
namespace
{
constexpr int kEdgeThreshold = 19, kPatchSize = 31;

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
}  // namespace

OrbPyramid::OrbPyramid(int features, float scale, int levels, int fastThreshold)
{
	// ORB keeps its scale factor as a double made from the float it is given.
	const double scaleFactor = scale;
	for (int level = 0; level < levels; ++level) m_levelScale.push_back(float(std::pow(scaleFactor, double(level))));
	for (const int n : featuresPerLevel(features, scaleFactor, levels))
		m_levelDetector.push_back(
			cv::ORB::create(n, scale, 1, kEdgeThreshold, 0, 2, cv::ORB::HARRIS_SCORE, kPatchSize, fastThreshold));
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
	std::vector<cv::KeyPoint> all, level;
	for (std::size_t l = 0; l < m_levelDetector.size(); ++l)
	{
		m_levelDetector[l]->detect(levels.images[l], level, levels.masks.empty() ? cv::Mat() : levels.masks[l]);
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

cv::Mat OrbPyramid::describe(const Levels& levels, const std::vector<cv::KeyPoint>& keypoints) const
{
	cv::Mat descriptors;
	std::vector<cv::KeyPoint> level;
	for (auto first = keypoints.begin(); first != keypoints.end();)
	{
		const int octave = first->octave;
		const auto last =
			std::find_if(first, keypoints.end(), [octave](const cv::KeyPoint& kp) { return kp.octave != octave; });
		// The level's pixels as ORB's description computes them from the full image's.
		const float toLevel = 1.f / m_levelScale[std::size_t(octave)];
		level.assign(first, last);
		for (auto& kp : level)
		{
			kp.pt *= toLevel;
			kp.octave = 0;
		}
		cv::Mat rows;
		m_describer->compute(levels.images[std::size_t(octave)], level, rows);
		if (rows.rows != int(level.size()))
			throw std::logic_error("OrbPyramid::describe: ORB dropped a keypoint of its own detection");
		descriptors.push_back(rows);
		first = last;
	}
	return descriptors;
}
}  // namespace avm::odometry::detail
