// The reprojection-and-depth residual's hand-written Jacobians against central
// differences of the same residual, at no rotation, at a rotation within
// double epsilon of none (Ceres' first-order branch), at large ones, and for
// a point that slipped behind the camera (its depth held still).
#include <gtest/gtest.h>

#include <array>
#include <memory>

#include "backend/ReprojectionCost.h"

using namespace avm::odometry::detail;

namespace
{
void expectSameJacobians(const std::array<double, 6>& pose, const std::array<double, 3>& point)
{
	const avm::io::DepthCamera K{542.8, 542.6, 315.6, 237.8, 640, 480, true};
	Observation obs;
	obs.pixel = Eigen::Vector2d(320.5, 241.25);
	obs.depth = 1.7;
	const ReprojectionDepthCost cost(obs, K, 0.5);
	std::array<double, 3> residual;
	std::array<double, 18> poseJ;  // row-major 3x6
	std::array<double, 9> pointJ;  // row-major 3x3
	cost.evaluate(pose.data(), point.data(), residual.data(), poseJ.data(), pointJ.data());

	// Parameter k of the 9 (pose then point) moved by +-h: column k of the Jacobian.
	const double h = 1e-6;
	for (int k = 0; k < 9; ++k)
	{
		std::array<double, 9> plus, minus;
		for (int i = 0; i < 9; ++i) plus[i] = minus[i] = i < 6 ? pose[i] : point[i - 6];
		plus[k] += h;
		minus[k] -= h;
		std::array<double, 3> rPlus, rMinus;
		cost.evaluate(plus.data(), plus.data() + 6, rPlus.data(), nullptr, nullptr);
		cost.evaluate(minus.data(), minus.data() + 6, rMinus.data(), nullptr, nullptr);
		for (int r = 0; r < 3; ++r)
		{
			const double numeric = (rPlus[r] - rMinus[r]) / (2 * h);
			const double analytic = k < 6 ? poseJ[r * 6 + k] : pointJ[r * 3 + k - 6];
			EXPECT_NEAR(analytic, numeric, 1e-5 * (1 + std::abs(numeric))) << "row " << r << ", parameter " << k;
		}
	}

	// Through Ceres: the pose-and-point residual and the fixed-point one give the same numbers.
	const std::unique_ptr<ceres::CostFunction> both(ReprojectionDepthCost::create(obs, K, 0.5));
	const std::unique_ptr<ceres::CostFunction> fixed(
		ReprojectionDepthCost::createFixedPoint(obs, Eigen::Vector3d(point[0], point[1], point[2]), K, 0.5));
	const double* parameters[2] = {pose.data(), point.data()};
	std::array<double, 3> bothResidual, fixedResidual;
	std::array<double, 18> bothPoseJ, fixedPoseJ;
	std::array<double, 9> bothPointJ;
	double* bothJacobians[2] = {bothPoseJ.data(), bothPointJ.data()};
	double* fixedJacobians[1] = {fixedPoseJ.data()};
	ASSERT_TRUE(both->Evaluate(parameters, bothResidual.data(), bothJacobians));
	ASSERT_TRUE(fixed->Evaluate(parameters, fixedResidual.data(), fixedJacobians));
	EXPECT_EQ(bothResidual, residual);
	EXPECT_EQ(bothPoseJ, poseJ);
	EXPECT_EQ(bothPointJ, pointJ);
	EXPECT_EQ(fixedResidual, residual);
	EXPECT_EQ(fixedPoseJ, poseJ);
}
}  // namespace

TEST(ReprojectionCost, JacobiansAtNoRotation) { expectSameJacobians({0, 0, 0, 0.1, -0.2, 0.3}, {0.4, 0.3, 2.0}); }

TEST(ReprojectionCost, JacobiansWithinEpsilonOfNoRotation)
{
	expectSameJacobians({1e-9, -2e-9, 5e-9, 0.1, -0.2, 0.3}, {-0.5, 0.2, 1.5});
}

TEST(ReprojectionCost, JacobiansAtLargeRotations)
{
	expectSameJacobians({0.3, -0.2, 0.1, 0.05, 0.1, -0.2}, {0.4, 0.3, 2.0});
	expectSameJacobians({1.2, 2.0, -0.7, -0.3, 0.2, 1.0}, {1.5, -0.8, 2.5});
}

TEST(ReprojectionCost, APointBehindTheCameraKeepsItsDepthStill)
{
	// The point lands at z = -1 in the camera: clamped to 1 mm, its depth does not move with the pose.
	expectSameJacobians({0, 0, 0, 0, 0, -3.0}, {0.001, 0.002, 2.0});
}
