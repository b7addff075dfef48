// The sighting estimator on a depth image made here: a person standing in
// front of a wall, seen through a detector-like box that also shows the wall.
#include <gtest/gtest.h>

#include <cmath>
#include <tuple>

#include "avm/persons/PersonBand.h"
#include "avm/persons/PersonLabels.h"
#include "avm/persons/PersonSighting.h"

using namespace avm::persons;

namespace
{
constexpr int kCols = 640, kRows = 480;
constexpr double kF = 525, kCx = 319.5, kCy = 239.5;

/** A wall at 4 m and, in columns [260, 380) and rows [100, 400), a person at
 *  2 m; sensor frame = world frame (X forward, Y left, Z up). */
mrpt::obs::CObservation3DRangeScan personBeforeAWall()
{
	mrpt::obs::CObservation3DRangeScan obs;
	obs.hasRangeImage = true;
	obs.rangeImage.resize(kRows, kCols);
	obs.rangeUnits = 0.001f;
	obs.range_is_depth = true;
	obs.cameraParams.ncols = kCols;
	obs.cameraParams.nrows = kRows;
	obs.cameraParams.setIntrinsicParamsFromValues(kF, kF, kCx, kCy);
	obs.sensorPose = mrpt::poses::CPose3D();
	for (int v = 0; v < kRows; v++)
		for (int u = 0; u < kCols; u++)
			obs.rangeImage(v, u) = (u >= 260 && u < 380 && v >= 100 && v < 400) ? 2000 : 4000;
	return obs;
}

/** Empty 8-bit labels of the depth image's size, named as avm-detect names
 *  them: bit 0 "person" (any number of persons), bit 1 "person/1" (one). */
std::shared_ptr<mrpt::obs::TPixelLabelInfo<1>> personLabels()
{
	auto labels = std::make_shared<mrpt::obs::TPixelLabelInfo<1>>();
	labels->setSize(kRows, kCols);
	labels->setLabelName(0, "person");
	labels->setLabelName(1, "person/1");
	return labels;
}
}  // namespace

TEST(PersonSighting, ThePersonNotTheWallBehindIt)
{
	const auto obs = personBeforeAWall();
	// The box is wider than the person: a third of it shows the wall.
	const auto est = estimateSighting(obs, {}, pixelsOfBox(230, 90, 410, 410, kCols, kRows), {});
	ASSERT_TRUE(est.sighting) << est.skipReason;
	const auto& s = *est.sighting;
	EXPECT_NEAR(s.depth, 2.0, 1e-3);
	EXPECT_EQ(s.points, 120u * 300u);
	EXPECT_NEAR(s.position.x, 2.0, 1e-3);
	EXPECT_NEAR(s.position.y, 0.0, 0.01);
	EXPECT_NEAR(s.box.min.x, 2.0, 1e-3);
	EXPECT_NEAR(s.box.max.x, 2.0, 1e-3);
	// Width: 120 px at 2 m is 0.457 m; the percentiles trim person_percentile
	// (0.08 by default) each side.
	const double kept = 1 - 2 * SightingOptions().percentile;
	EXPECT_NEAR(s.box.max.y - s.box.min.y, 0.457 * kept, 0.01);
	EXPECT_NEAR(s.box.max.z - s.box.min.z, 300 * 2.0 / kF * kept, 0.01);
}

TEST(PersonSighting, ThePersonsBandPixelsAreThePersonNotTheWall)
{
	const auto obs = personBeforeAWall();
	const auto box = pixelsOfBox(230, 90, 410, 410, kCols, kRows);
	const auto est = estimateSighting(obs, {}, box, {});
	ASSERT_TRUE(est.sighting) << est.skipReason;
	const auto band = personBandPixels(obs, box, *est.sighting, {});
	EXPECT_EQ(band.size(), est.sighting->points);
	for (const auto i : band)
	{
		const auto u = i % kCols, v = i / kCols;
		ASSERT_TRUE(u >= 260 && u < 380 && v >= 100 && v < 400) << u << ", " << v;
	}
	EXPECT_FALSE(inPersonBand(0.f, est.sighting->depth, {}));
}

