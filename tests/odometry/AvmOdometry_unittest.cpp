// The benchmark program end to end: outputs and clear failures.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "TestData.h"
#include "avm/io/Trajectory.h"

using namespace avm;

namespace
{
std::pair<int, std::string> run(const std::filesystem::path& dir, const std::string& args)
{
	const auto out = dir / "console.txt";
	const int rc =
		std::system((test::binary("avm-odometry").string() + " " + args + " > " + out.string() + " 2>&1").c_str());
	std::ifstream in(out);
	return {rc, std::string(std::istreambuf_iterator<char>(in), {})};
}
}  // namespace

TEST(AvmOdometry, WritesTrajectoryStatsAndTiming)
{
	const auto dir = test::scratchDir("avm-odometry");
	const auto traj = dir / "vo.txt", stats = dir / "vo.csv";
	const auto [rc, text] =
		run(dir, test::bonnRawlog().string() + " " + traj.string() + " --persons none --max-frames 20 --stats " +
					 stats.string() + " --config " + AVM_SOURCE_DIR + "/ini/odometry.ini");
	ASSERT_EQ(rc, 0) << text;
	EXPECT_NE(text.find("frames 20, lost 0"), std::string::npos) << text;
	EXPECT_NE(text.find("cpu  ms/frame: mean"), std::string::npos) << text;
	EXPECT_EQ(io::readTumTrajectory(traj).size(), 20u);
	std::ifstream csv(stats);
	const std::string all(std::istreambuf_iterator<char>(csv), {});
	EXPECT_EQ(std::count(all.begin(), all.end(), '\n'), 21);
	EXPECT_NE(all.find("\"tracking\""), std::string::npos);
}

TEST(AvmOdometry, WritesTheLoopsItVerifiedWithTheirErrorsAgainstGroundTruth)
{
	// Without --config: the built-in odometry, loop closing on. People left
	// unmasked drag the track off, and loops close.
	const auto dir = test::scratchDir("avm-odometry-loops");
	const auto loops = dir / "loops.csv";
	const auto [rc, text] = run(dir,
		test::bonnRawlog().string() + " " + (dir / "vo.txt").string() + " --persons none --loops " + loops.string());
	ASSERT_EQ(rc, 0) << text;
	std::size_t verified = 0, closed = 0;
	const auto said = text.find("loops ");
	ASSERT_NE(said, std::string::npos) << text;
	ASSERT_EQ(std::sscanf(text.c_str() + said, "loops %zu verified, %zu closed", &verified, &closed), 2) << text;
	EXPECT_GE(closed, 1u);
	EXPECT_NE(text.find("loop poses against ground truth"), std::string::npos) << text;

	std::ifstream csv(loops);
	std::string line;
	ASSERT_TRUE(std::getline(csv, line));
	EXPECT_EQ(line.rfind("frame,timestamp,candidate_frame,", 0), 0u) << line;
	std::size_t rows = 0, closedRows = 0;
	while (std::getline(csv, line))
	{
		++rows;
		std::vector<std::string> cells;
		std::stringstream row(line);
		for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
		ASSERT_EQ(cells.size(), 24u) << line;
		EXPECT_LT(std::stoul(cells[2]), std::stoul(cells[0])) << "the old keyframe comes first: " << line;
		closedRows += cells[5] == "1";
		// Both frames of sub300 have ground truth: every error is there, in metres and degrees.
		for (std::size_t c = 20; c < 24; ++c) EXPECT_GE(std::stod(cells[c]), 0.0) << line;
		EXPECT_LT(std::stod(cells[20]), 0.2) << line;
	}
	EXPECT_EQ(rows, verified);
	EXPECT_EQ(closedRows, closed);
}

TEST(AvmOdometry, BadInputNamesTheProblem)
{
	const auto dir = test::scratchDir("avm-odometry-bad");
	const auto rawlog = test::bonnRawlog().string(), out = (dir / "vo.txt").string();
	std::ofstream(dir / "bad.ini") << "[odometry]\nhuber_delta = -1\n";
	const auto cases = {std::make_pair((dir / "missing.rawlog").string() + " " + out + " --persons none",
							std::string("missing.rawlog")),
		std::make_pair(rawlog + " " + out + " --persons none -c " + (dir / "bad.ini").string(),
			std::string("[odometry] huber_delta = -1")),
		std::make_pair(rawlog + " " + out + " --model " + (dir / "none.onnx").string(), std::string("none.onnx")),
		std::make_pair(rawlog + " " + out + " --persons everyone", std::string("--persons"))};
	for (const auto& [args, expected] : cases)
	{
		const auto [rc, text] = run(dir, args);
		EXPECT_NE(rc, 0) << args;
		EXPECT_NE(text.find(expected), std::string::npos) << text;
	}
	EXPECT_FALSE(std::filesystem::exists(out));
}
