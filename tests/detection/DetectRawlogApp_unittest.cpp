// avm-detect over the Bonn rawlog as a user runs it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "TestData.h"

namespace fs = std::filesystem;
using namespace avm;

namespace
{
struct Run
{
	int exitCode;
	std::string out, err;
};

Run run(const std::string& args, const fs::path& dir)
{
	const auto out = dir / "stdout.txt", err = dir / "stderr.txt";
	const std::string cmd = test::binary("avm-detect").string() + " --model " +
							test::sharedFile("models/yolox_nano.onnx").string() + " " + args + " >" + out.string() +
							" 2>" + err.string();
	const int status = std::system(cmd.c_str());
	auto slurp = [](const fs::path& p) {
		std::ifstream f(p);
		std::stringstream s;
		s << f.rdbuf();
		return s.str();
	};
	return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}
}  // namespace

TEST(AvmDetectRawlog, WritesLabelledRawlogDetectionsAndOneProgressLineInALog)
{
	const auto dir = test::scratchDir("det-app-rawlog");
	const auto out = dir / "labelled.rawlog";
	const auto r = run("--rawlog " + test::bonnRawlog().string() + " --out " + out.string() + " --every 100", dir);
	ASSERT_EQ(r.exitCode, 0) << r.err;
	EXPECT_NE(r.out.find("frames:             300"), std::string::npos) << r.out;
	EXPECT_NE(r.out.find("detected frames:    3"), std::string::npos) << r.out;
	EXPECT_TRUE(fs::exists(out));
	EXPECT_TRUE(fs::exists(dir / "labelled_detections.txt"));
	EXPECT_TRUE(fs::is_symlink(dir / "labelled_Images"));
	// stderr is a file here: the bar is drawn once, complete.
	EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\r'), 1) << r.err;

	// A second run over the same output replaces it.
	EXPECT_EQ(run("--rawlog " + test::bonnRawlog().string() + " --out " + out.string() + " --every 100 -q", dir).exitCode, 0);
}

TEST(AvmDetectRawlog, RawlogWithoutOutOrBenchIsAnError)
{
	const auto dir = test::scratchDir("det-app-rawlog-noout");
	const auto r = run("--rawlog " + test::bonnRawlog().string(), dir);
	EXPECT_NE(r.exitCode, 0);
	EXPECT_NE(r.err.find("--out"), std::string::npos) << r.err;
}

TEST(AvmDetectRawlog, BenchPrintsOneRowPerThreadCount)
{
	const auto dir = test::scratchDir("det-app-bench");
	const auto r = run("--rawlog " + test::bonnRawlog().string() + " --bench --bench-frames 3", dir);
	ASSERT_EQ(r.exitCode, 0) << r.err;
	EXPECT_NE(r.out.find("\n| 1 | 3 | "), std::string::npos) << r.out;
	EXPECT_NE(r.out.find("\n| 2 | 3 | "), std::string::npos) << r.out;
}
