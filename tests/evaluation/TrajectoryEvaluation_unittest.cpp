#include <gtest/gtest.h>
#include <mrpt/core/bits_math.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <fstream>
#include <utility>

#include "TestData.h"
#include "avm/evaluation/TrajectoryEvaluation.h"

using namespace avm;
using mrpt::poses::CPose3D;

namespace
{
/** The Bonn ground truth (motion-capture body), a real, curved 6-DoF path. */
io::Trajectory bonnGroundTruth() { return io::readTumTrajectory(test::bonnDatasetDir() / "groundtruth.txt"); }
}  // namespace

TEST(TrajectoryEvaluation, RigidlyMovedCopyHasZeroErrorAndTheTransformIsRecovered)
{
	const auto gt = bonnGroundTruth();
	const CPose3D T(1.5, -2.0, 0.7, mrpt::DEG2RAD(40.0), mrpt::DEG2RAD(-15.0), mrpt::DEG2RAD(20.0));
	io::Trajectory moved = gt;
	for (auto& p : moved) p.pose = T + p.pose;

	const auto e = evaluation::evaluateTrajectory(moved, gt, {});
	EXPECT_EQ(e.matchedPairs, gt.size());
	EXPECT_LT(e.ate.rmse, 1e-6);
	EXPECT_LT(e.ate.max, 1e-6);
	EXPECT_LT(e.rpeTranslation.max, 1e-6);
	EXPECT_LT(e.rpeRotation.max, 1e-4);
	// gt = alignment (+) moved, so the alignment is T's inverse.
	const auto residual = e.alignment + T;
	EXPECT_LT(residual.translation().norm(), 1e-6);
	EXPECT_LT(std::abs(residual.yaw()) + std::abs(residual.pitch()) + std::abs(residual.roll()), 1e-6);
}

TEST(TrajectoryEvaluation, AccelerationIsExactOnAParabolaAndSeesFrameToFrameNoise)
{
	// p(t) = a t^2 / 2 at uneven times, and one timestamp repeated: the
	// central difference over uneven steps is exact on a parabola.
	const mrpt::math::TPoint3D a(0.3, -0.4, 1.2);  // [m/s^2], |a| = 1.3
	io::Trajectory parabola;
	for (const double t : {0.0, 0.03, 0.07, 0.07, 0.1, 0.16, 0.2})
		parabola.push_back({t, CPose3D(0.5 * a.x * t * t, 0.5 * a.y * t * t, 0.5 * a.z * t * t, 0, 0, 0)});
	const auto accelerations = evaluation::cameraAcceleration(parabola);
	ASSERT_EQ(accelerations.size(), 4u);
	for (const double value : accelerations) EXPECT_NEAR(value, 1.3, 1e-9);

	// The Bonn motion-capture path, moved rigidly and then shaken by 2 mm
	// from one pose to the next: the first does not change its acceleration,
	// the second adds about 4 * 2 mm / dt^2 to it.
	const auto gt = bonnGroundTruth();
	const CPose3D T(1.5, -2.0, 0.7, mrpt::DEG2RAD(40.0), mrpt::DEG2RAD(-15.0), mrpt::DEG2RAD(20.0));
	io::Trajectory moved = gt, shaken = gt;
	for (std::size_t k = 0; k < gt.size(); ++k)
	{
		moved[k].pose = T + gt[k].pose;
		shaken[k].pose.x_incr(k % 2 ? 0.002 : -0.002);
	}
	const auto still = evaluation::evaluateTrajectory(moved, gt, {});
	EXPECT_NEAR(still.acceleration.median, still.groundTruthAcceleration.median, 1e-6);
	EXPECT_EQ(still.acceleration.count, gt.size() - 2);
	// A hand-held camera: a fraction of g.
	EXPECT_LT(still.groundTruthAcceleration.median, 2.0);
	const double dt = (gt.back().timestamp - gt.front().timestamp) / double(gt.size() - 1);
	const auto noisy = evaluation::evaluateTrajectory(shaken, gt, {});
	EXPECT_GT(noisy.acceleration.median, 0.8 * 4 * 0.002 / (dt * dt)) << "mean time step " << dt << " s";
	EXPECT_NEAR(noisy.groundTruthAcceleration.median, still.groundTruthAcceleration.median, 1e-9);
}

