// The loop check on a synthetic straight path of keyframes 10 cm apart: a
// loop is refused beyond what it and the odometry since its candidate allow,
// waits for the loop of the keyframe before to agree, and moves the poses only
// for drift beyond one loop's own error, since two loops of consecutive
// keyframes against one place err alike (loop_sigma = 0.02 m, odometry_sigma
// = 0.01 m a keyframe: the built-in defaults).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "map/LoopClosing.h"

using namespace avm::odometry;
using namespace avm::odometry::detail;

namespace
{
constexpr int kNewest = 20;

/** T_cw of a camera whose centre is at `centre`, looking along the world's x axis. */
Eigen::Isometry3d cameraAt(const Eigen::Vector3d& centre)
{
	Eigen::Isometry3d T_wc = Eigen::Isometry3d::Identity();
	T_wc.translation() = centre;
	return T_wc.inverse();
}

Eigen::Vector3d centreOfKeyframe(int id) { return {0.1 * id, 0, 0}; }

class LoopCheck : public ::testing::Test
{
   protected:
	void SetUp() override
	{
		for (int id = 0; id <= kNewest; ++id) poses[id] = cameraAt(centreOfKeyframe(id));
	}

	/** A loop of keyframe `id` with candidate 0 that puts its camera centre
	 *  `shift` [m] sideways, its inliers giving it `inlierSigma` [m] on each axis. */
	LoopMeasurement loopAt(int id, double shift, double inlierSigma = 0) const
	{
		LoopMeasurement loop;
		loop.candidate = 0;
		loop.T_cw = cameraAt(centreOfKeyframe(id) + Eigen::Vector3d(0, shift, 0));
		loop.centreCovariance = Eigen::Matrix3d::Identity() * inlierSigma * inlierSigma;
		return loop;
	}

	LoopVerdict judge(double shift, std::optional<double> shiftBefore = std::nullopt, double inlierSigma = 0) const
	{
		std::vector<PoseGraphEdge> loops;
		if (shiftBefore)
			loops.push_back(loopEdge(loopAt(kNewest - 1, *shiftBefore, inlierSigma), kNewest - 1, poses, options));
		return judgeLoop(loopAt(kNewest, shift, inlierSigma), kNewest, loops, poses, options).verdict;
	}

	TOdometryOptions options;
	KeyframePoses poses;
};
}  // namespace

TEST_F(LoopCheck, ALoopBeyondItsOwnAndTheTracksUncertaintyIsRefused)
{
	// 20 keyframes of odometry and one loop: 0.165 m at 99 %.
	EXPECT_EQ(judge(0.5), LoopVerdict::Refused);
	EXPECT_EQ(judge(0.5, 0.5), LoopVerdict::Refused);
	EXPECT_EQ(judge(0.15, 0.15), LoopVerdict::Close);
}

TEST_F(LoopCheck, OneLoopAloneNeverMovesThePoses)
{
	EXPECT_EQ(judge(0.10), LoopVerdict::Unconfirmed);
	// The keyframe before saw the drift the other way: one of the two is off.
	EXPECT_EQ(judge(0.06, -0.06), LoopVerdict::Unconfirmed);
}

TEST_F(LoopCheck, TwoAgreeingLoopsCloseOnlyBeyondTheirOwnError)
{
	// Two loops agreeing: they err alike, so their mean's error is
	// loop_sigma's, and 99 % of it stays within 0.067 m (not loop_sigma /
	// sqrt(2)'s 0.048 m, as if they erred independently).
	EXPECT_EQ(judge(0.10, 0.09), LoopVerdict::Close);
	EXPECT_EQ(judge(0.03, 0.02), LoopVerdict::WithinOwnError);
	EXPECT_EQ(judge(0.052, 0.052), LoopVerdict::WithinOwnError);
	EXPECT_EQ(judge(0.066, 0.066), LoopVerdict::WithinOwnError);
	EXPECT_EQ(judge(0.068, 0.068), LoopVerdict::Close);
}

TEST_F(LoopCheck, EveryLoopIsJudgedByLoopSigmaWhateverItsInliers)
{
	// A loop's error on Bonn is about 10 times what its inliers alone give
	// (and weighing loops by it made the runs worse): inliers that fix the
	// centre to 4 mm, or not at all, change neither the verdict nor the
	// loop's weight in the pose graph.
	for (const double inlierSigma : {0.0, 0.004, std::numeric_limits<double>::infinity()})
	{
		EXPECT_EQ(judge(0.066, 0.066, inlierSigma), LoopVerdict::WithinOwnError) << inlierSigma;
		EXPECT_EQ(judge(0.068, 0.068, inlierSigma), LoopVerdict::Close) << inlierSigma;
		EXPECT_DOUBLE_EQ(
			loopEdge(loopAt(kNewest, 0.05, inlierSigma), kNewest, poses, options).sigmaTranslation, options.loop_sigma)
			<< inlierSigma;
	}
}
