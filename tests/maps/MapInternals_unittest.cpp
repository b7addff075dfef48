// The map's internal pieces on small synthetic inputs: octree keys, the key
// sets, the resolution policy's region space, the surface sketch, and the ray
// integrator through the map on a synthetic depth image.
#include <gtest/gtest.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <iterator>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "KeySet.h"
#include "OcTreeKeys.h"
#include "RegionSpace.h"
#include "ResolutionPolicy.h"
#include "SurfaceSketch.h"
#include "TreeOps.h"
#include "SerializationCopy.h"
#include "avm/plugin/CAdaptiveOctoMap.h"

using namespace avm;
using namespace avm::detail;
using mrpt::math::TBoundingBox;

TEST(OcTreeKeys, PackedKeysAreOctomapsKeys)
{
	std::mt19937 rng(7);
	std::uniform_real_distribution<double> coord(-50, 50);
	for (const double res : {0.05, 0.2, 1.5})
	{
		const octomap::OcTree tree(res);
		for (int i = 0; i < 2000; i++)
		{
			const double x = coord(rng), y = coord(rng), z = coord(rng);
			std::uint64_t packed = 0;
			ASSERT_TRUE(packedKeyOf(x, y, z, 1.0 / res, packed));
			const auto expected = tree.coordToKey(x, y, z);
			ASSERT_EQ(unpackKey(packed), expected) << x << " " << y << " " << z << " at " << res;
			ASSERT_EQ(packKey(expected), packed);
			const auto c = centreOf(packed, res);
			const auto e = tree.keyToCoord(expected);
			ASSERT_NEAR(c.x, e.x(), 1e-5);
			ASSERT_NEAR(c.z, e.z(), 1e-5);
		}
	}
	std::uint64_t packed = 0;
	EXPECT_FALSE(packedKeyOf(1e6, 0, 0, 1 / 0.05, packed)) << "beyond the tree";
	EXPECT_EQ(gridKeyOf(-0.2 + 1e-12, 0.2), kKeyOffset - 1);
	EXPECT_EQ(gridKeyOf(0.4 - 1e-12, 0.2), kKeyOffset + 2);
}

// A fine voxel's coarse voxel, its first fine key and its place in it, a
// packed key's steps and a node's span, against octomap's own keys of two
// trees ratio times finer than each other, on both sides of the origin.
TEST(OcTreeKeys, FinerAndCoarserKeysAreOctomapsKeysOfTheTwoGrids)
{
	std::mt19937 rng(11);
	std::uniform_real_distribution<double> coord(-5, 5);
	for (const unsigned ratio : {3u, 4u})
	{
		const octomap::OcTree coarse(0.2), fine(0.2 / ratio);
		for (int i = 0; i < 2000; i++)
		{
			const auto k = fine.coordToKey(coord(rng), coord(rng), coord(rng));
			const auto expected = coarse.coordToKey(fine.keyToCoord(k));
			ASSERT_EQ(unpackKey(coarserKeyOf(packKey(k), ratio)), expected);
			ASSERT_TRUE(KeyRange::finerKeysOf(expected, ratio).contains(k));
			for (int a = 0; a < 3; a++)
			{
				ASSERT_LT(placeInCoarser(k[a], ratio), ratio);
				ASSERT_EQ(firstFinerKey(expected[a], ratio) + placeInCoarser(k[a], ratio), k[a]);
				auto before = k;
				before[a]--;
				ASSERT_EQ(packKey(k) + packedStep(a, -1), packKey(before));
				ASSERT_EQ(packKey(before) + packedStep(a, 1), packKey(k));
			}
		}
	}
	const octomap::OcTree tree(0.05);
	for (unsigned depth = 0; depth <= tree.getTreeDepth(); depth++)
		EXPECT_DOUBLE_EQ(tree.getNodeSize(depth), 0.05 * keySpanAtDepth(depth)) << depth;
}

