// OpenCV's ORB, split where the front end needs it split. The front end
// detects candidates, keeps half of them by a grid, and describes those:
// cv::ORB would build its pyramid (of the image, and of the mask) for each of
// the two calls, orient every candidate, and run FAST over the border its edge
// cull then empties. Here the pyramid is built once, as ORB builds it; the
// detection is ORB's (FAST, the Harris score, the same culls) without the
// orientation, which describe() works out for the kept keypoints alone before
// ORB describes them on their level. The keypoints and descriptors are
// cv::ORB's to the bit (tests/odometry/OrbExtractor_unittest.cpp).
#pragma once

#include <opencv2/features2d.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace avm::odometry::detail
{
class OrbExtractor
{
   public:
	/** The parameters of cv::ORB::create(features, scale, levels, 19, 0, 2,
	 *  HARRIS_SCORE, 31, fastThreshold). */
	OrbExtractor(int features, float scale, int levels, int fastThreshold);

	/** A grey image's levels, and its mask's when there is one. */
	struct Pyramid
	{
		std::vector<cv::Mat> images, masks;
	};
	Pyramid build(const cv::Mat& grey, const cv::Mat& mask) const;
	/** The same images with another mask (or none, when it is empty). */
	Pyramid withMask(const Pyramid& pyramid, const cv::Mat& mask) const;

	/** The keypoints cv::ORB::detect gives on the image and mask of `pyramid`,
	 *  in the full image's pixels, with their level in `octave`, but not
	 *  oriented yet (`angle` -1). */
	std::vector<cv::KeyPoint> detect(const Pyramid& pyramid) const;

	/** Orients keypoints of detect() (their `angle` as cv::ORB's) and returns
	 *  the descriptors cv::ORB::compute gives them, one row each. They must be
	 *  ordered by level, as ORB orders them. */
	cv::Mat describe(const Pyramid& pyramid, std::vector<cv::KeyPoint>& keypoints) const;

	/** The columns -16 .. 15 of ORB's circular patch round a keypoint: two
	 *  16-byte loads of pixels. */
	static constexpr int kPatchColumns = 32;

   private:
	/** A row of the patch over its kPatchColumns columns: the column (u)
	 *  where the row is inside the circle and the row's distance from the
	 *  centre (v) there, zero outside it; the orientation's moments are these
	 *  weights times the pixels. */
	struct PatchRow
	{
		std::array<std::int16_t, kPatchColumns> column{}, row{};
	};
	/** Rows 0 .. 15 from the centre of ORB's circular patch. */
	static std::vector<PatchRow> patchRows();

	cv::Size levelSize(const cv::Size& full, std::size_t level) const;

	/** FAST's corners of a level (with ORB's threshold and non-maximum
	 *  suppression) that the edge cull can keep. */
	void fastCorners(const cv::Mat& image, std::vector<cv::KeyPoint>& corners) const;

	/** ORB's orientation of a keypoint at a level's pixel (x, y). */
	float orientation(const cv::Mat& image, int x, int y) const;

	std::vector<float> m_levelScale;   //!< a level's pixel in the full image's, as ORB computes it
	std::vector<int> m_levelFeatures;  //!< a level's share of the features
	int m_fastThreshold;
	std::vector<PatchRow> m_patchRows;  //!< rows 0 .. 15 from the centre (each stands for the row above too)
	cv::Ptr<cv::ORB> m_describer;
};
}  // namespace avm::odometry::detail
