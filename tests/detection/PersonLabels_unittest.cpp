// writePersonLabels on a real RGB-D observation (MRPT's test frame, 640x480).
#include <gtest/gtest.h>
#include <mrpt/math/CMatrixDynamic.h>  // TPixelLabelInfo.h needs it first
#include <mrpt/obs/TPixelLabelInfo.h>

#include "TestData.h"
#include "avm/detection/PersonLabels.h"
#include "avm/io/RawlogFrameReader.h"

using namespace avm;
using namespace avm::detection;

namespace
{
mrpt::obs::CObservation3DRangeScan::Ptr mrptTestFrame()
{
	io::RawlogFrameReader reader(test::sharedFile("datasets/tests_rgbd.rawlog"));
	auto f = reader.next();
	if (!f) throw std::runtime_error("tests_rgbd.rawlog has no frame");
	return f->observation;
}

Detection personAt(cv::Rect2f box) { return {box, 0, "person", 0.9f}; }
}  // namespace

TEST(PersonLabels, KeepsOtherLabelsAndReplacesEarlierPersons)
{
	auto obs = mrptTestFrame();
	auto labels = std::make_shared<mrpt::obs::TPixelLabelInfo<1>>();
	labels->setSize(480, 640);
	labels->setLabelName(0, "chair");
	labels->setLabel(10, 10, 0);
	obs->pixelLabels = labels;

	writePersonLabels(*obs, {personAt({100, 100, 50, 120})});
	writePersonLabels(*obs, {personAt({300, 200, 40, 100}), {cv::Rect2f(0, 0, 50, 50), 56, "chair", 0.9f}});
	EXPECT_EQ(obs->pixelLabels->checkLabelNameExistence("chair"), 0);
	EXPECT_TRUE(obs->pixelLabels->checkLabel(10, 10, 0));
	const cv::Mat mask = personLabelMask(*obs);
	ASSERT_EQ(mask.size(), cv::Size(640, 480));
	EXPECT_EQ(cv::countNonZero(mask(cv::Rect(100, 100, 50, 120))), 0) << "earlier person not cleared";
	EXPECT_GT(cv::countNonZero(mask(cv::Rect(300, 200, 40, 100))), 0);
	EXPECT_EQ(cv::countNonZero(mask), cv::countNonZero(mask(cv::Rect(300, 200, 40, 100))))
		<< "only the person is labelled, not the chair detection";
}

TEST(PersonLabels, EachPersonHasALabelOfItsOwnWhileBitsLast)
{
	auto obs = mrptTestFrame();
	obs->pixelLabels.reset();
	std::vector<Detection> crowd;
	for (int i = 0; i < 9; i++) crowd.push_back(personAt(cv::Rect2f(10.f + 60 * i, 50, 40, 80)));
	writePersonLabels(*obs, crowd);
	const auto& names = obs->pixelLabels->pixelLabelNames;
	ASSERT_EQ(names.size(), 8u) << "8-bit labels: the plain label and 7 persons of their own";
	EXPECT_EQ(obs->pixelLabels->checkLabelNameExistence("person"), 0);
	for (int k = 1; k <= 7; k++)
	{
		const int bit = obs->pixelLabels->checkLabelNameExistence("person/" + std::to_string(k));
		ASSERT_GE(bit, 0) << "person/" << k;
		// Person k's whole box, and nobody else's, carries its label.
		const int u = 10 + 60 * (k - 1);
		EXPECT_TRUE(obs->pixelLabels->checkLabel(50, u, static_cast<uint8_t>(bit)));
		EXPECT_TRUE(obs->pixelLabels->checkLabel(129, u + 39, static_cast<uint8_t>(bit)));
		EXPECT_FALSE(obs->pixelLabels->checkLabel(50, u + 60, static_cast<uint8_t>(bit)));
	}
	// The eighth and ninth share the plain label.
	EXPECT_TRUE(obs->pixelLabels->checkLabel(60, 10 + 60 * 7, 0));
	EXPECT_TRUE(obs->pixelLabels->checkLabel(60, 10 + 60 * 8, 0));
	EXPECT_EQ(cv::countNonZero(personLabelMask(*obs)), 9 * 40 * 80);
}

TEST(PersonLabels, NoPersonsStillMarksTheFrameAsLabelled)
{
	auto obs = mrptTestFrame();
	obs->pixelLabels.reset();
	writePersonLabels(*obs, {});
	const cv::Mat mask = personLabelMask(*obs);
	ASSERT_FALSE(mask.empty());
	EXPECT_EQ(cv::countNonZero(mask), 0);
}

TEST(PersonLabels, LabelsOfAnotherSizeAreAnError)
{
	auto obs = mrptTestFrame();
	auto labels = std::make_shared<mrpt::obs::TPixelLabelInfo<1>>();
	labels->setSize(10, 10);
	obs->pixelLabels = labels;
	EXPECT_THROW(writePersonLabels(*obs, {personAt({100, 100, 50, 120})}), std::runtime_error);
}