TEST(KeySets, InsertContainsClearAndGrow)
{
	KeySet set;
	std::set<std::uint64_t> reference;
	std::mt19937 rng(3);
	std::uniform_int_distribution<int> k(30000, 36000);
	for (int i = 0; i < 20000; i++)  // several times the initial capacity
	{
		const auto key = packKey(octomap::OcTreeKey(k(rng), k(rng), k(rng)));
		EXPECT_EQ(set.insert(key), reference.insert(key).second);
	}
	EXPECT_EQ(set.keys().size(), reference.size());
	for (const auto key : reference) ASSERT_TRUE(set.contains(key));
	set.clear();
	EXPECT_TRUE(set.keys().empty());
	EXPECT_FALSE(set.contains(*reference.begin()));
	// A few keys in the grown table: cleared key by key, not table-wide.
	for (const auto key : {*reference.begin(), *reference.rbegin()}) EXPECT_TRUE(set.insert(key));
	set.clear();
	for (const auto key : {*reference.begin(), *reference.rbegin()})
	{
		EXPECT_FALSE(set.contains(key));
		EXPECT_TRUE(set.insert(key)) << "gone after the clear";
	}

	// The dense box set answers as the hash set, inside its box; keys outside
	// are not stored.
	BoxKeySet box;
	box.reset(octomap::OcTreeKey(100, 100, 100), octomap::OcTreeKey(109, 109, 109));
	EXPECT_TRUE(box.insert(packKey(octomap::OcTreeKey(100, 105, 109))));
	EXPECT_FALSE(box.insert(packKey(octomap::OcTreeKey(100, 105, 109))));
	EXPECT_FALSE(box.insert(packKey(octomap::OcTreeKey(110, 105, 109))));
	EXPECT_TRUE(box.contains(packKey(octomap::OcTreeKey(100, 105, 109))));
	EXPECT_EQ(box.keys().size(), 1u);
	box.reset(octomap::OcTreeKey(100, 100, 100), octomap::OcTreeKey(109, 109, 109));
	EXPECT_FALSE(box.contains(packKey(octomap::OcTreeKey(100, 105, 109)))) << "a new scan starts empty";
}

// The bits of 4 x 4 x 4 voxels share a word: a box whose sides are no
// multiple of 4, keys on its faces and just outside it, and a second scan
// over another box must all answer as a plain set would.
TEST(KeySets, BoxKeySetAnswersAsASetWhateverTheBoxSides)
{
	BoxKeySet box;
	std::mt19937 rng(5);
	for (const unsigned side : {1u, 6u, 13u})
	{
		const octomap::OcTreeKey lo(1000, 2001, 3002), hi(1000 + side - 1, 2001 + side + 1, 3002 + 2 * side);
		box.reset(lo, hi);
		std::set<std::uint64_t> reference;
		std::uniform_int_distribution<int> dx(lo[0] - 2, hi[0] + 2), dy(lo[1] - 2, hi[1] + 2), dz(lo[2] - 2, hi[2] + 2);
		for (int i = 0; i < 3000; i++)
		{
			const octomap::OcTreeKey k(dx(rng), dy(rng), dz(rng));
			const bool inBox = KeyRange{{lo[0], lo[1], lo[2]}, {hi[0] + 1u, hi[1] + 1u, hi[2] + 1u}}.contains(k);
			const bool isNew = inBox && reference.insert(packKey(k)).second;
			ASSERT_EQ(box.insert(packKey(k)), isNew) << k[0] << " " << k[1] << " " << k[2];
		}
		EXPECT_EQ(std::set<std::uint64_t>(box.keys().begin(), box.keys().end()), reference);
		for (const auto k : reference) ASSERT_TRUE(box.contains(k));
		EXPECT_FALSE(box.contains(packKey(octomap::OcTreeKey(lo[0] - 1, lo[1], lo[2]))));
	}
}

namespace
{
std::size_t voxels(const TBoundingBox& b, double res)
{
	std::size_t n = 1;
	for (int i = 0; i < 3; i++) n *= static_cast<std::size_t>(std::lround((b.max[i] - b.min[i]) / res));
	return n;
}
}  // namespace

TEST(ResolutionPolicy, RegionSpaceIsTheExactUnionOfEachPersonsVoxels)
{
	ResolutionPolicy policy(SwitchPolicy::Region, 0.2);
	// Two people 4 m apart, boxes off the grid: grown to whole low voxels.
	policy.personSeen(1, TBoundingBox({0.05, 0.05, 0.0}, {0.55, 0.55, 1.7}), RegionLifetime::Follow, 0);
	policy.personSeen(2, TBoundingBox({4.05, 0.05, 0.0}, {4.55, 0.55, 1.7}), RegionLifetime::Follow, 0);
	const TBoundingBox aligned1({0.0, 0.0, 0.0}, {0.6, 0.6, 1.8});
	auto change = policy.takeSpaceChange();
	EXPECT_EQ(change.entered.size(), 2 * voxels(aligned1, 0.2));
	EXPECT_TRUE(change.left.empty());
	EXPECT_TRUE(policy.inHighResolutionSpace({0.1, 0.1, 1.7}));
	EXPECT_FALSE(policy.inHighResolutionSpace({2.0, 0.3, 1.0})) << "the space between them";
	EXPECT_TRUE(std::is_sorted(change.entered.begin(), change.entered.end()));

	// Follow: person 1 steps 0.4 m along x: the space it left leaves, the
	// space it reaches enters, the overlap stays.
	policy.personSeen(1, TBoundingBox({0.45, 0.05, 0.0}, {0.95, 0.55, 1.7}), RegionLifetime::Follow, 1);
	change = policy.takeSpaceChange();
	EXPECT_EQ(change.entered.size(), voxels(TBoundingBox({0.6, 0.0, 0.0}, {1.0, 0.6, 1.8}), 0.2));
	EXPECT_EQ(change.left.size(), voxels(TBoundingBox({0.0, 0.0, 0.0}, {0.4, 0.6, 1.8}), 0.2));
	EXPECT_EQ(policy.regions().size(), 2u);

	// Ending person 2 gives all of its space back; an unknown person nothing.
	EXPECT_TRUE(policy.endRegion(2));
	EXPECT_FALSE(policy.endRegion(2));
	EXPECT_FALSE(policy.endRegion(0)) << "fixed regions are not a person's";
	change = policy.takeSpaceChange();
	EXPECT_EQ(change.left.size(), voxels(aligned1, 0.2));
	EXPECT_TRUE(change.entered.empty());
}

