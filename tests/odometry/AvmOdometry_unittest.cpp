// The benchmark program end to end: outputs and clear failures.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <iterator>

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
