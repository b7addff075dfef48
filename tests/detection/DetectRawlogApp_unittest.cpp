// avm-detect over the Bonn rawlog as a user runs it.
#include <gtest/gtest.h>

#include <fstream>

#include "DetectionTestSupport.h"

namespace fs = std::filesystem;
using namespace avm;

TEST(AvmDetectRawlog, WritesLabelledRawlogDetectionsAndOneProgressLineInALog)
{
	const auto dir = test::scratchDir("det-app-rawlog");
	const auto out = dir / "labelled.rawlog";
	const auto r = test::runAvmDetect(test::yoloxModelArgument() + " --rawlog " + test::bonnRawlog().string() +
										  " --out " + out.string() + " --every 100",
		dir);
	ASSERT_EQ(r.exitCode, 0) << r.err;
	EXPECT_NE(r.out.find("frames:             300"), std::string::npos) << r.out;
	EXPECT_NE(r.out.find("detected frames:    3"), std::string::npos) << r.out;
	EXPECT_TRUE(fs::exists(out));
	EXPECT_TRUE(fs::exists(dir / "labelled_detections.txt"));
	EXPECT_TRUE(fs::is_symlink(dir / "labelled_Images"));
	// stderr is a file here: the bar is drawn once, complete.
	EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\r'), 1) << r.err;

	// A second run over the same output replaces it.
	EXPECT_EQ(test::runAvmDetect(test::yoloxModelArgument() + " --rawlog " + test::bonnRawlog().string() + " --out " +
									 out.string() + " --every 100 -q",
				  dir)
				  .exitCode,
		0);
}

TEST(AvmDetectRawlog, RawlogWithoutOutOrBenchIsAnError)
{
	const auto dir = test::scratchDir("det-app-rawlog-noout");
	const auto r = test::runAvmDetect(test::yoloxModelArgument() + " --rawlog " + test::bonnRawlog().string(), dir);
	EXPECT_NE(r.exitCode, 0);
	EXPECT_NE(r.err.find("--out"), std::string::npos) << r.err;
}

TEST(AvmDetectRawlog, BenchPrintsOneRowPerThreadCount)
{
	const auto dir = test::scratchDir("det-app-bench");
	const auto r = test::runAvmDetect(
		test::yoloxModelArgument() + " --rawlog " + test::bonnRawlog().string() + " --bench --bench-frames 3", dir);
	ASSERT_EQ(r.exitCode, 0) << r.err;
	EXPECT_NE(r.out.find("\n| 1 | 3 | "), std::string::npos) << r.out;
	EXPECT_NE(r.out.find("\n| 2 | 3 | "), std::string::npos) << r.out;
}