namespace
{
/** The packed low keys of a grid-aligned box, counted by hand. */
std::set<std::uint64_t> lowKeysOf(const TBoundingBox& b, double res)
{
	std::set<std::uint64_t> keys;
	for (double x = b.min.x + res / 2; x < b.max.x; x += res)
		for (double y = b.min.y + res / 2; y < b.max.y; y += res)
			for (double z = b.min.z + res / 2; z < b.max.z; z += res)
			{
				std::uint64_t k = 0;
				EXPECT_TRUE(packedKeyOf(x, y, z, 1 / res, k));
				keys.insert(k);
			}
	return keys;
}
std::vector<std::uint64_t> minus(const std::set<std::uint64_t>& a, const std::set<std::uint64_t>& b)
{
	std::vector<std::uint64_t> out;
	std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
	return out;
}
std::set<std::uint64_t> joined(const std::set<std::uint64_t>& a, const std::set<std::uint64_t>& b)
{
	auto out = a;
	out.insert(b.begin(), b.end());
	return out;
}
}  // namespace

// The voxels themselves, not only how many: overlapping boxes share voxels,
// which stay while either box holds them; changes that undo each other before
// the trees catch up, and sightings that move nothing, report nothing.
TEST(ResolutionPolicy, SpaceChangesNameTheVoxelsThatEnterAndLeave)
{
	ResolutionPolicy policy(SwitchPolicy::Region, 0.2);
	const TBoundingBox a({0.0, 0.0, 0.0}, {0.6, 0.6, 1.8}), b({0.4, 0.2, 0.0}, {1.0, 0.8, 1.8}),
		c({2.0, 0.0, 0.0}, {2.6, 0.6, 1.8});
	const auto ka = lowKeysOf(a, 0.2), kb = lowKeysOf(b, 0.2), kc = lowKeysOf(c, 0.2);
	ASSERT_LT(joined(ka, kb).size(), ka.size() + kb.size()) << "a and b must overlap";

	policy.personSeen(1, a, RegionLifetime::Follow, 0);
	policy.personSeen(2, b, RegionLifetime::Follow, 0);
	auto change = policy.takeSpaceChange();
	EXPECT_EQ(change.entered, minus(joined(ka, kb), {}));
	EXPECT_TRUE(change.left.empty());

	change = policy.takeSpaceChange();
	EXPECT_TRUE(change.entered.empty() && change.left.empty()) << "nothing changed";
	policy.personSeen(1, a, RegionLifetime::Follow, 1);
	change = policy.takeSpaceChange();
	EXPECT_TRUE(change.entered.empty() && change.left.empty()) << "seen where it was";
	policy.personSeen(1, c, RegionLifetime::Follow, 2);
	policy.personSeen(1, a, RegionLifetime::Follow, 2);
	change = policy.takeSpaceChange();
	EXPECT_TRUE(change.entered.empty() && change.left.empty()) << "moved away and back before the trees caught up";

	// Person 1 moves from a to c: what b still holds of a stays.
	policy.personSeen(1, c, RegionLifetime::Follow, 3);
	change = policy.takeSpaceChange();
	EXPECT_EQ(change.entered, minus(kc, {}));
	EXPECT_EQ(change.left, minus(ka, kb));

	EXPECT_TRUE(policy.endRegion(2));
	change = policy.takeSpaceChange();
	EXPECT_TRUE(change.entered.empty());
	EXPECT_EQ(change.left, minus(kb, {}));

	EXPECT_TRUE(policy.endRegion(1));
	change = policy.takeSpaceChange();
	EXPECT_EQ(change.left, minus(kc, {}));
	EXPECT_FALSE(policy.hasSwitched());
	EXPECT_FALSE(policy.boxes().covers(*kc.begin(), 1)) << "no space left";
}

