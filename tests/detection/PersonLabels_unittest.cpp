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
