// The back end: robust (Huber) Ceres refinement of one pose against fixed
// landmarks, and a sliding-window bundle adjustment of keyframe poses and the
// landmarks they share.
#pragma once

#include <deque>
#include <optional>
#include <vector>

#include "../Types.h"
#include "../frontend/FeatureFrontend.h"
#include "avm/odometry/TOdometryOptions.h"

namespace avm::odometry::detail
{
/** A keyframe of the bundle adjustment's window: what it observed. Its pose
 *  is the map keyframe's of the same id (KeyframeMap, the one owner of
 *  keyframe poses). */
struct Keyframe
{
	int id = -1;  //!< the keyframe's id in the KeyframeMap
	std::vector<Observation> observations;
	/** Most inliers a frame tracked against the map while this was the newest keyframe. */
	std::size_t bestInliers = 0;
};

class CeresBackend
{
   public:
	explicit CeresBackend(const TOdometryOptions& options) : m_options(options) {}

	/** Where the camera centre should be, and how sure that is. */
	struct CentrePrior
	{
		Eigen::Vector3d centre;
		double sigma = 0;  //!< [m]
	};

	/** Refines T_cw in place from observations of fixed landmarks, and the
	 *  camera centre's prior if there is one. */
	void refinePose(Eigen::Isometry3d& T_cw, const std::vector<Observation>& observations, const LandmarkMap& landmarks,
		const io::DepthCamera& K, const std::optional<CentrePrior>& prior = std::nullopt) const;

	/** The end of every pose against fixed points (tracking, relocalisation,
	 *  a loop's measurement): PnP's pose refined from its inliers, then
	 *  refine_rounds - 1 times more from the matches that reproject within
	 *  ransac_reprojection at the last refined pose; those matches at the
	 *  end, and the covariance of the camera centre they give. Nothing when a
	 *  refinement diverged. */
	struct RefinedPose
	{
		Eigen::Isometry3d T_cw;
		std::vector<Match> inliers;
		double squaredErrors = 0;  //!< [px^2] summed over the inliers
		/** [m^2] Of the camera centre -R^T t, from the inliers alone (the
		 *  motion prior left out): the measurement's own uncertainty,
		 *  s^2 (J^T J)^-1 of the robust pose-only problem at T_cw, s^2 its
		 *  residuals' variance, carried to the centre by its Jacobian.
		 *  Infinite when the inliers do not fix the pose. */
		Eigen::Matrix3d centreCovariance = Eigen::Matrix3d::Zero();
	};
	std::optional<RefinedPose> refinePnp(const FrameFeatures& f, const FeatureFrontend::PnpResult& pnp,
		const std::vector<Match>& matches, const LandmarkMap& landmarks,
		const std::optional<CentrePrior>& prior = std::nullopt) const;

	/** Bundle adjustment over the window, whose poses (T_cw, one per
	 *  keyframe, in window order) it moves: the oldest keyframe is held fixed
	 *  (it anchors the gauge); landmarks seen by at least two keyframes move. */
	void bundleAdjust(const std::deque<Keyframe>& window, std::vector<Eigen::Isometry3d>& poses, LandmarkMap& landmarks,
		const io::DepthCamera& K) const;

   private:
	/** RefinedPose::centreCovariance of T_cw from these observations. */
	Eigen::Matrix3d centreCovariance(const Eigen::Isometry3d& T_cw, const std::vector<Observation>& observations,
		const LandmarkMap& landmarks, const io::DepthCamera& K) const;

	const TOdometryOptions& m_options;
};
}  // namespace avm::odometry::detail