// What the integrator asks of every key: whether its voxel lies in the
// space, for the low grid and for grids 3 and 4 times finer, against the
// boxes themselves.
TEST(ResolutionPolicy, AVoxelIsCoveredExactlyWhenItsCentreIsInABox)
{
	ResolutionPolicy policy(SwitchPolicy::Region, 0.2);
	const std::vector<TBoundingBox> boxes{TBoundingBox({-0.6, -0.4, 0.0}, {0.2, 0.4, 1.0}),
		TBoundingBox({0.0, 0.2, 0.4}, {0.8, 1.0, 1.2}), TBoundingBox({3.0, -1.0, -0.2}, {3.4, -0.6, 0.2})};
	for (std::uint32_t i = 0; i < boxes.size(); i++) policy.personSeen(i + 1, boxes[i], RegionLifetime::Follow, 0);
	const auto& space = policy.boxes();
	for (const unsigned ratio : {1u, 3u, 4u})
	{
		const double res = 0.2 / ratio;
		std::size_t inside = 0;
		for (double x = -1.0 + res / 2; x < 4.0; x += res)
			for (double y = -1.4 + res / 2; y < 1.4; y += res)
				for (double z = -0.6 + res / 2; z < 1.6; z += res)
				{
					std::uint64_t k = 0;
					ASSERT_TRUE(packedKeyOf(x, y, z, 1 / res, k));
					const auto c = centreOf(k, res);
					const bool expected = std::any_of(boxes.begin(), boxes.end(),
						[&](const TBoundingBox& b) { return Region{b}.contains(c.x, c.y, c.z); });
					ASSERT_EQ(space.covers(k, ratio), expected)
						<< c.x << " " << c.y << " " << c.z << " ratio " << ratio;
					inside += expected;
				}
		EXPECT_GT(inside, 0u);
	}
}

TEST(ResolutionPolicy, PersistKeepsEveryPlaceAndMergesExactly)
{
	ResolutionPolicy policy(SwitchPolicy::Region, 0.2);
	policy.personSeen(1, TBoundingBox({0.0, 0.0, 0.0}, {0.6, 0.6, 1.8}), RegionLifetime::Persist, 0);
	policy.personSeen(1, TBoundingBox({0.1, 0.1, 0.1}, {0.5, 0.5, 1.7}), RegionLifetime::Persist, 1);
	EXPECT_EQ(policy.regions().at(0).boxes.size(), 1u) << "a box already covered adds nothing";
	policy.personSeen(1, TBoundingBox({0.6, 0.0, 0.0}, {1.2, 0.6, 1.8}), RegionLifetime::Persist, 2);
	ASSERT_EQ(policy.regions().at(0).boxes.size(), 1u) << "boxes that extend each other exactly merge";
	EXPECT_NEAR(policy.regions().at(0).boxes[0].max.x, 1.2, 1e-9);
	policy.personSeen(1, TBoundingBox({3.0, 3.0, 0.0}, {3.6, 3.6, 1.8}), RegionLifetime::Persist, 3);
	EXPECT_EQ(policy.regions().at(0).boxes.size(), 2u) << "a far box is a box of its own, not a bounding box";
	EXPECT_FALSE(policy.inHighResolutionSpace({2.0, 2.0, 1.0}));
}

TEST(ResolutionPolicy, PaperPolicySwitchesAtTheFirstPersonAndSerializes)
{
	ResolutionPolicy paper(SwitchPolicy::Paper, 1.5);
	EXPECT_FALSE(paper.hasSwitched());
	paper.personSeen(3, TBoundingBox({0, 0, 0}, {1, 1, 1}), RegionLifetime::Follow, 7);
	EXPECT_TRUE(paper.hasSwitched());
	EXPECT_EQ(paper.switchIndex(), std::optional<std::size_t>(7));
	EXPECT_TRUE(paper.regions().empty());
	EXPECT_THROW(ResolutionPolicy(SwitchPolicy::Region, 0.2).switchToHighResolution(0), std::logic_error);
	EXPECT_THROW(paper.addFixedRegion(TBoundingBox({0, 0, 0}, {0, 1, 1}), 0), std::invalid_argument);

	ResolutionPolicy region(SwitchPolicy::Region, 0.2);
	region.personSeen(1, TBoundingBox({0, 0, 0}, {0.6, 0.6, 1.8}), RegionLifetime::Persist, 0);
	region.personSeen(1, TBoundingBox({3, 3, 0}, {3.6, 3.6, 1.8}), RegionLifetime::Persist, 1);
	ResolutionPolicy restored(SwitchPolicy::Region, 0.2);
	test::copyBySerialization(region, restored);
	ASSERT_EQ(restored.regions().size(), 1u);
	EXPECT_EQ(restored.regions()[0].boxes.size(), 2u);
	EXPECT_TRUE(restored.takeSpaceChange().entered.empty()) << "the serialized trees already hold it";
}

