// The .bt files the map writes: the bytes of octomap's own writeBinary
// (maximum-likelihood, pruned) for the same tree, written without changing the
// live tree and without a word on stderr, and read back the same way.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "BonnFrames.h"
#include "avm/plugin/CAdaptiveOctoMap.h"
#include "avm/maps/OcTreeFile.h"

using avm::CAdaptiveOctoMap;
using avm::Resolution;

namespace
{
std::string octomapWriteBinary(const octomap::OcTree& tree)
{
	octomap::OcTree copy(tree);
	std::ostringstream s;
	copy.writeBinary(s);
	return s.str();
}

std::string storedForm(const octomap::OcTree& tree)
{
	std::ostringstream s;
	tree.writeBinaryConst(s);
	return s.str();
}

/** What `run` prints on stderr (file descriptor 2: liboctomap prints with fprintf). */
template <typename F>
std::string stderrOf(F run)
{
	std::fflush(stderr);
	const auto file = avm::test::scratchDir("bt-stderr") / "stderr.txt";
	std::FILE* capture = std::fopen(file.c_str(), "w");
	const int saved = ::dup(2);
	::dup2(::fileno(capture), 2);
	run();
	std::fflush(stderr);
	::dup2(saved, 2);
	::close(saved);
	std::fclose(capture);
	return avm::test::fileBytes(file);
}

/** Bonn frames in the paper policy, switched half way: both trees hold a
 *  surface (the low tree the first half's, the high tree the rest). */
const CAdaptiveOctoMap& bonnMap()
{
	static const auto map = []
	{
		const auto frames = avm::test::bonnFrames(60, 6);
		CAdaptiveOctoMap::TCreationOptions creation;
		creation.low.resolution = 0.2;
		creation.high.resolution = 0.05;
		CAdaptiveOctoMap::TInsertionOptions insertion;
		insertion.switchPolicy = avm::SwitchPolicy::Paper;
		insertion.switchAtFraction = 0.5;
		auto m = std::make_unique<CAdaptiveOctoMap>(creation, insertion, CAdaptiveOctoMap::TLikelihoodOptions{});
		m->setExpectedFrameCount(frames.size());
		for (const auto& f : frames) m->insertObservation(*f.obs, f.pose);
		return m;
	}();
	return *map;
}
}  // namespace

TEST(OcTreeFile, TheMapWritesWhatOctomapsWriteBinaryWritesAndKeepsItsLogOdds)
{
	const auto& map = bonnMap();
	const auto* low = map.tree(Resolution::Low);
	const auto* high = map.tree(Resolution::High);
	ASSERT_TRUE(low && high);
	ASSERT_GT(high->getNumLeafNodes(), 1000u);
	const auto lowBefore = storedForm(*low), highBefore = storedForm(*high);

	const auto prefix = (avm::test::scratchDir("bt-files") / "bonn").string();
	// Written once before the capture: under UBSan, the .3Dscene beside the
	// .bt files reports MRPT's header-only alignment false positive
	// (tests/sanitizers/ubsan.supp), once per source location and process.
	map.saveMetricMapRepresentationToFile(prefix);
	const auto printed = stderrOf([&] { map.saveMetricMapRepresentationToFile(prefix); });
	EXPECT_EQ(printed, "") << "writing the .bt files printed on stderr";

	for (const auto& [suffix, tree] : {std::pair{"_low.bt", low}, std::pair{"_high.bt", high}})
	{
		const auto written = avm::test::fileBytes(prefix + suffix);
		EXPECT_TRUE(written == octomapWriteBinary(*tree)) << suffix << " differs from octomap's writeBinary";
		// The stored form (writeBinaryConst) is what avm wrote before: larger.
		EXPECT_LT(written.size(), storedForm(*tree).size()) << suffix;
		const auto stats = tree == low ? map.lowResolutionStats() : map.highResolutionStats();
		EXPECT_EQ(stats.binaryBytes, written.size()) << suffix;
	}
	EXPECT_TRUE(storedForm(*low) == lowBefore) << "writing changed the low tree's log-odds";
	EXPECT_TRUE(storedForm(*high) == highBefore) << "writing changed the high tree's log-odds";
}

TEST(OcTreeFile, SmallTreesAndAnEmptyOneAreWrittenAsOctomapWritesThem)
{
	octomap::OcTree empty(0.1);
	EXPECT_TRUE(avm::binaryTreeBytes(empty) == octomapWriteBinary(empty));
	// Eight free voxels of one parent, four of them seen free twice: the live
	// tree keeps them apart (different log-odds), the maximum-likelihood form
	// prunes them into one leaf.
	octomap::OcTree cube(0.1);
	for (float x : {0.05f, 0.15f})
		for (float y : {0.05f, 0.15f})
			for (float z : {0.05f, 0.15f})
			{
				cube.updateNode(octomap::point3d(x, y, z), false);
				if (x < 0.1f) cube.updateNode(octomap::point3d(x, y, z), false);
			}
	ASSERT_GT(cube.getNumLeafNodes(), 1u);
	const auto bytes = avm::binaryTreeBytes(cube);
	EXPECT_TRUE(bytes == octomapWriteBinary(cube));
	EXPECT_LT(bytes.size(), storedForm(cube).size());
	// An occupied voxel beside them keeps that parent apart.
	cube.updateNode(octomap::point3d(0.25f, 0.05f, 0.05f), true);
	EXPECT_TRUE(avm::binaryTreeBytes(cube) == octomapWriteBinary(cube));
}

TEST(OcTreeFile, ReadsBackWhatItWroteQuietlyAndNamesAFileThatIsNotATree)
{
	const auto* high = bonnMap().tree(Resolution::High);
	const auto file = avm::test::scratchDir("bt-read") / "high.bt";
	avm::writeBinaryTree(*high, file);
	std::unique_ptr<octomap::OcTree> back;
	EXPECT_EQ(stderrOf([&] { back = avm::readBinaryTree(file); }), "");
	ASSERT_TRUE(back);
	EXPECT_DOUBLE_EQ(back->getResolution(), 0.05);
	EXPECT_TRUE(avm::binaryTreeBytes(*back) == avm::test::fileBytes(file));

	const auto notATree = file.parent_path() / "not.bt";
	std::ofstream(notATree) << "hello\n";
	try
	{
		avm::readBinaryTree(notATree);
		ADD_FAILURE() << "no error for a file that is not a .bt";
	}
	catch (const std::runtime_error& e)
	{
		EXPECT_NE(std::string(e.what()).find(notATree.string()), std::string::npos) << e.what();
	}
}
