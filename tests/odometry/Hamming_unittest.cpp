// The Hamming counts against OpenCV's: the build's, and hammingByPopcount,
// the code the projection search runs with the popcount instruction where the
// processor has it (here built for the baseline, so the same expression by
// the compiler's library), on the ORB descriptors of a real frame (every pair
// of the first 300: distances from 0 to well over half the bits).
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "TestData.h"
#include "Types.h"
#include "avm/io/RawlogFrameReader.h"
#include "avm/io/RgbdFrame.h"

using namespace avm;

TEST(Hamming, CountsTheBitsOpenCvCountsOnRealOrbDescriptors)
{
	io::RawlogFrameReader reader(test::bonnRawlog());
	const auto frame = reader.next();
	ASSERT_TRUE(frame);
	cv::Mat grey;
	cv::cvtColor(io::colourImage(*frame->observation), grey, cv::COLOR_BGR2GRAY);
	std::vector<cv::KeyPoint> keypoints;
	cv::Mat descriptors;
	cv::ORB::create(300)->detectAndCompute(grey, cv::noArray(), keypoints, descriptors);
	ASSERT_GE(descriptors.rows, 200);
	ASSERT_EQ(descriptors.cols, 32);
	int largest = 0;
	for (int i = 0; i < descriptors.rows; ++i)
		for (int j = 0; j < descriptors.rows; ++j)
		{
			const int expected = int(cv::norm(descriptors.row(i), descriptors.row(j), cv::NORM_HAMMING));
			ASSERT_EQ(odometry::detail::hamming(descriptors.ptr(i), descriptors.ptr(j)), expected) << i << ", " << j;
			ASSERT_EQ(odometry::detail::hammingByPopcount(descriptors.ptr(i), descriptors.ptr(j)), expected)
				<< i << ", " << j;
			largest = std::max(largest, expected);
		}
	EXPECT_GT(largest, 128);
}
