// Space moving between the trees on small synthetic inputs: the surface
// sketch's bits, the tree operations (erasing a key range, setting many
// values), and a low voxel refined into the high tree or a high leaf
// coarsened into the low tree.
#include <gtest/gtest.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "OcTreeKeys.h"
#include "RegionSpace.h"
#include "SerializationCopy.h"
#include "SurfaceSketch.h"
#include "TreeOps.h"

using namespace avm;
using namespace avm::detail;

namespace
{
/** The sketch as serializeTo writes it. */
std::string bytesOf(const SurfaceSketch& sketch)
{
	mrpt::io::CMemoryStream buf;
	auto arch = mrpt::serialization::archiveFrom(buf);
	sketch.serializeTo(arch);
	return std::string(static_cast<const char*>(buf.getRawBufferData()), buf.getTotalBytesCount());
}
}  // namespace

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
	sketch.markScan({h}, {});
	sketch.markScan({h}, {});
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
	SurfaceSketch restored;
	test::copyBySerialization(grown, restored);
	ASSERT_EQ(restored.size(), 400u);
	EXPECT_EQ(restored.memoryBytes(), grown.memoryBytes());
	EXPECT_EQ(pruned.memoryBytes(), grown.memoryBytes());
	EXPECT_EQ(bytesOf(restored), bytesOf(grown));
	EXPECT_EQ(bytesOf(pruned), bytesOf(grown));
	EXPECT_EQ(grown.memoryBytes(), 400u * 16u) << "a low key and its 64 bits an entry";
}

// A scan's marks at once give the sketch that the same marks one at a time
// give: low voxels it held gain their bits, new ones join in key order.
TEST(SurfaceSketch, AScansMarksAtOnceAreTheMarksOneAtATime)
{
	const octomap::OcTree high(0.05);
	std::mt19937 rng(5);
	std::uniform_real_distribution<double> coord(-1.5, 1.5);
	SurfaceSketch atOnce(4), oneByOne(4);
	for (int i = 0; i < 200; i++)
	{
		const auto k = packKey(high.coordToKey(coord(rng), coord(rng), coord(rng)));
		atOnce.markScan({k}, {});
		oneByOne.markScan({k}, {});
	}
	std::vector<std::uint64_t> surface, seen;
	for (int i = 0; i < 3000; i++) surface.push_back(packKey(high.coordToKey(coord(rng), coord(rng), coord(rng))));
	for (int i = 0; i < 300; i++)
		seen.push_back(atOnce.lowKeyOf(packKey(high.coordToKey(coord(rng), coord(rng), 2 + coord(rng)))));
	const auto sizeBefore = atOnce.size();
	atOnce.markScan(surface, seen);
	for (const auto k : surface) oneByOne.markScan({k}, {});
	for (const auto k : seen) oneByOne.markScan({}, {k});
	EXPECT_GT(atOnce.size(), sizeBefore + 100) << "the scan brought new low voxels";
	EXPECT_EQ(bytesOf(atOnce), bytesOf(oneByOne));
	SurfaceSketch restored;
	test::copyBySerialization(atOnce, restored);
	EXPECT_EQ(restored.size(), atOnce.size()) << "read back: the entries are in key order";
}

// A frame updates the sketch around its camera only: every low voxel of the
// range and no other, wherever the others lie (beyond the range on one axis,
// on two, or at the ends of the key space).
TEST(SurfaceSketch, UpdatesReachTheLowVoxelsOfTheRangeAndNoOthers)
{
	SurfaceSketch sketch(4);
	std::vector<std::uint64_t> keys;
	for (unsigned x = 0; x < 12; x++)
		for (unsigned y = 0; y < 12; y++)
			for (unsigned z = 0; z < 12; z++)
				keys.push_back(packKey(octomap::OcTreeKey(kKeyOffset - 6 + x, kKeyOffset - 6 + y, kKeyOffset - 6 + z)));
	keys.push_back(packKey(octomap::OcTreeKey(0, 0, 0)));
	keys.push_back(packKey(octomap::OcTreeKey(kKeyEnd - 1, kKeyEnd - 1, kKeyEnd - 1)));
	keys.push_back(packKey(octomap::OcTreeKey(kKeyOffset, 0, kKeyOffset)));
	keys.push_back(packKey(octomap::OcTreeKey(kKeyOffset, kKeyOffset, kKeyEnd - 1)));
	for (const auto k : keys) sketch.set(k, 1);
	const auto range = KeyRange::around({0.13, -0.27, 0.23}, 0.5, 1 / 0.2);
	std::set<std::uint64_t> visited;
	sketch.updateBitsWithin(range,
		[&](std::uint64_t lowKey, std::uint64_t bits)
		{
			EXPECT_TRUE(visited.insert(lowKey).second) << "visited twice";
			return bits + 1;
		});
	std::size_t inside = 0;
	for (const auto k : keys)
	{
		const bool in = range.contains(unpackKey(k));
		inside += in;
		EXPECT_EQ(visited.count(k), in ? 1u : 0u)
			<< unpackKey(k)[0] << " " << unpackKey(k)[1] << " " << unpackKey(k)[2];
		EXPECT_EQ(sketch.take(k), in ? 2u : 1u);
	}
	EXPECT_EQ(inside, 6u * 6u * 6u) << "the range: 6 low voxels an axis";
	EXPECT_EQ(visited.size(), inside);
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
	sketch.markScan({packKey(surfaceKey)}, {});
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
	sketch.markScan({packKey(surfaceKey)}, {});
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
	sketch.markScan({}, {packKey(lowOctKey)});
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
