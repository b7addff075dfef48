// OpenCV's ORB, split where the front end needs it split. cv::ORB builds its
// pyramid (of the image, and of the mask) in every call, and the front end
// called it twice a frame, to detect the candidates and then to describe the
// ones the bucketing keeps: the second pyramid was a third of ORB's resizing.
// And its detection orients every candidate, though half of them are dropped
// undescribed. Here the pyramid is built once, as ORB builds it; the detection
// is ORB's (FAST, the Harris score, the same culls) without the orientation,
// which describe() works out for the kept keypoints alone; ORB describes them
// on their level. The keypoints and descriptors are cv::ORB's to the bit.
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
	 *  in the full image's pixels, with their level in `octave`, but not
	 *  oriented yet (`angle` -1). */
	std::vector<cv::KeyPoint> detect(const Levels& levels) const;

	/** Orients keypoints of detect() (their `angle` as cv::ORB's) and returns
	 *  the descriptors cv::ORB::compute gives them, one row each. They must be
	 *  ordered by level, as ORB orders them. */
	cv::Mat describe(const Levels& levels, std::vector<cv::KeyPoint>& keypoints) const;

   private:
	cv::Size levelSize(const cv::Size& full, std::size_t level) const;

	/** ORB's orientation of a keypoint at a level's pixel (x, y). */
	float orientation(const cv::Mat& image, int x, int y) const;

	std::vector<float> m_levelScale;   //!< a level's pixel in the full image's, as ORB computes it
	std::vector<int> m_levelFeatures;  //!< a level's share of the features
	int m_fastThreshold;
	std::vector<int> m_patchRowEnd;  //!< the orientation's circular patch: its half-width at each row from the centre
	cv::Ptr<cv::ORB> m_describer;
};
}  // namespace avm::odometry::detail