TEST(PersonSighting, ASightingIsPlacedByTheSensorPose)
{
	const auto obs = personBeforeAWall();
	const mrpt::poses::CPose3D pose(10, 5, 1, 0.5, 0, 0);
	const auto here = estimateSighting(obs, {}, pixelsOfBox(230, 90, 410, 410, kCols, kRows), {});
	const auto there = estimateSighting(obs, pose, pixelsOfBox(230, 90, 410, 410, kCols, kRows), {});
	ASSERT_TRUE(here.sighting && there.sighting);
	const auto expected = pose.composePoint(here.sighting->position);
	EXPECT_NEAR((there.sighting->position - expected).norm(), 0, 0.01);
}

TEST(PersonSighting, TooFewPixelsOrTooLittleDepthGiveNoSighting)
{
	auto obs = personBeforeAWall();
	SightingOptions o;
	o.minPixels = 200;
	const auto tiny = estimateSighting(obs, {}, pixelsOfBox(300, 200, 310, 210, kCols, kRows), o);
	EXPECT_FALSE(tiny.sighting);
	EXPECT_NE(tiny.skipReason.find("min_person_pixels"), std::string::npos) << tiny.skipReason;

	for (int v = 0; v < kRows; v++)
		for (int u = 0; u < 200; u++) obs.rangeImage(v, u) = 0;
	const auto dark = estimateSighting(obs, {}, pixelsOfBox(0, 0, 220, 480, kCols, kRows), o);
	EXPECT_FALSE(dark.sighting);
	EXPECT_NE(dark.skipReason.find("min_person_depth_fraction"), std::string::npos) << dark.skipReason;
	EXPECT_FALSE(estimateSighting(obs, {}, {}, o).sighting);
}

TEST(PersonSighting, LabelBlobsAreOnePersonEachOrOneLabelOnePerson)
{
	auto obs = personBeforeAWall();
	auto labels = personLabels();
	// Two blobs under the plain label, and one person whose own label is split.
	for (int v = 100; v < 200; v++)
	{
		for (int u = 20; u < 60; u++) labels->setLabel(v, u, 0);
		for (int u = 500; u < 540; u++) labels->setLabel(v, u, 0);
		for (int u = 260; u < 380; u++)
			if (u != 320) labels->setLabel(v, u, 1);
	}
	obs.pixelLabels = labels;
	const auto persons = personPixelsFromLabels(obs, "person", 100);
	ASSERT_EQ(persons.size(), 3u);
	std::size_t sizes = 0;
	for (const auto& p : persons) sizes += p.size();
	EXPECT_EQ(sizes, 2u * 40u * 100u + 119u * 100u);
	EXPECT_TRUE(personPixelsFromLabels(obs, "dog", 100).empty());
}

// Labels are judged as a detector's box is: pixels without depth count
// against min_person_depth_fraction, whatever names the person.
TEST(PersonSighting, ALabelMostlyWithoutDepthGivesNoSighting)
{
	auto obs = personBeforeAWall();
	auto labels = personLabels();
	// The person under a label of its own, a blob of wall under the plain
	// label; only every tenth column of either has depth.
	for (int v = 100; v < 400; v++)
	{
		for (int u = 260; u < 380; u++) labels->setLabel(v, u, 1);
		for (int u = 20; u < 140; u++) labels->setLabel(v, u, 0);
		for (int u = 0; u < kCols; u++)
			if (u % 10 != 0) obs.rangeImage(v, u) = 0;
	}
	obs.pixelLabels = labels;
	const SightingOptions options;
	const auto persons = personPixelsFromLabels(obs, "person", options.minPixels);
	EXPECT_EQ(persons.size(), 2u) << "one blob under the plain label, one person under its own";
	for (const auto& pixels : persons)
	{
		EXPECT_EQ(pixels.size(), 120u * 300u);
		const auto est = estimateSighting(obs, {}, pixels, options);
		EXPECT_FALSE(est.sighting);
		EXPECT_NE(est.skipReason.find("min_person_depth_fraction"), std::string::npos) << est.skipReason;
	}
}