// A checkpoint's policy goes on as the original: the next change reports the
// same space entering and leaving (what the trees must refine and coarsen).
// Read back with nothing marked as applied, it would report all of its space
// as entering and none as leaving: the space a region leaves would then stay
// in the high tree for good.
TEST(ResolutionPolicy, ARestoredPolicyReportsTheSameSpaceChangesAsTheOriginal)
{
	ResolutionPolicy original(SwitchPolicy::Region, 0.2);
	original.personSeen(1, TBoundingBox({0.05, 0.05, 0.0}, {0.55, 0.55, 1.7}), RegionLifetime::Follow, 0);
	original.personSeen(2, TBoundingBox({2.05, 0.05, 0.0}, {2.55, 0.55, 1.7}), RegionLifetime::Follow, 0);
	original.takeSpaceChange();  // the trees caught up, as after every insertion
	ResolutionPolicy restored(SwitchPolicy::Region, 0.2);
	test::copyBySerialization(original, restored);

	// Person 1 steps 0.4 m along x, person 2 leaves.
	for (auto* p : {&original, &restored})
	{
		p->personSeen(1, TBoundingBox({0.45, 0.05, 0.0}, {0.95, 0.55, 1.7}), RegionLifetime::Follow, 1);
		EXPECT_TRUE(p->endRegion(2));
	}
	const auto expected = original.takeSpaceChange(), got = restored.takeSpaceChange();
	EXPECT_FALSE(expected.entered.empty());
	EXPECT_FALSE(expected.left.empty());
	EXPECT_EQ(got.entered, expected.entered);
	EXPECT_EQ(got.left, expected.left);
}

TEST(SurfaceSketch, BitsNameTheHighVoxelsOfTheirLowVoxel)
{
	SurfaceSketch sketch(4);
	ASSERT_TRUE(sketch.usable());
	EXPECT_FALSE(SurfaceSketch(8).usable()) << "512 high voxels do not fit 64 bits";
	const octomap::OcTree low(0.2), high(0.05);
	std::mt19937 rng(11);
	std::uniform_real_distribution<double> coord(-20, 20);
	for (int i = 0; i < 2000; i++)
	{
		const double x = coord(rng), y = coord(rng), z = coord(rng);
		const auto h = packKey(high.coordToKey(x, y, z));
		ASSERT_EQ(unpackKey(sketch.lowKeyOf(h)), low.coordToKey(x, y, z)) << x << " " << y << " " << z;
		ASSERT_LT(sketch.bitOf(h), 64u);
		ASSERT_EQ(sketch.highKeyOf(sketch.lowKeyOf(h), sketch.bitOf(h)), h);
	}
	const auto h = packKey(high.coordToKey(-0.01, 0.01, 0.19));
	sketch.markHighVoxel(h);
	sketch.markHighVoxel(h);
	EXPECT_EQ(sketch.size(), 1u);
	const auto lowKey = sketch.lowKeyOf(h);
	sketch.prune([&](std::uint64_t k, std::uint64_t) { return k == lowKey; });
	EXPECT_EQ(sketch.take(lowKey), std::uint64_t(1) << sketch.bitOf(h));
	EXPECT_FALSE(sketch.take(lowKey)) << "taken";
}

// What the map reports of the sketch depends on its entries only, not on how
// its storage got there: a sketch that grew and lost entries (regions took
// them, a prune shrank it) and the same sketch read back from a checkpoint
// report the same bytes, and serialize to the same bytes.
TEST(SurfaceSketch, SameEntriesSameBytesWhateverTheHistory)
{
	SurfaceSketch grown(4);
	for (unsigned i = 0; i < 1000; i++)
		grown.set(packKey(octomap::OcTreeKey(kKeyOffset + i, kKeyOffset, kKeyOffset)), 1 + i);
	for (unsigned i = 0; i < 600; i++) grown.take(packKey(octomap::OcTreeKey(kKeyOffset + i, kKeyOffset, kKeyOffset)));
	SurfaceSketch pruned = grown;
	pruned.prune([](std::uint64_t, std::uint64_t) { return true; });
	const auto bytesOf = [](const SurfaceSketch& s)
	{
		mrpt::io::CMemoryStream buf;
		auto arch = mrpt::serialization::archiveFrom(buf);
		s.serializeTo(arch);
		return std::string(static_cast<const char*>(buf.getRawBufferData()), buf.getTotalBytesCount());
	};
	SurfaceSketch restored;
	test::copyBySerialization(grown, restored);
	ASSERT_EQ(restored.size(), 400u);
	EXPECT_EQ(restored.memoryBytes(), grown.memoryBytes());
	EXPECT_EQ(pruned.memoryBytes(), grown.memoryBytes());
	EXPECT_EQ(bytesOf(restored), bytesOf(grown));
	EXPECT_EQ(bytesOf(pruned), bytesOf(grown));
	EXPECT_EQ(grown.memoryBytes(), 400u * 16u) << "a low key and its 64 bits an entry";
}