TEST(TrajectoryEvaluation, KnownDriftGivesItsRateAsRpe)
{
	// A straight 1 m/s path sampled at 30 Hz. One estimate drifts sideways at
	// 0.05 m/s; another stays on the path but turns at 2 deg/s about its axis.
	io::Trajectory gt, sideways, turning;
	const double drift = 0.05, turn = 2.0;
	for (int i = 0; i <= 300; ++i)
	{
		const double t = 100.0 + i / 30.0, s = t - 100.0;
		gt.push_back({t, CPose3D(s, 0, 0, 0, 0, 0)});
		sideways.push_back({t + 0.005, CPose3D(s, drift * s, 0, 0, 0, 0)});
		turning.push_back({t - 0.005, CPose3D(s, 0, 0, 0, 0, mrpt::DEG2RAD(turn * s))});
	}
	const auto a = evaluation::evaluateTrajectory(sideways, gt, {});
	EXPECT_EQ(a.matchedPairs, gt.size());
	EXPECT_NEAR(a.rpeTranslation.median, drift, 1e-6);
	EXPECT_NEAR(a.rpeTranslation.max, drift, 1e-6);
	EXPECT_LT(a.rpeRotation.max, 1e-6);
	EXPECT_GT(a.rpeTranslation.count, 250u);

	const auto b = evaluation::evaluateTrajectory(turning, gt, {});
	EXPECT_NEAR(b.rpeRotation.median, turn, 1e-6);
	EXPECT_NEAR(b.rpeRotation.max, turn, 1e-6);
	EXPECT_LT(b.ate.max, 1e-9);  // positions are exact: rotation does not enter the ATE
}

// Sessions mapped in another order than they were recorded: an estimate and
// a ground truth whose halves come the later first are judged as in time order.
TEST(TrajectoryEvaluation, TheOrderOfThePosesDoesNotMatter)
{
	const auto gt = bonnGroundTruth();
	io::Trajectory estimate = gt;
	for (std::size_t i = 0; i < estimate.size(); ++i)
		estimate[i].pose =
			CPose3D(0.002 * std::sin(0.7 * double(i)), 0.001 * i / 100.0, 0, 0.001 * std::cos(0.3 * double(i)), 0, 0) +
			estimate[i].pose;
	const auto laterFirst = [](io::Trajectory t)
	{
		std::rotate(t.begin(), t.begin() + static_cast<std::ptrdiff_t>(t.size() / 2), t.end());
		return t;
	};
	const auto inOrder = evaluation::evaluateTrajectory(estimate, gt, {});
	for (const auto& [est, truth] : {std::pair{laterFirst(estimate), gt}, std::pair{estimate, laterFirst(gt)},
			 std::pair{laterFirst(estimate), laterFirst(gt)}})
	{
		const auto e = evaluation::evaluateTrajectory(est, truth, {});
		EXPECT_EQ(e.matchedPairs, gt.size());
		EXPECT_DOUBLE_EQ(e.ate.rmse, inOrder.ate.rmse);
		EXPECT_DOUBLE_EQ(e.rpeTranslation.rmse, inOrder.rpeTranslation.rmse);
		EXPECT_DOUBLE_EQ(e.frameToFrame.rmse, inOrder.frameToFrame.rmse);
		EXPECT_DOUBLE_EQ(e.acceleration.rmse, inOrder.acceleration.rmse);
	}
	EXPECT_GT(inOrder.ate.rmse, 1e-4) << "the estimate is not the ground truth";
}

