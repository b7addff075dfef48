// The default detector and the 3-D person regions on the real Bonn sequence.
#include <gtest/gtest.h>

#include <cmath>

#include "DetectionTestSupport.h"
#include "avm/detection/Detector.h"
#include "avm/detection/PersonRegion.h"
#include "avm/io/RawlogFrameReader.h"

using namespace avm;
using namespace avm::detection;

namespace
{
io::RgbdFrame bonnFrame(std::size_t index)
{
	io::RawlogFrameReader reader(test::bonnRawlog());
	while (auto f = reader.next())
		if (f->index == index) return *f;
	throw std::runtime_error("no frame " + std::to_string(index));
}


std::vector<Detection> personsIn(const io::RgbdFrame& f)
{
	return personsOnly(createDetector(test::yoloxOptions())->detect(io::colourImage(*f.observation)));
}

/** The 8 corners of a world box in the camera optical frame. */
std::vector<mrpt::math::TPoint3D> cornersInCamera(const mrpt::math::TBoundingBox& b, const mrpt::poses::CPose3D& cam)
{
	std::vector<mrpt::math::TPoint3D> out;
	for (int i = 0; i < 8; ++i)
	{
		const mrpt::math::TPoint3D w(i & 1 ? b.max.x : b.min.x, i & 2 ? b.max.y : b.min.y, i & 4 ? b.max.z : b.min.z);
		mrpt::math::TPoint3D c;
		cam.inverseComposePoint(w, c);
		out.push_back(c);
	}
	return out;
}
}  // namespace

TEST(BonnPersons, NoPersonInTheFirstFrame)
{
	EXPECT_TRUE(personsIn(bonnFrame(0)).empty());
}

TEST(BonnPersons, PersonInFrame150)
{
	EXPECT_FALSE(personsIn(bonnFrame(150)).empty());
}

// "In front" is along the optical axis (camera z), "tall" along the camera's
// -y axis: the Bonn motion-capture world need not have z up.
TEST(BonnPersons, RegionOfAPersonInFrame150IsInFrontAndPersonSized)
{
	const auto frame = bonnFrame(150);
	ASSERT_TRUE(frame.groundTruth);
	const auto persons = personsIn(frame);
	ASSERT_FALSE(persons.empty());
	auto o = test::yoloxOptions();
	o.region_margin = 0;  // the person's own extent
	const cv::Mat depth = io::depthInMetres(*frame.observation);
	std::size_t regions = 0;
	for (const auto& p : persons)
	{
		const auto est = estimatePersonRegion(p, depth, frame.observation->cameraParams, *frame.groundTruth, o);
		if (!est.box)
		{
			std::cout << "person at " << p.box << " skipped: " << est.skipReason << "\n";
			continue;
		}
		++regions;
		EXPECT_GE(est.depth, 0.5f);
		EXPECT_LE(est.depth, 5.f);
		double minY = 1e9, maxY = -1e9, minZ = 1e9, maxZ = -1e9;
		for (const auto& c : cornersInCamera(*est.box, *frame.groundTruth))
		{
			minY = std::min(minY, c.y), maxY = std::max(maxY, c.y);
			minZ = std::min(minZ, c.z), maxZ = std::max(maxZ, c.z);
		}
		std::cout << "person " << p.box << ": depth " << est.depth << " m, camera z " << minZ << ".." << maxZ
				  << ", height " << maxY - minY << " m, " << est.points << " points\n";
		EXPECT_GT(minZ, 0.0) << "part of the region is behind the camera";
		EXPECT_GE(0.5 * (minZ + maxZ), 0.5);
		EXPECT_LE(0.5 * (minZ + maxZ), 5.0);
		EXPECT_LE(maxY - minY, 2.5);
		EXPECT_GT(maxY - minY, 0.5);  // a person, not a speck
	}
	EXPECT_GE(regions, 1u);
}

TEST(BonnPersons, RegionMarginGrowsTheBoxOnEverySide)
{
	const auto frame = bonnFrame(150);
	const auto persons = personsIn(frame);
	ASSERT_FALSE(persons.empty());
	auto o = test::yoloxOptions();
	o.region_margin = 0;
	const auto tight = personRegion(persons[0], *frame.observation, *frame.groundTruth, o);
	o.region_margin = 0.25;
	const auto grown = personRegion(persons[0], *frame.observation, *frame.groundTruth, o);
	ASSERT_TRUE(tight && grown);
	EXPECT_NEAR(grown->min.x, tight->min.x - 0.25, 1e-9);
	EXPECT_NEAR(grown->max.z, tight->max.z + 0.25, 1e-9);
}

TEST(BonnPersons, MaskIsThePersonsDepthBandNotTheBackground)
{
	const auto frame = bonnFrame(150);
	const auto persons = personsIn(frame);
	ASSERT_FALSE(persons.empty());
	const auto o = test::yoloxOptions();
	const cv::Mat depth = io::depthInMetres(*frame.observation);
	const auto& p = persons[0];
	const cv::Rect box = pixelBox(p.box, depth.size());
	const cv::Mat mask = personMask(p, depth, o);
	const auto z = robustPersonDepth(depth, box, o.person_depth_band);
	ASSERT_TRUE(z);
	const int inMask = cv::countNonZero(mask), inBox = cv::countNonZero(mask(box));
	EXPECT_EQ(inMask, inBox) << "mask pixels outside the box";
	EXPECT_GT(inBox, 0.2 * box.area());
	EXPECT_LT(inBox, 0.95 * box.area());  // the background through the box is left out
	for (int v = 0; v < depth.rows; ++v)
		for (int u = 0; u < depth.cols; ++u)
			if (mask.at<uint8_t>(v, u))
			{
				ASSERT_LE(std::abs(depth.at<float>(v, u) - *z), o.person_depth_band + 1e-6);
			}
}

TEST(BonnPersons, BoxWithoutDepthIsSkippedAndMaskedWhole)
{
	const auto frame = bonnFrame(150);
	const auto persons = personsIn(frame);
	ASSERT_FALSE(persons.empty());
	const auto o = test::yoloxOptions();
	cv::Mat depth = io::depthInMetres(*frame.observation);
	const cv::Rect box = pixelBox(persons[0].box, depth.size());
	depth(box).setTo(0);
	const auto est = estimatePersonRegion(persons[0], depth, frame.observation->cameraParams, *frame.groundTruth, o);
	EXPECT_FALSE(est.box);
	EXPECT_NE(est.skipReason.find("depth"), std::string::npos) << est.skipReason;
	const cv::Mat mask = personMask(persons[0], depth, o);
	EXPECT_EQ(cv::countNonZero(mask), box.area());
	EXPECT_EQ(cv::countNonZero(mask(box)), box.area());
}
