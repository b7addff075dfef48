// The front end: grid-bucketed ORB features with depth, matching to landmarks
// (guided by a predicted pose, or by descriptor alone when there is none), and
// the initial pose by PnP RANSAC.
#pragma once

#include <mrpt/system/CTimeLogger.h>

#include <optional>
#include <unordered_map>
#include <vector>

#include "../Types.h"
#include "OrbExtractor.h"
#include "avm/odometry/TOdometryOptions.h"

namespace avm::odometry::detail
{
using LandmarkMap = std::unordered_map<int, Landmark>;

class FeatureFrontend
{
   public:
	explicit FeatureFrontend(const TOdometryOptions& options);

	/** Features of a grey image with their depth (metres, CV_32F). Pixels in
	 *  `excluded` boxes, without depth, or on a depth edge give none. With
	 *  `masked`, also the keypoints the boxes took away: those ORB finds on
	 *  the masked pixels with depth. That is for the live view only (a second
	 *  detection on the same person mask); the features are the same either way.
	 *  With `stageTimer`, ORB's own share (detection, description) is timed in it. */
	FrameFeatures extract(const cv::Mat& grey, const cv::Mat& depth, const io::DepthCamera& K,
		const std::vector<cv::Rect>& excluded, std::vector<cv::KeyPoint>* masked = nullptr,
		mrpt::system::CTimeLogger* stageTimer = nullptr) const;

	/** Each landmark projected with T_cw, matched to the best feature within
	 *  search_radius (distance and ratio tests; one landmark per feature). */
	std::vector<Match> matchByProjection(
		const FrameFeatures& frame, const LandmarkMap& landmarks, const Eigen::Isometry3d& T_cw) const;

	/** Descriptor matching against all landmarks (ratio test), for when no pose
	 *  prediction can be trusted. */
	std::vector<Match> matchByDescriptor(const FrameFeatures& frame, const LandmarkMap& landmarks) const;

	/** PnP RANSAC from `guess`; the pose and the inlier matches, or nothing
	 *  when there are too few. The pose is `guess` when OpenCV's pose does
	 *  not reproject its own inliers (a diverged final refinement). */
	struct PnpResult
	{
		Eigen::Isometry3d T_cw;
		std::vector<Match> inliers;
	};
	std::optional<PnpResult> solvePnp(const FrameFeatures& frame, const LandmarkMap& landmarks,
		const std::vector<Match>& matches, const Eigen::Isometry3d& guess) const;

   private:
	/** 255 where a person box masks the image: the whole grown box, or only
	 *  the pixels nearer than the box's background depth. */
	cv::Mat personMask(const cv::Mat& depth, const std::vector<cv::Rect>& boxes) const;

	const TOdometryOptions& m_options;
	OrbExtractor m_orb;
};
/** The frame's feature as an observation of `landmark`. */
Observation observationOf(const FrameFeatures& f, int feature, int landmark);
/** The frame's features of `matches` as observations of their landmarks. */
std::vector<Observation> observationsOf(const FrameFeatures& f, const std::vector<Match>& matches);

/** The matches that reproject within `maxError` [px] at pose T, and the sum
 *  of their squared errors. */
std::vector<Match> inliersAt(const Eigen::Isometry3d& T, const FrameFeatures& f, const std::vector<Match>& matches,
	const LandmarkMap& landmarks, double maxError, double& squaredErrors);

/** The world points of a keyframe's features, as landmarks numbered from
 *  `firstId` in feature order. */
void addKeyframePoints(const Eigen::Isometry3d& T_cw, const cv::Mat& descriptors,
	const std::vector<Eigen::Vector3d>& points, int firstId, LandmarkMap& out);
}  // namespace avm::odometry::detail
