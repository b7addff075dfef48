// The ray integrator through the map on a synthetic depth image: a wall
// split at a region's faces, and the surface sketch forgetting what a later
// image sees through.
#include <gtest/gtest.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <cmath>
#include <cstdint>
#include <optional>

#include "avm/plugin/CAdaptiveOctoMap.h"

using namespace avm;
using mrpt::math::TBoundingBox;

namespace
{
/** A 160 x 120 depth image of a wall 3 m ahead (the plane X = 3 in the
 *  sensor frame), with (optionally) a 0.25 m square object 1.5 m ahead in the
 *  middle of the view. */
mrpt::obs::CObservation3DRangeScan wallScan(bool withObject, std::uint16_t wallMillimetres = 3000)
{
	mrpt::obs::CObservation3DRangeScan obs;
	obs.hasRangeImage = true;
	obs.rangeImage.resize(120, 160);
	obs.rangeUnits = 0.001f;
	obs.cameraParams.ncols = 160;
	obs.cameraParams.nrows = 120;
	obs.cameraParams.setIntrinsicParamsFromValues(120, 120, 79.5, 59.5);
	obs.rangeImage.fill(wallMillimetres);
	if (withObject)
		for (int v = 50; v < 70; v++)
			for (int u = 70; u < 90; u++) obs.rangeImage(v, u) = 1500;
	obs.sensorPose = mrpt::poses::CPose3D();
	return obs;
}

std::size_t occupiedLowVoxels(const CAdaptiveOctoMap& map, const TBoundingBox& box)
{
	std::size_t n = 0;
	map.forEachLeaf(Resolution::Low, [&](const TLeafVoxel& v) { n += v.occupied && box.containsPoint(v.center); });
	return n;
}

/** The map with one free-only box on its depth images while `freeOnly` is
 *  set, as the person layer gives a moving person's. */
class MapWithFreeOnlyBox : public CAdaptiveOctoMap
{
   public:
	std::optional<TBoundingBox> freeOnly;

   protected:
	FreeOnlyBoxes beforeDepthImage(const mrpt::obs::CObservation3DRangeScan&, const mrpt::poses::CPose3D&) override
	{
		return freeOnly ? FreeOnlyBoxes{*freeOnly} : FreeOnlyBoxes{};
	}
};

std::size_t occupiedHighVoxels(const CAdaptiveOctoMap& map, const TBoundingBox& box)
{
	std::size_t n = 0;
	map.forEachLeaf(Resolution::High, [&](const TLeafVoxel& v) { n += v.occupied && box.containsPoint(v.center); });
	return n;
}
}  // namespace

// The integrator through the map on a synthetic scan: a flat wall 3 m ahead,
// a region around part of it. The wall inside the region is in the high tree
// at 5 cm, the rest in the low tree at 20 cm, the space before it free in the
// tree that owns it, and no voxel in both.
TEST(RayIntegrator, AWallSplitsAtTheRegionFaces)
{
	CAdaptiveOctoMap map;
	const TBoundingBox region({2.6, -0.4, -0.4}, {3.4, 0.4, 0.4});
	map.addHighResolutionRegion(region);
	ASSERT_TRUE(map.insertObservation(wallScan(false), mrpt::poses::CPose3D()));

	std::size_t highWall = 0, lowWall = 0;
	map.forEachLeaf(Resolution::High,
		[&](const TLeafVoxel& v)
		{
			if (!v.occupied) return;
			++highWall;
			EXPECT_NEAR(v.center.x, 3.025, 1e-4) << "the wall's 5 cm layer";
			EXPECT_TRUE(region.containsPoint(v.center));
		});
	map.forEachLeaf(Resolution::Low,
		[&](const TLeafVoxel& v)
		{
			if (!v.occupied) return;
			++lowWall;
			EXPECT_NEAR(v.center.x, 3.1, 1e-4) << "the wall's 20 cm layer";
			EXPECT_FALSE(region.containsPoint(v.center));
		});
	// The region's face of the wall is 0.8 x 0.8 m: 16 x 16 high voxels.
	EXPECT_EQ(highWall, 16u * 16u);
	EXPECT_GT(lowWall, 20u);
	// Between the camera and the wall: free, in the tree that owns the space.
	EXPECT_EQ(map.query({2.8, 0.0, 0.0}).state, OccupancyState::Free);
	EXPECT_EQ(map.query({2.8, 0.0, 0.0}).tree, Resolution::High);
	EXPECT_EQ(map.query({1.5, 0.0, 0.0}).state, OccupancyState::Free);
	EXPECT_EQ(map.query({1.5, 0.0, 0.0}).tree, Resolution::Low);
	EXPECT_EQ(map.query({3.6, 0.0, 0.0}).state, OccupancyState::Unknown) << "behind the wall";
}

