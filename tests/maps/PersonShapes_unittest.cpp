// Each person's last shape on real Bonn frames with ground
// truth poses: a patch of pixels labelled "person" in each frame, inserted
// through the plugin map as any MRPT app does. The track keeps the shape of
// the last sighting at the high resolution inside the person's region; the
// map draws it and serializes it.
#include <gtest/gtest.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/math/CMatrixDynamic.h>
#include <mrpt/opengl/CPointCloud.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/serialization/CArchive.h>

#include <array>
#include <cmath>
#include <set>

#include "BonnFrames.h"
#include "SerializationCopy.h"
#include "avm/persons/PersonColour.h"
#include "avm/plugin/CAdaptiveOctoMap.h"

using avm::CAdaptiveOctoMap;

using avm::test::withPersonAtCentre;

TEST(PersonShapes, ATrackKeepsItsLastShapeAtTheRegionsResolutionInsideTheRegion)
{
	CAdaptiveOctoMap map;
	const double res = map.creationOptions().high.resolution;
	std::vector<mrpt::math::TPoint3Df> before;
	for (const auto& f : avm::test::bonnFrames(50, 10))
	{
		ASSERT_TRUE(map.insertObservation(*withPersonAtCentre(f), f.pose));
		ASSERT_EQ(map.personTracks().size(), 1u) << "frame " << f.index;
		ASSERT_EQ(map.highResolutionRegions().size(), 1u);
		const auto& shape = map.personTracks()[0].shape;
		const auto& region = map.highResolutionRegions()[0].boxes.back();
		// A patch of about 0.2 x 0.45 m at 2-3 m: tens of voxels of 5 cm.
		EXPECT_GT(shape.size(), 20u) << "frame " << f.index;
		std::set<std::array<long, 3>> voxels;
		for (const auto& p : shape)
		{
			EXPECT_TRUE(region.containsPoint(mrpt::math::TPoint3D(p))) << p << " outside " << region.asString();
			std::array<long, 3> key{};
			for (int k = 0; k < 3; k++)
			{
				const double cell = p[k] / res - 0.5;
				EXPECT_NEAR(cell, std::round(cell), 1e-3) << "not a voxel centre: " << p;
				key[k] = std::lround(cell);
			}
			EXPECT_TRUE(voxels.insert(key).second) << "two points in one voxel: " << p;
		}
		EXPECT_NE(shape, before) << "frame " << f.index << ": the shape of the last sighting replaces the one before";
		before = shape;
	}

	mrpt::opengl::CSetOfObjects scene;
	map.getVisualizationInto(scene);
	const auto cloud = scene.getByClass<mrpt::opengl::CPointCloud>();
	ASSERT_TRUE(cloud) << "no person shape drawn";
	EXPECT_EQ(cloud->getName(), CAdaptiveOctoMap::kPersonShapesName);
	EXPECT_EQ(cloud->size(), before.size());
	EXPECT_EQ(cloud->getColor_u8(), avm::persons::kPersonColour);

	// A checkpoint keeps it: the copy holds the same shape and streams alike.
	CAdaptiveOctoMap copy;
	{
		mrpt::io::CMemoryStream buf;
		auto arch = mrpt::serialization::archiveFrom(buf);
		arch << map;
		buf.Seek(0);
		arch >> copy;
	}
	ASSERT_EQ(copy.personTracks().size(), 1u);
	EXPECT_EQ(copy.personTracks()[0].shape, before);
	EXPECT_EQ(avm::test::serializedBytes(copy), avm::test::serializedBytes(map));
}
