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
	// The place around the keyframe found (its neighbours' points too)
	// measures the pose as a loop is measured: more points over a wider view
	// than one keyframe's, so the session starts as well placed as the
	// odometry tracks.
	const int newestEarlier = session.firstKeyframe - 1;
	auto measured = measureLoop(f, r->T_cw, newestEarlier, keyframeMap, frontend, backend, options);
	if (!measured)
	{
		measured.emplace();
		measured->candidate = r->keyframe;
		measured->T_cw = r->T_cw;
		measured->inliers = r->inliers.size();
	}
	// Measured against the keyframe map's pose of the keyframe; the earlier
	// sessions' trajectory, and so their map, has it where the frame that
	// made it was tracked, apart by the window adjustment's offset.
	const Eigen::Isometry3d candidate = keyframeMap.find(measured->candidate)->T_cw;
	const std::size_t made = frameThatMade(measured->candidate);
	const Eigen::Isometry3d tracked = made < frames.size() ? frames[made].T_cw : candidate;
	restartLocalMap(f, measured->T_cw * candidate.inverse() * tracked);
	T_cw = keyframeMap.find(window.back().id)->T_cw;
	joinPlace(*measured, newestEarlier);
	session.joined[measured->candidate] = window.back().id;
	session.placing = false;
	PoseGraphEdge placement;
	placement.from = measured->candidate;
	placement.to = window.back().id;
	placement.T_to_from = T_cw * tracked.inverse();
	placement.sigmaTranslation = placement.sigmaRotation = options.loop_sigma;
	session.placements.push_back(placement);
	e.placed = e.tracked = e.keyframe = true;
	e.inliers = measured->inliers;
	char said[128];
	std::snprintf(said, sizeof(said), "placed in the earlier sessions' map on keyframe %d (%zu inliers)",
		measured->candidate, measured->inliers);
	e.status = said;
	e.pose = toPose(T_cw.inverse());
	return e;
}

void VisualOdometry::continueSession() { m_impl->continueSession(); }

std::size_t VisualOdometry::framesBeforeSession() const { return m_impl->session.firstFrame; }
}  // namespace avm::odometry