namespace
{
/** A 160 x 120 depth image of a wall 3 m ahead (the plane X = 3 in the
 *  sensor frame), with (optionally) a 0.25 m square object 1.5 m ahead in the
 *  middle of the view. */
mrpt::obs::CObservation3DRangeScan wallScan(bool withObject)
{
	mrpt::obs::CObservation3DRangeScan obs;
	obs.hasRangeImage = true;
	obs.rangeImage.resize(120, 160);
	obs.rangeUnits = 0.001f;
	obs.cameraParams.ncols = 160;
	obs.cameraParams.nrows = 120;
	obs.cameraParams.setIntrinsicParamsFromValues(120, 120, 79.5, 59.5);
	obs.rangeImage.fill(3000);
	if (withObject)
		for (int v = 50; v < 70; v++)
			for (int u = 70; u < 90; u++) obs.rangeImage(v, u) = 1500;
	obs.sensorPose = mrpt::poses::CPose3D();
	return obs;
}

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

namespace
{
/** A tree at `res` whose cube of 8 x 8 x 8 finest voxels from `first` (a
 *  multiple of 8 on each axis) is one pruned occupied leaf. */
octomap::OcTree treeWithPrunedCube(double res, const octomap::OcTreeKey& first)
{
	octomap::OcTree tree(res);
	for (unsigned x = 0; x < 8; x++)
		for (unsigned y = 0; y < 8; y++)
			for (unsigned z = 0; z < 8; z++)
				tree.setNodeValue(octomap::OcTreeKey(first[0] + x, first[1] + y, first[2] + z), 2.0f);
	tree.prune();
	return tree;
}
std::size_t leafCount(const octomap::OcTree& tree)
{
	std::size_t n = 0;
	for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) n++;
	return n;
}
}  // namespace

TEST(KeyRange, TheCubeOfAPrunedLeafIsWalkedOnlyWhereItOverlaps)
{
	const KeyRange range{{10, 20, 30}, {13, 22, 40}};
	std::vector<octomap::OcTreeKey> expected, got;
	const octomap::OcTreeKey first(8, 16, 32);
	for (unsigned x = 0; x < 8; x++)
		for (unsigned y = 0; y < 8; y++)
			for (unsigned z = 0; z < 8; z++)
			{
				const octomap::OcTreeKey k(first[0] + x, first[1] + y, first[2] + z);
				if (range.contains(k)) expected.push_back(k);
			}
	range.forEachKeyOfCube(first, 8, [&](const octomap::OcTreeKey& k) { got.push_back(k); });
	EXPECT_EQ(got, expected);
	EXPECT_EQ(got.size(), 3u * 2u * 8u);
	got.clear();
	range.forEachKeyOfCube(octomap::OcTreeKey(0, 16, 32), 8, [&](const octomap::OcTreeKey& k) { got.push_back(k); });
	EXPECT_TRUE(got.empty()) << "no overlap";
}

// A range that cuts a pruned leaf: the leaf is split, exactly the finest
// voxels in the range go, the rest of the leaf stays with its value.
TEST(TreeOps, ErasingARangeThatCutsAPrunedLeafKeepsTheRestOfIt)
{
	const octomap::OcTreeKey first(kKeyOffset, kKeyOffset, kKeyOffset);
	auto tree = treeWithPrunedCube(0.05, first);
	ASSERT_EQ(leafCount(tree), 1u) << "the cube is one pruned leaf";
	// Reaches out of the cube in y.
	const KeyRange range{
		{kKeyOffset + 2, kKeyOffset + 4, kKeyOffset + 1}, {kKeyOffset + 4, kKeyOffset + 12, kKeyOffset + 2}};
	eraseKeyRange(tree, range);
	std::size_t kept = 0;
	for (unsigned x = 0; x < 8; x++)
		for (unsigned y = 0; y < 8; y++)
			for (unsigned z = 0; z < 8; z++)
			{
				const octomap::OcTreeKey k(first[0] + x, first[1] + y, first[2] + z);
				const auto* node = tree.search(k);
				ASSERT_EQ(node == nullptr, range.contains(k)) << x << " " << y << " " << z;
				if (node)
				{
					EXPECT_FLOAT_EQ(node->getLogOdds(), 2.0f);
					kept++;
				}
			}
	EXPECT_EQ(kept, 512u - 2u * 4u * 1u);
}

