// avm-detect's rawlog pass: labels written, read back through MRPT, images kept.
#include <gtest/gtest.h>

#include <fstream>

#include "DetectionTestSupport.h"
#include "avm/detection/Detector.h"
#include "avm/detection/PersonLabels.h"
#include "avm/detection/RawlogDetection.h"
#include "avm/io/RawlogFrameReader.h"

using namespace avm;
using namespace avm::detection;
namespace fs = std::filesystem;

TEST(RawlogLabels, PersonLabelsSurviveARawlogRoundTripWithTheSameImages)
{
	const auto dir = test::scratchDir("det-labelled");
	const auto out = dir / "labelled.rawlog";
	const auto o = test::yoloxOptions();
	const auto det = createDetector(o);
	const auto s = labelRawlog(*det, test::bonnRawlog(), out, 50);
	EXPECT_EQ(s.frames, 300u);
	EXPECT_EQ(s.detectedFrames, 6u);
	EXPECT_TRUE(s.skipped.empty());
	EXPECT_GE(s.framesWithPerson, 1u);
	ASSERT_TRUE(fs::exists(out));
	ASSERT_TRUE(fs::is_directory(dir / "labelled_Images"));
	ASSERT_TRUE(fs::exists(s.detectionsFile));

	io::RawlogFrameReader input(test::bonnRawlog()), labelled(out);
	std::size_t n = 0;
	while (auto f = labelled.next())
	{
		auto g = input.next();
		ASSERT_TRUE(g);
		ASSERT_EQ(f->index, g->index);
		ASSERT_TRUE(f->groundTruth) << "frame " << f->index;
		EXPECT_TRUE(f->groundTruth->m_coords == g->groundTruth->m_coords);
		const cv::Mat mask = personLabelMask(*f->observation);
		if (f->index % 50 != 0)
		{
			EXPECT_FALSE(f->observation->hasPixelLabels()) << "frame " << f->index;
		}
		else
		{
			ASSERT_FALSE(mask.empty()) << "frame " << f->index << " has no person label";
			EXPECT_EQ(mask.size(), cv::Size(640, 480));
			// What the detector says on this frame now is what the labels hold.
			const auto persons = personsOnly(det->detect(io::colourImage(*g->observation)));
			mrpt::obs::CObservation3DRangeScan fresh = *g->observation;
			fresh.pixelLabels.reset();
			writePersonLabels(fresh, persons);
			EXPECT_EQ(cv::countNonZero(mask != personLabelMask(fresh)), 0) << "frame " << f->index;
			if (f->index == 0)
			{
				EXPECT_EQ(cv::countNonZero(mask), 0);
			}
			if (f->index == 150)
			{
				EXPECT_GT(cv::countNonZero(mask), 5000);
			}
		}
		// The images are read through the link to the input's images folder.
		EXPECT_EQ(cv::norm(io::colourImage(*f->observation), io::colourImage(*g->observation), cv::NORM_INF), 0);
		++n;
	}
	EXPECT_EQ(n, 300u);
	EXPECT_TRUE(labelled.skipped().empty());

	std::ifstream txt(s.detectionsFile);
	std::size_t lines150 = 0;
	for (std::string line; std::getline(txt, line);)
		if (line.rfind("150 ", 0) == 0)
		{
			++lines150;
			EXPECT_NE(line.find(" person "), std::string::npos) << line;
		}
	EXPECT_GE(lines150, 1u);
}

TEST(RawlogLabels, TruncatedInputIsAnErrorAndLeavesNoOutput)
{
	const auto dir = test::scratchDir("det-truncated-rawlog");
	const auto cut = dir / "cut.rawlog";
	{
		const std::string bytes = mrpt::io::file_get_contents(test::bonnRawlog().string());
		std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 3));
	}
	const auto o = test::yoloxOptions();
	const auto det = createDetector(o);
	try
	{
		labelRawlog(*det, cut, dir / "out.rawlog");
		FAIL() << "truncated rawlog accepted";
	}
	catch (const std::runtime_error& e)
	{
		EXPECT_NE(std::string(e.what()).find(cut.string()), std::string::npos) << e.what();
	}
	EXPECT_FALSE(fs::exists(dir / "out.rawlog"));
	EXPECT_FALSE(fs::exists(dir / "out_detections.txt"));
}

TEST(RawlogLabels, MissingInputAndOutputOverInputAreRefused)
{
	const auto dir = test::scratchDir("det-bad-args");
	const auto o = test::yoloxOptions();
	const auto det = createDetector(o);
	EXPECT_THROW(labelRawlog(*det, dir / "none.rawlog", dir / "out.rawlog"), std::runtime_error);
	EXPECT_THROW(labelRawlog(*det, test::bonnRawlog(), test::bonnRawlog()), std::runtime_error);
}
