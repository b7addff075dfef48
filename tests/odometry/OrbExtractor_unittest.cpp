// The front end's ORB (detection and description on one pyramid) against cv::ORB itself,
// on real frames of the Bonn sequence (people in view from frame ~70) with the
// front end's kind of mask (pixels with depth, less a box): the same
// keypoints, then the same orientations and descriptors for every other one
// of them (the front end orients and describes only the features it keeps),
// and the same without a mask.
#include <gtest/gtest.h>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "TestData.h"
#include "avm/io/RawlogFrameReader.h"
#include "avm/io/RgbdFrame.h"
#include "frontend/OrbExtractor.h"

using namespace avm;

namespace
{
void expectSameKeypoints(
	const std::vector<cv::KeyPoint>& actual, const std::vector<cv::KeyPoint>& expected, bool oriented)
{
	ASSERT_EQ(actual.size(), expected.size());
	for (std::size_t i = 0; i < actual.size(); ++i)
	{
		// Bit for bit: the front end's tie-breaks follow these numbers.
		EXPECT_EQ(actual[i].pt, expected[i].pt) << i;
		EXPECT_EQ(actual[i].response, expected[i].response) << i;
		if (oriented)
		{
			EXPECT_EQ(actual[i].angle, expected[i].angle) << i;
		}
		EXPECT_EQ(actual[i].octave, expected[i].octave) << i;
		EXPECT_EQ(actual[i].size, expected[i].size) << i;
	}
}

void expectSameAsOpenCv(const cv::Mat& grey, const cv::Mat& mask)
{
	const int features = 2000, levels = 4, fastThreshold = 12;
	const float scale = 1.2f;
	const auto orb = cv::ORB::create(features, scale, levels, 19, 0, 2, cv::ORB::HARRIS_SCORE, 31, fastThreshold);
	std::vector<cv::KeyPoint> expected;
	orb->detect(grey, expected, mask);
	ASSERT_GT(expected.size(), 1500u);

	const odometry::detail::OrbExtractor extractor(features, scale, levels, fastThreshold);
	const auto pyramid = extractor.build(grey, mask);
	const auto detected = extractor.detect(pyramid);
	expectSameKeypoints(detected, expected, false);

	std::vector<cv::KeyPoint> kept, expectedKept;
	for (std::size_t i = 0; i < detected.size(); i += 2)
	{
		kept.push_back(detected[i]);
		expectedKept.push_back(expected[i]);
	}
	cv::Mat expectedDescriptors;
	orb->compute(grey, expectedKept, expectedDescriptors);
	const cv::Mat descriptors = extractor.describe(pyramid, kept);
	expectSameKeypoints(kept, expectedKept, true);
	ASSERT_EQ(descriptors.rows, int(kept.size()));
	EXPECT_EQ(cv::norm(descriptors, expectedDescriptors, cv::NORM_HAMMING), 0);
}
}  // namespace

TEST(OrbExtractor, GivesOpenCvsKeypointsAndDescriptorsOnRealFrames)
{
	io::RawlogFrameReader reader(test::bonnRawlog());
	int checked = 0;
	for (int index = 0; index <= 150; ++index)
	{
		const auto frame = reader.next();
		ASSERT_TRUE(frame);
		if (index % 75 != 0) continue;  // frames 0, 75 and 150
		SCOPED_TRACE("frame " + std::to_string(index));
		cv::Mat grey;
		cv::cvtColor(io::colourImage(*frame->observation), grey, cv::COLOR_BGR2GRAY);
		const cv::Mat depth = io::depthInMetres(*frame->observation);
		cv::Mat mask = depth > 0;
		mask(cv::Rect(200, 100, 160, 300)).setTo(0);
		expectSameAsOpenCv(grey, mask);
		expectSameAsOpenCv(grey, cv::Mat());
		++checked;
	}
	EXPECT_EQ(checked, 3);
}
