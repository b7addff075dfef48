// Octree keys and the sets and boxes of them on small synthetic inputs,
// against octomap's own keys and plain sets: the packed keys, the grids
// ratio times finer and coarser, the scan's key sets, key ranges.
#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include <random>
#include <set>
#include <vector>

#include "KeySet.h"
#include "OcTreeKeys.h"

using namespace avm::detail;
using avm::centreOf;
using avm::keySpanAtDepth;
using avm::kKeyOffset;

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

TEST(KeySets, ABoxKeySetStartsEmptyAfterAScanOfFewKeys)
{
	// A scan of few keys in a large box is cleared word by word, not the
	// whole box: the next box, moved and of another size, must start empty
	// all the same.
	BoxKeySet box;
	std::mt19937 rng(7);
	octomap::OcTreeKey lo(30000, 30000, 30000), hi(30099, 30099, 30099);
	for (int scan = 0; scan < 4; scan++)
	{
		box.reset(lo, hi);
		EXPECT_TRUE(box.keys().empty());
		KeyRange{{lo[0], lo[1], lo[2]}, {hi[0] + 1u, hi[1] + 1u, hi[2] + 1u}}.forEachKey(
			[&](const octomap::OcTreeKey& k) { ASSERT_FALSE(box.contains(packKey(k))) << "scan " << scan; });
		std::uniform_int_distribution<int> dx(lo[0], hi[0]), dy(lo[1], hi[1]), dz(lo[2], hi[2]);
		std::set<std::uint64_t> reference;
		for (int i = 0; i < 300; i++)
		{
			const auto k = packKey(octomap::OcTreeKey(dx(rng), dy(rng), dz(rng)));
			ASSERT_EQ(box.insert(k), reference.insert(k).second);
		}
		EXPECT_EQ(std::set<std::uint64_t>(box.keys().begin(), box.keys().end()), reference);
		for (int i = 0; i < 3; i++)
		{
			lo[i] = static_cast<octomap::key_type>(lo[i] + 3 + i);
			hi[i] = static_cast<octomap::key_type>(hi[i] + 3 + i + (scan % 2 ? -9 : 7));
		}
	}
}

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