// A person's shape: their points (not the wall's), one per voxel of the given
// resolution on octomap's grid, inside the box given; the same every time.
TEST(PersonSighting, APersonsShapeIsOnePointPerVoxelOfTheirPointsInsideTheBox)
{
	const auto obs = personBeforeAWall();
	const auto pixels = pixelsOfBox(230, 90, 410, 410, kCols, kRows);
	const auto est = estimateSighting(obs, {}, pixels, {}, BandPoints::Keep);
	ASSERT_TRUE(est.sighting) << est.skipReason;
	EXPECT_TRUE(estimateSighting(obs, {}, pixels, {}).bandPoints.empty()) << "kept only when asked for";
	const double res = 0.05;
	const mrpt::math::TPoint3D margin(0.2, 0.2, 0.2);
	const mrpt::math::TBoundingBox region(est.sighting->box.min - margin, est.sighting->box.max + margin);
	const auto shape = personShape(est.bandPoints, res, region);
	// 120 x 300 px at 2 m: 0.457 m x 1.143 m, 10 x 23 voxels, give or take
	// one on each axis where the grid cuts.
	EXPECT_GE(shape.size(), 9u * 22u);
	EXPECT_LE(shape.size(), 11u * 24u);
	for (std::size_t i = 0; i < shape.size(); i++)
	{
		const auto& p = shape[i];
		EXPECT_NEAR(p.x, 2.025, 1e-5) << "the person at 2 m, in voxel [2.00, 2.05); not the wall at 4 m";
		for (const double c : {double(p.x), double(p.y), double(p.z)})
			EXPECT_NEAR(c / res - 0.5, std::round(c / res - 0.5), 1e-3) << "not a voxel centre: " << p;
		EXPECT_TRUE(region.containsPoint(mrpt::math::TPoint3D(p))) << p;
		if (i > 0)
		{
			EXPECT_LT(std::tie(shape[i - 1].x, shape[i - 1].y, shape[i - 1].z), std::tie(p.x, p.y, p.z));
		}
	}
	EXPECT_EQ(est.bandPoints.size(), est.sighting->points) << "one point for each pixel within the band";
	EXPECT_EQ(personShape(estimateSighting(obs, {}, pixels, {}, BandPoints::Keep).bandPoints, res, region), shape);
	// A coarser grid, fewer points; a smaller box, only the points inside.
	EXPECT_LT(personShape(est.bandPoints, 0.2, region).size(), shape.size() / 4);
	const mrpt::math::TBoundingBox upperHalf({1, -1, 0}, {3, 1, 1});
	const auto upper = personShape(est.bandPoints, res, upperHalf);
	EXPECT_GT(upper.size(), 0u);
	EXPECT_LT(upper.size(), shape.size());
	for (const auto& p : upper) EXPECT_GT(p.z, 0.0f) << p;
}

TEST(PersonBand, ADepthEdgeIsWhereTheNeighbourhoodSpansMoreThanTheRatioOfTheDepth)
{
	auto obs = personBeforeAWall();
	// Inside the person and inside the wall: flat.
	EXPECT_FALSE(onDepthEdge(obs, 320, 250, 0.05));
	EXPECT_FALSE(onDepthEdge(obs, 100, 250, 0.05));
	// On the silhouette, either side of it: 2 m against 4 m.
	EXPECT_TRUE(onDepthEdge(obs, 260, 250, 0.05));
	EXPECT_TRUE(onDepthEdge(obs, 259, 250, 0.05));
	// A mixed pixel between the two is on the edge too.
	obs.rangeImage(250, 258) = 3000;
	EXPECT_TRUE(onDepthEdge(obs, 258, 250, 0.05));
	// A small step is within the ratio: 2.00 against 2.08 m at 0.05.
	obs.rangeImage(200, 321) = 2080;
	EXPECT_FALSE(onDepthEdge(obs, 320, 200, 0.05));
	EXPECT_TRUE(onDepthEdge(obs, 320, 200, 0.03));
	// A neighbour without depth, or a neighbourhood leaving the image, is no
	// stable depth either (the odometry's rule).
	obs.rangeImage(300, 101) = 0;
	EXPECT_TRUE(onDepthEdge(obs, 100, 300, 0.05));
	EXPECT_TRUE(onDepthEdge(obs, 0, 250, 0.05));
}
