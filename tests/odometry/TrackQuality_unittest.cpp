// The pieces of a frame's TrackQuality: chi-square's quantiles, the inliers'
// spread over the image, the prediction's variance from recent deviations and
// the Mahalanobis agreement of the two.
#include <gtest/gtest.h>

#include "TrackQuality.h"

using namespace avm::odometry;
using namespace avm::odometry::detail;

TEST(TrackQuality, ChiSquareQuantilesWithThreeDegreesOfFreedom)
{
	// The tables' values (e.g. NIST/SEMATECH e-Handbook, 1.3.6.7.4).
	EXPECT_NEAR(chiSquare3Quantile(0.5), 2.366, 1e-3);
	EXPECT_NEAR(chiSquare3Quantile(0.99), 11.345, 1e-3);
	EXPECT_NEAR(chiSquare3Quantile(0.999), 16.266, 1e-3);
}

TEST(TrackQuality, SpreadIsTheShareOfTheImagesCellsWithAnInlier)
{
	FrameFeatures f;
	f.imageSize = cv::Size(640, 480);
	for (const auto& p : {cv::Point2f(10, 10), cv::Point2f(20, 30), cv::Point2f(630, 470), cv::Point2f(320, 240)})
		f.keypoints.emplace_back(p, 8.0f);
	// The first two share the top-left cell: three of 48 cells.
	EXPECT_DOUBLE_EQ(inlierSpread(f, {{0, 0}, {1, 1}, {2, 2}, {3, 3}}), 3.0 / 48);
	EXPECT_DOUBLE_EQ(inlierSpread(f, {{0, 0}}), 1.0 / 48);
	EXPECT_DOUBLE_EQ(inlierSpread(f, {}), 0.0);
}

TEST(TrackQuality, AgreementIsMeasuredInTheMetricOfBothUncertainties)
{
	// Deviations whose squares' median is chi-square(3)'s median times 1e-6:
	// a prediction of 1 mm per axis.
	const double d = std::sqrt(2.365974e-6);
	EXPECT_NEAR(predictionVariance({d / 2, d, 2 * d}), 1e-6, 1e-12);
	EXPECT_EQ(predictionVariance({}), 0.0);

	FrameFeatures f;
	f.imageSize = cv::Size(640, 480);
	const Eigen::Vector3d off(0.003, 0, 0);
	// A certain measurement: 3 mm off a 1 mm prediction is chi-square 9.
	const auto sure = qualityOf(f, {}, Eigen::Matrix3d::Zero(), off, 1e-6);
	EXPECT_NEAR(sure.motionChi2, 9.0, 1e-9);
	EXPECT_NEAR(sure.predictionSigma, 0.001, 1e-12);
	// A measurement as unsure as the prediction along x halves it; centreSigma is its worst axis.
	const Eigen::Matrix3d unsureAlongX = Eigen::Vector3d(1e-6, 0.25e-6, 0.25e-6).asDiagonal();
	const auto unsure = qualityOf(f, {}, unsureAlongX, off, 1e-6);
	EXPECT_NEAR(unsure.motionChi2, 4.5, 1e-9);
	EXPECT_NEAR(unsure.centreSigma, 0.001, 1e-12);
	// No prediction: nothing to agree with.
	EXPECT_EQ(qualityOf(f, {}, unsureAlongX, off, 0).motionChi2, 0.0);
	// A pose the inliers do not fix.
	const Eigen::Matrix3d unknown = Eigen::Matrix3d::Identity() * std::numeric_limits<double>::infinity();
	EXPECT_TRUE(std::isinf(qualityOf(f, {}, unknown, off, 1e-6).centreSigma));
}
