// A session that continues a finished one (a robot's next run in the same
// building): the earlier sessions' keyframe map is where the new frames are
// looked up until one is placed there; from then on the session tracks,
// relocalises and closes loops on the whole map, the earlier keyframes and
// frames held fixed (VisualOdometry_loops.cpp).
#include <cstdio>

#include "VisualOdometryImpl.h"

namespace avm::odometry
{
void VisualOdometry::Impl::continueSession()
{
	session.firstKeyframe = nextKeyframeId;
	session.firstFrame = frames.size();
	session.placing = true;
	// Nothing of the last session's tracking carries over: not its local map,
	// not its motion, not a loss in progress.
	window.clear();
	landmarks.clear();
	velocity = Eigen::Isometry3d::Identity();
	velocityMeasured = false;
	recentDeviations.clear();
	lostFrames = lostFramesWithFeatures = 0;
}

OdometryEstimate VisualOdometry::Impl::place(const FrameFeatures& f)
{
	OdometryEstimate e;
	e.placed = false;
	if (int(f.keypoints.size()) < options.min_inliers)
	{
		e.status = "not placed: " + std::to_string(f.keypoints.size()) + " features with depth";
		return e;
	}
	mrpt::system::CTimeLoggerEntry timer(stageTimer, "5 relocalisation");
	const auto r = relocalise(f, nullptr);
	timer.stop();
	if (!r)
	{
		e.status = "not placed: no keyframe of the earlier sessions has " +
				   std::to_string(options.relocalisation_min_inliers) + " inliers with this frame";
		return e;
	}
	restartLocalMap(f, r->T_cw);
	T_cw = keyframeMap.find(window.back().id)->T_cw;
	session.placing = false;
	PoseGraphEdge placement;
	placement.from = r->keyframe;
	placement.to = window.back().id;
	placement.T_to_from = T_cw * keyframeMap.find(r->keyframe)->T_cw.inverse();
	placement.sigmaTranslation = placement.sigmaRotation = options.loop_sigma;
	session.placements.push_back(placement);
	e.placed = e.tracked = e.keyframe = true;
	e.inliers = r->inliers.size();
	e.reprojectionRmse = r->rmse;
	char said[128];
	std::snprintf(said, sizeof(said), "placed in the earlier sessions' map on keyframe %d (%zu inliers, %.2f px)",
		r->keyframe, r->inliers.size(), r->rmse);
	e.status = said;
	e.pose = toPose(T_cw.inverse());
	return e;
}

void VisualOdometry::continueSession() { m_impl->continueSession(); }

std::size_t VisualOdometry::framesBeforeSession() const { return m_impl->session.firstFrame; }
}  // namespace avm::odometry
