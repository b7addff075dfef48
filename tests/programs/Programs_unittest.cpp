// What every avm program does at its edges: --help and --version print and exit
// 0, and every error is one line "avm-<program>: error: ..." with a non-zero
// exit status, an option error naming the file (or --set), section, key and
// value, and why: a non-number, an empty value, an out-of-range value, a bad
// map option (thrown inside MRPT's CMultiMetricMap).
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "TestData.h"

using namespace avm;
namespace fs = std::filesystem;

namespace
{
const std::vector<std::string> kPrograms = {
	"avm-map", "avm-tum2rawlog", "avm-detect", "avm-odometry", "avm-eval", "avm-bench-map", "avm-paper", "avm-view"};

test::CommandResult run(const std::string& program, const std::string& arguments, const std::string& scratchName)
{
	return test::runCommand(test::binary(program).string() + " " + arguments, test::scratchDir(scratchName));
}

std::size_t lineCount(const std::string& text)
{
	std::size_t n = 0;
	for (char c : text) n += c == '\n';
	return n;
}

/** The program failed with exactly `line` on its output, beside the INFO
 *  lines of MRPT's logger (avm-map tells which detector it loaded). */
void expectOneLineError(const test::CommandResult& r, const std::string& line)
{
	EXPECT_EQ(r.exitCode, 1) << r.output;
	std::istringstream in(r.output);
	std::string rest;
	for (std::string l; std::getline(in, l);)
		if (l.find("|INFO |") == std::string::npos) rest += l + "\n";
	EXPECT_EQ(rest, line + "\n");
}

fs::path writeIni(const std::string& scratchName, const std::string& text)
{
	const fs::path ini = test::scratchDir(scratchName) / "bad.ini";
	std::ofstream(ini) << text;
	return ini;
}

/** An avm-map ini that gets as far as creating the map: no detector, a map. */
std::string mapIni(const std::string& creation, const std::string& insertion = "")
{
	return "[pipeline]\ndetect_every_n = 0\n[map]\nadaptiveOctoMap_count = 1\n"
		   "[map_adaptiveOctoMap_00_creationOpts]\n" +
		   creation + "\n[map_adaptiveOctoMap_00_insertOpts]\n" + insertion + "\n";
}

test::CommandResult runMap(const fs::path& ini, const std::string& extra = "")
{
	return test::runCommand(test::binary("avm-map").string() + " --config '" + ini.string() + "' --rawlog '" +
								(ini.parent_path() / "none.rawlog").string() + "' --out '" +
								(ini.parent_path() / "out").string() + "' " + extra,
		ini.parent_path());
}

class Program : public ::testing::TestWithParam<std::string>
{
};
}  // namespace

TEST_P(Program, HelpPrintsTheUsageAndExitsZero)
{
	const auto r = run(GetParam(), "--help", "help-" + GetParam());
	EXPECT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("USAGE"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("--verbose"), std::string::npos) << r.output;
	EXPECT_EQ(r.output.find(": error:"), std::string::npos) << r.output;
}

TEST_P(Program, VersionPrintsTheProjectVersionAndExitsZero)
{
	const auto r = run(GetParam(), "--version", "version-" + GetParam());
	EXPECT_EQ(r.exitCode, 0) << r.output;
	// project(VERSION) in CMakeLists.txt, and the commit of this checkout.
	EXPECT_NE(r.output.find("version: " AVM_VERSION " (git "), std::string::npos) << r.output;
	EXPECT_EQ(r.output.find(": error:"), std::string::npos) << r.output;
}

TEST_P(Program, AnUnknownArgumentIsOneLine)
{
	const auto r = run(GetParam(), "--no-such-option", "unknown-" + GetParam());
	// Not taken for the value of an unlabeled argument (a file named --no-such-option).
	expectOneLineError(r, GetParam() + ": error: --no-such-option: unknown argument (see " + GetParam() + " --help)");
}

INSTANTIATE_TEST_SUITE_P(AllPrograms, Program, ::testing::ValuesIn(kPrograms),
	[](const auto& info)
	{
		std::string name = info.param;
		for (auto& c : name)
			if (c == '-') c = '_';
		return name;
	});

TEST(ProgramErrors, MissingRequiredArgumentsAreNamed)
{
	expectOneLineError(run("avm-map", "", "missing-map"),
		"avm-map: error: missing required argument -r <RAWLOG>, -c <INI> (or --resume DIR; see avm-map --help)");
	expectOneLineError(run("avm-map", "--resume out -c x.ini", "resume-with-config"),
		"avm-map: error: --resume: --config is not allowed with it (the checkpoint holds the run's configuration, "
		"rawlog and folder)");
	const auto empty = test::scratchDir("resume-without-checkpoint");
	expectOneLineError(run("avm-map", "--resume '" + empty.string() + "'", "resume-nothing"),
		"avm-map: error: " + (empty / "checkpoint.bin").string() +
			": no checkpoint (the run finished, which removes it, or was stopped before its first frame, or " +
			empty.string() + " is not an avm-map output folder)");
	expectOneLineError(run("avm-tum2rawlog", "", "missing-tum"),
		"avm-tum2rawlog: error: missing required argument <DATASET_DIR>, <OUT.rawlog> (see avm-tum2rawlog --help)");
}

TEST(ProgramErrors, ABadArgumentValueIsOneLine)
{
	expectOneLineError(run("avm-tum2rawlog", "--compression abc in out.rawlog", "bad-argument"),
		"avm-tum2rawlog: error: --compression: Couldn't read argument value from string 'abc' (see avm-tum2rawlog "
		"--help)");
}

