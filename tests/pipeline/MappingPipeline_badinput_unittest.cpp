// Bad input to avm-map: a clear error naming the problem, a non-zero exit, and
// no outputs in the output folder.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <fstream>
#include <sstream>

#include "TestData.h"

using namespace avm;
namespace fs = std::filesystem;

namespace
{
test::CommandResult runMap(const std::string& args, const fs::path& logDir)
{
	return test::runCommand(test::binary("avm-map").string() + " -q " + args, logDir);
}

/** ini/default.ini with ground-truth poses and no detector: the quick run. */
std::string quickConfig(const std::string& extra = "")
{
	return "-c " + (fs::path(AVM_SOURCE_DIR) / "ini/default.ini").string() +
		   " -s pipeline:detect_every_n=0 -s pipeline:pose_source=gt " + extra;
}

void expectFailureWithoutOutputs(const test::CommandResult& r, const fs::path& out, const std::string& expected)
{
	EXPECT_NE(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find(expected), std::string::npos) << "expected '" << expected << "' in: " << r.output;
	if (fs::is_directory(out))
	{
		EXPECT_TRUE(fs::is_empty(out)) << "outputs left in " << out;
	}
}
}  // namespace

TEST(MappingPipelineBadInput, MissingRawlog)
{
	const auto dir = test::scratchDir("map-bad-missing");
	const auto r =
		runMap(quickConfig() + " -r " + (dir / "none.rawlog").string() + " -o " + (dir / "out").string(), dir);
	expectFailureWithoutOutputs(r, dir / "out", "none.rawlog: rawlog not found");
}

TEST(MappingPipelineBadInput, TruncatedRawlog)
{
	const auto dir = test::scratchDir("map-bad-truncated");
	const auto src = test::bonnRawlog();
	const auto cut = dir / "cut.rawlog";
	fs::copy_file(src, cut);
	fs::resize_file(cut, fs::file_size(src) / 10);
	fs::create_directory_symlink(src.parent_path() / (src.stem().string() + "_Images"), dir / "cut_Images");
	const auto r = runMap(quickConfig() + " -r " + cut.string() + " -o " + (dir / "out").string(), dir);
	expectFailureWithoutOutputs(r, dir / "out", "cut.rawlog: corrupt or truncated rawlog");
}

TEST(MappingPipelineBadInput, MissingImageFolder)
{
	const auto dir = test::scratchDir("map-bad-images");
	fs::create_symlink(test::bonnRawlog(), dir / "alone.rawlog");
	const auto r =
		runMap(quickConfig() + " -r " + (dir / "alone.rawlog").string() + " -o " + (dir / "out").string(), dir);
	expectFailureWithoutOutputs(r, dir / "out", "alone_Images not found");
}

TEST(MappingPipelineBadInput, BadIniValueNamesSectionAndKey)
{
	const auto dir = test::scratchDir("map-bad-ini");
	const auto r = runMap(quickConfig("-s pipeline:detect_every_n=-2") + " -r " + test::bonnRawlog().string() + " -o " +
							  (dir / "out").string(),
		dir);
	expectFailureWithoutOutputs(r, dir / "out", "[pipeline] detect_every_n");
}

TEST(MappingPipelineBadInput, MissingIniFile)
{
	const auto dir = test::scratchDir("map-bad-ini-file");
	const auto r = runMap(
		"-c " + (dir / "nope.ini").string() + " -r " + test::bonnRawlog().string() + " -o " + (dir / "out").string(),
		dir);
	expectFailureWithoutOutputs(r, dir / "out", "nope.ini: ini file not found");
}

TEST(MappingPipelineBadInput, UnwritableOutputFolder)
{
	// Tests run as root, which ignores permissions: a folder under a regular
	// file cannot be created by anyone.
	const auto dir = test::scratchDir("map-bad-out");
	std::ofstream(dir / "a-file") << "x";
	const auto r =
		runMap(quickConfig() + " -r " + test::bonnRawlog().string() + " -o " + (dir / "a-file" / "out").string(), dir);
	expectFailureWithoutOutputs(r, dir / "a-file" / "out", "cannot create the output folder");
}

TEST(MappingPipelineBadInput, UnknownKeyIsWarnedAbout)
{
	const auto dir = test::scratchDir("map-unknown-key");
	const auto r = runMap(quickConfig("-s pipeline:max_frames=3 -s pipeline:detect_evry_n=2") + " -r " +
							  test::bonnRawlog().string() + " -o " + (dir / "out").string(),
		dir);
	EXPECT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("unknown key [pipeline] detect_evry_n"), std::string::npos) << r.output;
}

TEST(MappingPipelineBadInput, InsertOptsKnowsTheMapsAndThePersonLayersKeys)
{
	// _insertOpts feeds two options structs: a key is unknown only when neither reads it.
	const auto dir = test::scratchDir("map-unknown-insert-key");
	const std::string section = "map_adaptiveOctoMap_00_insertOpts";
	const auto r = runMap(quickConfig("-s pipeline:max_frames=3 -s " + section + ":region_margn=0.3 -s " + section +
									  ":track_gate=0.5 -s " + section + ":region_end_after_s=2") +
							  " -r " + test::bonnRawlog().string() + " -o " + (dir / "out").string(),
		dir);
	EXPECT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("unknown key [" + section + "] region_margn"), std::string::npos) << r.output;
	EXPECT_EQ(r.output.find("] track_gate"), std::string::npos) << r.output;
	EXPECT_EQ(r.output.find("] region_end_after_s"), std::string::npos) << r.output;
}
