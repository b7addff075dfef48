// How good a frame's pose measurement is: the spread of its inliers over the
// image, its camera centre's covariance, and its agreement with the
// constant-velocity model in the metric of both uncertainties.
#pragma once

#include <deque>
#include <vector>

#include "Types.h"
#include "avm/odometry/VisualOdometry.h"

namespace avm::odometry::detail
{
/** The value chi-square with 3 degrees of freedom stays below with probability p, in (0, 1). */
double chiSquare3Quantile(double p);

/** TrackQuality::spread of the inliers' features. */
double inlierSpread(const FrameFeatures& f, const std::vector<Match>& inliers);

/** [m^2] The per-axis variance of the constant-velocity prediction's centre
 *  from the distances [m] of recent frames' centres from theirs: the median
 *  squared distance over chi-square(3)'s median, robust to the few bad frames
 *  among them. 0 for no distances. */
double predictionVariance(const std::deque<double>& deviations);

/** The TrackQuality of a frame whose centre is `deviation` [m] from the
 *  prediction, measured with `centreCovariance` [m^2] from `inliers`, beside
 *  a prediction of per-axis variance `predictionVariance` [m^2] (0: no
 *  prediction to judge by). */
TrackQuality qualityOf(const FrameFeatures& f, const std::vector<Match>& inliers,
	const Eigen::Matrix3d& centreCovariance, const Eigen::Vector3d& deviation, double predictionVariance);
}  // namespace avm::odometry::detail
