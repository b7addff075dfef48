#include <gtest/gtest.h>
#include <mrpt/core/bits_math.h>

#include <fstream>

#include "TestData.h"
#include "avm/io/Trajectory.h"

using namespace avm;
using mrpt::poses::CPose3D;

TEST(Trajectory, TumRoundTripKeepsPoses)
{
	const auto gt = io::readTumTrajectory(test::bonnDatasetDir() / "groundtruth.txt");
	ASSERT_GT(gt.size(), 300u);
	const auto file = test::scratchDir("trajectory") / "copy.txt";
	io::writeTumTrajectory(file, gt, "copy");
	const auto back = io::readTumTrajectory(file);
	ASSERT_EQ(back.size(), gt.size());
	for (std::size_t i = 0; i < gt.size(); ++i)
	{
		EXPECT_NEAR(back[i].timestamp, gt[i].timestamp, 1e-6);
		EXPECT_LT((back[i].pose - gt[i].pose).translation().norm(), 2e-6);
	}
}

TEST(Trajectory, InterpolationIsHalfwayInTranslationAndRotation)
{
	using mrpt::DEG2RAD;
	const io::Trajectory t = {{10.0, CPose3D(0, 0, 0, 0, 0, 0)}, {11.0, CPose3D(2, 0, 0, DEG2RAD(90.0), 0, 0)}};
	const auto mid = io::interpolatePose(t, 10.5, /*maxGap=*/2.0);
	ASSERT_TRUE(mid);
	EXPECT_NEAR(mid->x(), 1.0, 1e-12);
	EXPECT_NEAR(mid->yaw(), DEG2RAD(45.0), 1e-9);
	EXPECT_FALSE(io::interpolatePose(t, 9.99));
	EXPECT_FALSE(io::interpolatePose(t, 10.5, /*maxGap=*/0.5));
}

TEST(Trajectory, BadLinesNameFileAndLine)
{
	const auto dir = test::scratchDir("trajectory-bad");
	const auto check = [&](const std::string& text, const std::string& expected)
	{
		const auto file = dir / "t.txt";
		std::ofstream(file) << text;
		try
		{
			io::readTumTrajectory(file);
			ADD_FAILURE() << "accepted: " << text;
		}
		catch (const std::runtime_error& e)
		{
			EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
		}
	};
	check("# c\n1 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n", "t.txt:3: timestamps out of order");
	check("1 0 0 0 0 0 0\n", "t.txt:1: expected");
	check("1 nan 0 0 0 0 0 1\n", "t.txt:1: non-finite");
	check("1 0 0 0 0 0 0 3\n", "t.txt:1: quaternion is not of unit norm");
}

// Sessions that overlap in time each write a pose for the frames they share.
TEST(Trajectory, TwoPosesOfOneInstantAreRead)
{
	const auto file = test::scratchDir("trajectory-same-time") / "t.txt";
	std::ofstream(file) << "1 0 0 0 0 0 0 1\n1 0.5 0 0 0 0 0 1\n2 1 0 0 0 0 0 1\n";
	const auto t = io::readTumTrajectory(file);
	ASSERT_EQ(t.size(), 3u);
	EXPECT_EQ(t[0].timestamp, t[1].timestamp);
	EXPECT_DOUBLE_EQ(t[1].pose.x(), 0.5);
}