// A high leaf pruned over 2 x 2 x 2 low voxels folds into one of them: all of
// that low voxel's 64 high voxels are surface, and only its part of the leaf
// leaves the high tree.
TEST(RegionSpace, CoarseningTakesALowVoxelsPartOfAPrunedHighLeaf)
{
	const octomap::OcTreeKey first(kKeyOffset, kKeyOffset, kKeyOffset);
	auto high = treeWithPrunedCube(0.05, first);
	octomap::OcTree low(0.2);
	SurfaceSketch sketch(4);
	const auto lowKey = packKey(low.coordToKey(0.3, 0.1, 0.3));  // the low voxel [0.2, 0.4) x [0, 0.2) x [0.2, 0.4)
	coarsenIntoLowTree(high, low, lowKey, sketch);
	const auto* node = low.search(unpackKey(lowKey));
	ASSERT_NE(node, nullptr);
	EXPECT_TRUE(low.isNodeOccupied(node));
	EXPECT_EQ(sketch.take(lowKey), ~std::uint64_t(0)) << "every high voxel of the low voxel is surface";
	std::size_t kept = 0;
	for (auto it = high.begin_leafs(), end = high.end_leafs(); it != end; ++it)
	{
		const auto c = it.getCoordinate();
		EXPECT_FALSE(c.x() > 0.2 && c.x() < 0.4 && c.y() < 0.2 && c.z() > 0.2 && c.z() < 0.4) << "left the high tree";
		const std::size_t span = keySpanAtDepth(it.getDepth());
		kept += span * span * span;
	}
	EXPECT_EQ(kept, 512u - 64u);
}

namespace
{
std::string bytesOf(const octomap::OcTree& tree)
{
	std::ostringstream out;
	tree.write(out);
	return out.str();
}
}  // namespace

