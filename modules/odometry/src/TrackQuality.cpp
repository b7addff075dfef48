#include "TrackQuality.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>

namespace avm::odometry::detail
{
namespace
{
/** The image's cells for the spread: about 80 px square at 640 x 480, a few
 *  features' worth each. */
constexpr int kSpreadColumns = 8, kSpreadRows = 6;
}  // namespace

double chiSquare3Quantile(double p)
{
	// The distribution function erf(sqrt(x/2)) - sqrt(2x/pi) exp(-x/2), increasing: bisection.
	const auto cdf = [](double x) { return std::erf(std::sqrt(x / 2)) - std::sqrt(2 * x / M_PI) * std::exp(-x / 2); };
	double low = 0, high = 1;
	while (cdf(high) < p) high *= 2;
	for (int i = 0; i < 60; ++i)
	{
		const double mid = (low + high) / 2;
		(cdf(mid) < p ? low : high) = mid;
	}
	return (low + high) / 2;
}

double inlierSpread(const FrameFeatures& f, const std::vector<Match>& inliers)
{
	if (f.imageSize.area() <= 0) return 0;
	std::vector<bool> occupied(kSpreadColumns * kSpreadRows, false);
	for (const auto& m : inliers)
	{
		const cv::Point2f& p = f.keypoints[m.feature].pt;
		const int column = std::clamp(int(p.x * kSpreadColumns / f.imageSize.width), 0, kSpreadColumns - 1);
		const int row = std::clamp(int(p.y * kSpreadRows / f.imageSize.height), 0, kSpreadRows - 1);
		occupied[row * kSpreadColumns + column] = true;
	}
	return double(std::count(occupied.begin(), occupied.end(), true)) / double(occupied.size());
}

double predictionVariance(const std::deque<double>& deviations)
{
	if (deviations.empty()) return 0;
	std::vector<double> squares;
	for (const double d : deviations) squares.push_back(d * d);
	std::nth_element(squares.begin(), squares.begin() + squares.size() / 2, squares.end());
	static const double median = chiSquare3Quantile(0.5);
	return squares[squares.size() / 2] / median;
}

TrackQuality qualityOf(const FrameFeatures& f, const std::vector<Match>& inliers,
	const Eigen::Matrix3d& centreCovariance, const Eigen::Vector3d& deviation, double predictionVariance)
{
	TrackQuality q;
	q.spread = inlierSpread(f, inliers);
	if (!centreCovariance.allFinite())
	{
		q.centreSigma = std::numeric_limits<double>::infinity();
		return q;
	}
	const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(centreCovariance, Eigen::EigenvaluesOnly);
	q.centreSigma = std::sqrt(std::max(0.0, eigen.eigenvalues().maxCoeff()));
	if (predictionVariance <= 0) return q;
	q.predictionSigma = std::sqrt(predictionVariance);
	const Eigen::Matrix3d both = centreCovariance + predictionVariance * Eigen::Matrix3d::Identity();
	q.motionChi2 = deviation.dot(both.ldlt().solve(deviation));
	return q;
}
}  // namespace avm::odometry::detail
