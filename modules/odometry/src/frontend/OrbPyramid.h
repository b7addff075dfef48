// OpenCV's ORB with its image pyramid built once a frame. cv::ORB builds the
// pyramid (of the image, and of the mask) in every call, and the front end
// calls it twice a frame, to detect the candidates and then to describe the
// ones the bucketing keeps: the second pyramid was a third of ORB's resizing
// (doc/performance.md). Here the pyramid is built as ORB builds it, and ORB
// runs on each level as on a one-level image, so the keypoints and the
// descriptors are those cv::ORB gives, to the bit.
#pragma once

#include <opencv2/features2d.hpp>

#include <vector>

namespace avm::odometry::detail
{
class OrbPyramid
{
   public:
	/** The parameters of cv::ORB::create(features, scale, levels, 19, 0, 2,
	 *  HARRIS_SCORE, 31, fastThreshold). */
	OrbPyramid(int features, float scale, int levels, int fastThreshold);

	/** A grey image's pyramid, and its mask's when there is one. */
	struct Levels
	{
		std::vector<cv::Mat> images, masks;
	};
	Levels build(const cv::Mat& grey, const cv::Mat& mask) const;
	/** The same images with another mask (or none, when it is empty). */
	Levels withMask(const Levels& levels, const cv::Mat& mask) const;

	/** The keypoints cv::ORB::detect gives on the image and mask of `levels`,
	 *  in the full image's pixels, with their level in `octave`. */
	std::vector<cv::KeyPoint> detect(const Levels& levels) const;

	/** The descriptors cv::ORB::compute gives for keypoints of detect(), ordered
	 *  by level (as ORB orders them), one row each. */
	cv::Mat describe(const Levels& levels, const std::vector<cv::KeyPoint>& keypoints) const;

   private:
	cv::Size levelSize(const cv::Size& full, std::size_t level) const;

	std::vector<float> m_levelScale;                //!< a level's pixel in the full image's, as ORB computes it
	std::vector<cv::Ptr<cv::ORB>> m_levelDetector;  //!< ORB on one level, with that level's share of the features
	cv::Ptr<cv::ORB> m_describer;
};
}  // namespace avm::odometry::detail