TEST(ProgramErrors, ANonNumberIsCalledOne)
{
	// Was "[odometry] num_features = 0: must be at least 50".
	const auto ini = writeIni("non-number", "[odometry]\nnum_features = abc\n");
	expectOneLineError(run("avm-odometry", "--config '" + ini.string() + "' in.rawlog out.txt", "non-number-run"),
		"avm-odometry: error: " + ini.string() + ": [odometry] num_features = abc: not a number");
}

TEST(ProgramErrors, AnEmptyValueIsCalledOne)
{
	const auto ini = writeIni("empty-value", "[detection]\nscore_threshold =\n");
	expectOneLineError(run("avm-detect", "--config '" + ini.string() + "' --image x.png", "empty-value-run"),
		"avm-detect: error: " + ini.string() + ": [detection] score_threshold = \"\": empty value, a number needed");
}

TEST(ProgramErrors, OutOfRangeValuesAreCalledSo)
{
	const auto tooBig = writeIni("out-of-range-int", "[odometry]\nnum_features = 1e12\n");
	expectOneLineError(run("avm-odometry", "--config '" + tooBig.string() + "' in.rawlog out.txt", "oor-int-run"),
		"avm-odometry: error: " + tooBig.string() +
			": [odometry] num_features = 1e12: out of range (-2147483648..2147483647)");
	const auto tooFew = writeIni("out-of-range-min", "[odometry]\nnum_features = 10\n");
	expectOneLineError(run("avm-odometry", "--config '" + tooFew.string() + "' in.rawlog out.txt", "oor-min-run"),
		"avm-odometry: error: " + tooFew.string() + ": [odometry] num_features = 10: must be at least 50");
	const auto fraction = writeIni("fraction", "[detection]\ninput_width = 3.5\n");
	expectOneLineError(run("avm-detect", "--config '" + fraction.string() + "' --image x.png", "fraction-run"),
		"avm-detect: error: " + fraction.string() + ": [detection] input_width = 3.5: not a whole number");
}

TEST(ProgramErrors, BadMapOptionsAreOneLineWithoutMrptsCallStack)
{
	const std::string creation = "[map_adaptiveOctoMap_00_creationOpts] ";
	struct Case
	{
		std::string ini, expected;
	};
	const std::vector<Case> cases = {
		{mapIni("low_resolution = -1"), creation + "low_resolution = -1: must be a positive length in metres"},
		{mapIni("low_probHit = 1.5"), creation + "low_probHit = 1.5: must be in (0.5, 1)"},
		{mapIni("low_resolution = abc"), creation + "low_resolution = abc: not a number"},
		{mapIni("", "switch_policy = sometimes"),
			"[map_adaptiveOctoMap_00_insertOpts] switch_policy = sometimes: expected paper or region"},
	};
	for (std::size_t i = 0; i < cases.size(); ++i)
	{
		const auto ini = writeIni("bad-map-" + std::to_string(i), cases[i].ini);
		expectOneLineError(runMap(ini), "avm-map: error: " + ini.string() + ": " + cases[i].expected);
	}
}

TEST(ProgramErrors, AValueGivenWithSetIsNamedSo)
{
	const auto ini = writeIni("set-value", mapIni(""));
	expectOneLineError(runMap(ini, "--set odometry:num_features=abc"),
		"avm-map: error: --set: [odometry] num_features = abc: not a number");
}

TEST(ProgramErrors, VerboseAddsMrptsCallStack)
{
	const auto ini = writeIni("verbose", mapIni("low_resolution = -1"));
	const auto r = runMap(ini, "--verbose");
	EXPECT_EQ(r.exitCode, 1);
	EXPECT_NE(r.output.find("\navm-map: error: " + ini.string() +
							": [map_adaptiveOctoMap_00_creationOpts] low_resolution = -1: must be a positive length in "
							"metres\n"),
		std::string::npos)
		<< r.output;
	EXPECT_NE(r.output.find("Call stack backtrace"), std::string::npos) << r.output;
	EXPECT_GT(lineCount(r.output), 3u);
}

// A good run prints through its logger (stdout) and progress bar only: no
// library's chatter on stderr (liboctomap printed " done." for every .bt it
// wrote, the reference maps' included), and the finished run's folder holds
// its outputs without the checkpoint it no longer needs.
TEST(ProgramOutput, AGoodAvmMapRunPrintsNothingOnStderrButLogLines)
{
	const auto dir = test::scratchDir("quiet-run");
	const auto out = dir / "run", err = dir / "stderr.txt";
	const auto r = test::runCommand(
		test::binary("avm-map").string() + " -c '" + AVM_SOURCE_DIR + "/ini/default.ini' -r '" +
			test::bonnRawlog().string() + "' -o '" + out.string() + "' --poses gt --set pipeline:max_frames=100" +
			" --set pipeline:reference_maps=true --set detection:model='" +
			test::sharedFile("models/yolox_nano.onnx").string() + "' 2> '" + err.string() + "'",
		dir);
	ASSERT_EQ(r.exitCode, 0) << r.output << test::fileBytes(err);
	ASSERT_TRUE(fs::exists(out / "map_high.bt"));
	EXPECT_NE(r.output.find("|INFO |avm-map]"), std::string::npos) << r.output;
	std::istringstream in(test::fileBytes(err));
	for (std::string line; std::getline(in, line);)
		EXPECT_TRUE(line.rfind("[", 0) == 0 && line.find("|avm-map] ") != std::string::npos)
			<< "not a log line on stderr: '" << line << "'";
	EXPECT_FALSE(fs::exists(out / "checkpoint.bin")) << "a finished run keeps its checkpoint";
}