TEST(TrajectoryEvaluation, AteOfAKnownOffsetAndStatistics)
{
	const auto s = evaluation::statisticsOf({3, 1, 2, 4});
	EXPECT_DOUBLE_EQ(s.mean, 2.5);
	EXPECT_DOUBLE_EQ(s.median, 2.5);
	EXPECT_DOUBLE_EQ(s.max, 4);
	EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(30.0 / 4));

	// A constant offset is removed by the alignment.
	const auto gt = bonnGroundTruth();
	io::Trajectory shifted = gt;
	for (auto& p : shifted) p.pose.x_incr(0.3);
	EXPECT_LT(evaluation::evaluateTrajectory(shifted, gt, {}).ate.rmse, 1e-6);

	// Scaling the path about its start is not rigid: the error is the scale
	// residue, well above zero, and the same for the tool and a hand check.
	io::Trajectory scaled = gt;
	for (auto& p : scaled)
	{
		const auto d = p.pose.translation() - gt.front().pose.translation();
		p.pose.x(gt.front().pose.x() + 1.5 * d.x);
		p.pose.y(gt.front().pose.y() + 1.5 * d.y);
		p.pose.z(gt.front().pose.z() + 1.5 * d.z);
	}
	const auto e = evaluation::evaluateTrajectory(scaled, gt, {});
	EXPECT_GT(e.ate.rmse, 0.02);
	// Reference: scaling by s about the centroid leaves (s-1)*|p - c| per point.
	mrpt::math::TPoint3D c(0, 0, 0);
	for (const auto& p : gt) c += p.pose.translation() * (1.0 / gt.size());
	double sq = 0;
	for (const auto& p : gt) sq += std::pow(0.5 * (p.pose.translation() - c).norm(), 2);
	EXPECT_NEAR(e.ate.rmse, std::sqrt(sq / gt.size()), 1e-6);
}

TEST(TrajectoryEvaluation, FrameRangeAndTimeTolerance)
{
	const auto gt = bonnGroundTruth();
	io::Trajectory est = gt;
	// Corrupt the poses after index 60: the first 60 stay exact.
	for (std::size_t i = 60; i < est.size(); ++i) est[i].pose.y_incr(0.01 * double(i - 60));
	evaluation::TEvaluationOptions opt;
	opt.maxFrames = 60;
	const auto first = evaluation::evaluateTrajectory(est, gt, opt);
	EXPECT_EQ(first.evaluatedPoses, 60u);
	EXPECT_EQ(first.matchedPairs, 60u);
	EXPECT_LT(first.ate.rmse, 1e-6);
	EXPECT_GT(evaluation::evaluateTrajectory(est, gt, {}).ate.rmse, 0.1);

	opt.firstFrame = 10;
	opt.maxFrames = 20;
	EXPECT_EQ(evaluation::evaluateTrajectory(est, gt, opt).evaluatedPoses, 20u);

	// Timestamps shifted beyond the tolerance match nothing: a clear error.
	io::Trajectory late = gt;
	for (auto& p : late) p.timestamp += 1000.0;
	EXPECT_THROW(evaluation::evaluateTrajectory(late, gt, {}), std::runtime_error);

	opt = {};
	opt.maxTimeDifference = -1;
	try
	{
		opt.validate("evaluation");
		ADD_FAILURE() << "negative tolerance accepted";
	}
	catch (const std::invalid_argument& e)
	{
		EXPECT_NE(std::string(e.what()).find("[evaluation] max_time_difference"), std::string::npos) << e.what();
	}
}

TEST(AvmEval, ReportsOnFilesAndFailsOnBadInput)
{
	const auto dir = test::scratchDir("avm-eval");
	const auto gtFile = test::bonnDatasetDir() / "groundtruth.txt";
	const auto run = [&](const std::string& args)
	{
		const auto out = dir / "out.txt";
		const int rc =
			std::system((test::binary("avm-eval").string() + " " + args + " > " + out.string() + " 2>&1").c_str());
		std::ifstream in(out);
		return std::make_pair(rc, std::string(std::istreambuf_iterator<char>(in), {}));
	};
	const auto [ok, text] = run(gtFile.string() + " " + gtFile.string() + " --max-frames 60");
	EXPECT_EQ(ok, 0) << text;
	EXPECT_NE(text.find("poses evaluated: 60"), std::string::npos) << text;
	EXPECT_NE(text.find("ATE        rmse 0.0000"), std::string::npos) << text;
	// The ground truth against itself: its acceleration line twice.
	const auto lineAfter = [&](const std::string& label)
	{
		const auto at = text.find(label);
		return at == std::string::npos ? std::string()
									   : text.substr(at + label.size(), text.find('\n', at) - at - label.size());
	};
	EXPECT_FALSE(lineAfter("accel      rmse").empty()) << text;
	EXPECT_EQ(lineAfter("accel      rmse"), lineAfter("accel gt   rmse")) << text;

	const auto [bad, msg] = run((dir / "missing.txt").string() + " " + gtFile.string());
	EXPECT_NE(bad, 0);
	EXPECT_NE(msg.find("missing.txt"), std::string::npos) << msg;
}
