// avm-detect as a user runs it: exit codes, what it prints, files it writes.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <fstream>

#include "DetectionTestSupport.h"

namespace fs = std::filesystem;
using namespace avm;

namespace
{

std::size_t lines(const std::string& s) { return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n')); }
}  // namespace

TEST(AvmDetectApp, ImagePrintsOneLinePerPersonAndWritesTheAnnotatedPng)
{
	const auto dir = test::scratchDir("det-app-image");
	const auto png = dir / "bus-annotated.png";
	const auto r = test::runAvmDetect(test::yoloxModelArgument() + " --image " +
										  test::sharedFile("images/bus.jpg").string() + " --annotate " + png.string(),
		dir);
	EXPECT_EQ(r.exitCode, 0) << r.err;
	EXPECT_GE(lines(r.out), 3u) << r.out;
	EXPECT_EQ(r.out.rfind("person ", 0), 0u) << r.out;
	EXPECT_NE(r.err.find("detector: ONNX yolox model"), std::string::npos) << r.err;
	const cv::Mat annotated = cv::imread(png.string());
	EXPECT_EQ(annotated.size(), cv::Size(810, 1080));
}

TEST(AvmDetectApp, EmptyModelRunsHogAndSaysSo)
{
	const auto dir = test::scratchDir("det-app-hog");
	const auto r = test::runAvmDetect("--model '' --image " + test::sharedFile("images/person.jpg").string(), dir);
	EXPECT_EQ(r.exitCode, 0) << r.err;
	EXPECT_NE(r.err.find("HOG people detector"), std::string::npos) << r.err;
	EXPECT_GE(lines(r.out), 1u);
}

TEST(AvmDetectApp, BadInputsExitNonZeroNamingTheFile)
{
	const auto dir = test::scratchDir("det-app-bad");
	const auto image = test::sharedFile("images/person.jpg").string();
	auto r = test::runAvmDetect("--model " + (dir / "missing.onnx").string() + " --image " + image, dir);
	EXPECT_NE(r.exitCode, 0);
	EXPECT_NE(r.err.find("missing.onnx"), std::string::npos) << r.err;

	r = test::runAvmDetect("--model '' --image " + (dir / "nothing.jpg").string(), dir);
	EXPECT_NE(r.exitCode, 0);
	EXPECT_NE(r.err.find("nothing.jpg"), std::string::npos) << r.err;

	std::ofstream(dir / "bad.ini") << "[detection]\nscore_threshold = 7\n";
	r = test::runAvmDetect("--config " + (dir / "bad.ini").string() + " --image " + image, dir);
	EXPECT_NE(r.exitCode, 0);
	EXPECT_NE(r.err.find("[detection] score_threshold"), std::string::npos) << r.err;

	r = test::runAvmDetect("--config " + (dir / "none.ini").string() + " --image " + image, dir);
	EXPECT_NE(r.exitCode, 0);
	EXPECT_NE(r.err.find("none.ini"), std::string::npos) << r.err;
}

TEST(AvmDetectApp, UnknownIniKeyIsWarnedAbout)
{
	const auto dir = test::scratchDir("det-app-typo");
	std::ofstream(dir / "typo.ini") << "[detection]\nmodel = \"\"\nscore_treshold = 0.2\n";
	const auto r = test::runAvmDetect(
		"--config " + (dir / "typo.ini").string() + " --image " + test::sharedFile("images/person.jpg").string(), dir);
	EXPECT_EQ(r.exitCode, 0) << r.err;
	EXPECT_NE(r.err.find("unknown key [detection] score_treshold"), std::string::npos) << r.err;
}

TEST(AvmDetectApp, ProjectIniLoadsWithoutWarnings)
{
	const auto dir = test::scratchDir("det-app-ini");
	const auto r = test::runAvmDetect("--config " + (fs::path(AVM_SOURCE_DIR) / "ini/detect.ini").string() +
										  " --model '' --image " + test::sharedFile("images/person.jpg").string(),
		dir);
	EXPECT_EQ(r.exitCode, 0) << r.err;
	EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
}