// Something seen once at low resolution and then seen through (a person who
// walked past) leaves the low voxel occupied, but the sketch forgets where:
// when a region reaches it, no surface comes back there, while the wall that
// is still seen does. A single fine map would have freed it the same way.
TEST(RayIntegrator, TheSketchForgetsWhatALaterDepthImageSeesThrough)
{
	CAdaptiveOctoMap map;
	ASSERT_TRUE(map.insertObservation(wallScan(true), mrpt::poses::CPose3D()));
	for (int i = 0; i < 2; i++) ASSERT_TRUE(map.insertObservation(wallScan(false), mrpt::poses::CPose3D()));
	const TBoundingBox object({1.4, -0.2, -0.2}, {1.8, 0.2, 0.2}), wall({2.8, -0.2, -0.2}, {3.2, 0.2, 0.2});
	ASSERT_EQ(map.query({1.5, 0.0, 0.0}).state, OccupancyState::Occupied) << "one hit, two misses at 0.20 m";
	map.addHighResolutionRegion(object);
	map.addHighResolutionRegion(wall);
	EXPECT_EQ(occupiedHighVoxels(map, object), 0u);
	EXPECT_EQ(occupiedHighVoxels(map, wall), 8u * 8u) << "the wall's 5 cm layer, 0.4 x 0.4 m";
}

// A free-only endpoint voxel is not freed by the scan's other rays, as
// octomap's computeUpdate keeps every endpoint voxel of a scan out of its free
// set (the free-only reference of avm-map's reference_maps does the same). A
// floor 1.1 m below the sensor, seen at a grazing angle: the ray to a far
// floor voxel crosses nearer floor voxels before it ends. Mapped twice, then
// seen five times with a free-only box over part of it (a person passing):
// the floor's voxels in the box stay occupied. Before, the rays to the
// farther floor freed them (two hits, five misses).
TEST(RayIntegrator, AFreeOnlyEndpointVoxelIsNotFreedByTheScansOtherRays)
{
	auto floor = wallScan(false);
	floor.rangeImage.fill(0);
	const auto& cam = floor.cameraParams;
	for (int v = 0; v < 120; v++)
	{
		const double down = (v - cam.cy()) / cam.fy();  // depth per metre of drop
		if (down <= 0) continue;
		const double depth = 1.1 / down;
		if (depth > 4.8) continue;
		for (int u = 0; u < 160; u++) floor.rangeImage(v, u) = static_cast<std::uint16_t>(std::lround(depth * 1000));
	}
	MapWithFreeOnlyBox map;
	const TBoundingBox passing({2.4, -0.6, -1.3}, {4.0, 0.6, -0.9});
	for (int i = 0; i < 2; i++) ASSERT_TRUE(map.insertObservation(floor, mrpt::poses::CPose3D()));
	const auto mapped = occupiedLowVoxels(map, passing);
	ASSERT_GE(mapped, 10u) << "the floor's 0.20 m voxels in the box";
	map.freeOnly = passing;
	for (int i = 0; i < 5; i++) ASSERT_TRUE(map.insertObservation(floor, mrpt::poses::CPose3D()));
	EXPECT_EQ(occupiedLowVoxels(map, passing), mapped);
}