// setNodeValues against octomap's setNodeValue key by key: trees that
// already hold voxels (pruned blocks among them) get blocks of unknown keys
// and scattered ones; the two trees must be the same node for node. The
// first case completes a block next to equal pruned blocks, so the pruning
// climbs above it.
TEST(TreeOps, SetNodeValuesGivesOctomapsTreeKeyByKey)
{
	std::mt19937 rng(17);
	for (int trial = 0; trial < 20; trial++)
	{
		octomap::OcTree reference(0.05);
		std::uniform_int_distribution<int> near(kKeyOffset - 8, kKeyOffset + 23), value(0, 3);
		// Seven of the eight 8-cubes of a 16-cube, all at 1.0: pruned blocks.
		for (unsigned x = 0; x < 16; x++)
			for (unsigned y = 0; y < 16; y++)
				for (unsigned z = 0; z < 16; z++)
					if (x >= 8 || y >= 8 || z >= 8)
						reference.setNodeValue(
							octomap::OcTreeKey(kKeyOffset + x, kKeyOffset + y, kKeyOffset + z), 1.0f);
		for (int i = 0; i < 300 * (trial % 3); i++)
			reference.setNodeValue(octomap::OcTreeKey(near(rng), near(rng), near(rng)), 0.5f * value(rng) - 0.7f);
		reference.prune();
		std::vector<octomap::OcTreeKey> keys;
		auto addIfUnknown = [&](const octomap::OcTreeKey& k)
		{
			if (!reference.search(k) && std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
		};
		for (unsigned x = 0; x < 8; x++)
			for (unsigned y = 0; y < 8; y++)
				for (unsigned z = 0; z < 8; z++)
					addIfUnknown(octomap::OcTreeKey(kKeyOffset + x, kKeyOffset + y, kKeyOffset + z));
		for (int i = 0; i < 40 * trial; i++) addIfUnknown(octomap::OcTreeKey(near(rng), near(rng), near(rng)));
		auto batched = reference;
		const float v = trial == 0 ? 1.0f : 0.5f * value(rng) - 0.7f;
		for (const auto& k : keys) reference.setNodeValue(k, v);
		setNodeValues(batched, keys, v);
		ASSERT_EQ(batched.size(), reference.size()) << "trial " << trial;
		ASSERT_EQ(bytesOf(batched), bytesOf(reference)) << "trial " << trial;
		if (trial == 0)
		{
			EXPECT_EQ(leafCount(batched), 1u) << "the 16-cube pruned into one leaf";
		}
	}
}

// A surface the sketch remembers comes back into the high tree occupied, as a
// voxel hit once: the sketch says where, not how often, so looks through the
// voxel at high resolution clear it as they would a voxel of a single fine map
// hit once (three, with octomap's default sensor model).
TEST(RegionSpace, ASketchedSurfaceEntersTheHighTreeAsSeenOnce)
{
	octomap::OcTree low(0.2), high(0.05);
	SurfaceSketch sketch(4);
	const auto lowOctKey = low.coordToKey(0.1, 0.1, 0.1);
	for (int i = 0; i < 10; i++) low.updateNode(lowOctKey, true);  // seen often: clamped occupied
	const auto surfaceKey = high.coordToKey(0.125, 0.025, 0.075);
	sketch.markHighVoxel(packKey(surfaceKey));
	refineIntoHighTree(low, high, packKey(lowOctKey), &sketch);

	EXPECT_EQ(low.search(lowOctKey), nullptr) << "the low voxel left the low tree";
	EXPECT_EQ(high.getNumLeafNodes(), 1u) << "only the sketched voxel is known";
	const auto* node = high.search(surfaceKey);
	ASSERT_NE(node, nullptr);
	EXPECT_FLOAT_EQ(node->getLogOdds(), high.getProbHitLog());
	octomap::OcTree single(0.05);
	single.updateNode(surfaceKey, true);
	for (int miss = 1; miss <= 3; miss++)
	{
		high.updateNode(surfaceKey, false);
		single.updateNode(surfaceKey, false);
		EXPECT_EQ(high.isNodeOccupied(high.search(surfaceKey)), single.isNodeOccupied(single.search(surfaceKey)))
			<< miss << " misses";
	}
	EXPECT_FALSE(high.isNodeOccupied(high.search(surfaceKey)));
}

// A free low voxel can hold a surface the sketch kept (the edge of a table in
// a voxel of mostly air): that voxel comes back just occupied, the rest free.
TEST(RegionSpace, AFreeLowVoxelGivesBackItsSketchedSurfaceAndFreeSpace)
{
	octomap::OcTree low(0.2), high(0.05);
	SurfaceSketch sketch(4);
	const auto lowOctKey = low.coordToKey(0.1, 0.1, 0.1);
	for (int i = 0; i < 10; i++) low.updateNode(lowOctKey, false);
	const auto surfaceKey = high.coordToKey(0.125, 0.025, 0.075);
	sketch.markHighVoxel(packKey(surfaceKey));
	refineIntoHighTree(low, high, packKey(lowOctKey), &sketch);

	std::size_t occupied = 0, free = 0;
	for (auto it = high.begin_leafs(), end = high.end_leafs(); it != end; ++it)
	{
		const std::size_t span = keySpanAtDepth(it.getDepth()), voxels = span * span * span;
		(high.isNodeOccupied(*it) ? occupied : free) += voxels;
	}
	EXPECT_EQ(occupied, 1u);
	EXPECT_EQ(free, 63u);
	EXPECT_TRUE(high.isNodeOccupied(high.search(surfaceKey)));
	high.updateNode(surfaceKey, false);
	EXPECT_FALSE(high.isNodeOccupied(high.search(surfaceKey))) << "one miss frees it";
}

// An occupied low voxel whose sketched surfaces have all been seen through
// since holds no surface: nothing occupied comes back, not a solid block.
TEST(RegionSpace, ALowVoxelWhoseSurfaceWasSeenThroughGivesBackNoSurface)
{
	octomap::OcTree low(0.2), high(0.05);
	SurfaceSketch sketch(4);
	const auto lowOctKey = low.coordToKey(0.1, 0.1, 0.1);
	for (int i = 0; i < 10; i++) low.updateNode(lowOctKey, true);
	sketch.markLowVoxel(packKey(lowOctKey));
	refineIntoHighTree(low, high, packKey(lowOctKey), &sketch);
	EXPECT_EQ(high.size(), 0u);
	EXPECT_EQ(low.search(lowOctKey), nullptr);
}

// Without a sketch the whole low voxel comes down with its own confidence.
TEST(RegionSpace, AnOccupiedLowVoxelWithoutSketchKeepsItsConfidence)
{
	octomap::OcTree low(0.2), high(0.05);
	const auto lowOctKey = low.coordToKey(0.1, 0.1, 0.1);
	for (int i = 0; i < 10; i++) low.updateNode(lowOctKey, true);
	refineIntoHighTree(low, high, packKey(lowOctKey), nullptr);
	const auto* node = high.search(high.coordToKey(0.125, 0.025, 0.075));
	ASSERT_NE(node, nullptr);
	EXPECT_FLOAT_EQ(node->getLogOdds(), high.getClampingThresMaxLog());
}
