// Loop closing in the odometry: a new keyframe measured against an old
// place (map/LoopClosing.h), the pose graph's correction applied to the map
// keyframes, the local map and every frame, and the place joined.
#include <algorithm>
#include <cstdio>

#include "VisualOdometryImpl.h"

namespace avm::odometry
{
void VisualOdometry::Impl::closeLoop(const FrameFeatures& f, OdometryEstimate& e)
{
	mrpt::system::CTimeLoggerEntry timer(stageTimer, "6 loop closing");
	const Keyframe& newest = window.back();
	const auto loop =
		measureLoop(f, T_cw, newest.id - options.loop_min_separation, keyframeMap, frontend, backend, options);
	if (!loop) return;
	const Eigen::Isometry3d T_candidate = keyframeMap.find(loop->candidate)->T_cw;
	// The frame that made a keyframe is the first tracked against it.
	const auto made =
		std::find_if(frames.begin(), frames.end(), [&](const FramePose& p) { return p.keyframe == loop->candidate; });
	e.loop = LoopReport{std::size_t(made - frames.begin()), loop->inliers, toPose(T_candidate * loop->T_cw.inverse()),
		toPose(T_candidate * T_cw.inverse())};
	char said[160];
	std::snprintf(said, sizeof(said), "; loop with keyframe %d (%zu inliers, %.3f m, %.2f deg): ", loop->candidate,
		loop->inliers, loop->translation, loop->rotation);
	e.status += said;
	if (loop->translation > options.loop_max_correction)
	{
		e.status += "refused, beyond loop_max_correction";
		return;
	}
	loops.erase(std::remove_if(loops.begin(), loops.end(),
					[&](const PoseGraphEdge& l) { return !keyframeMap.find(l.from) || !keyframeMap.find(l.to); }),
		loops.end());
	// A loop moves the poses only when it shows more drift than its own error
	// and the loop of the keyframe before found the same.
	const bool drifted =
		loop->translation >= options.loop_min_correction || loop->rotation >= options.loop_min_rotation;
	const bool confirmed = drifted && confirmsLoopBefore(*loop, newest, loops, keyframeMap, options);
	loops.push_back(loopEdge(*loop, newest.id, keyframeMap, options));
	if (!confirmed)
	{
		e.status += drifted ? "kept, not confirmed by the keyframe before" : "kept, within its own error";
		return;
	}
	const auto poses = closeLoops(keyframeMap, loops, options);
	if (!poses)
	{
		e.status += "kept, the pose graph found no solution";
		return;
	}
	// The graph moved the place too; the loop measured the new keyframe
	// against the place as it was.
	const Eigen::Isometry3d T_loop = loop->T_cw * (T_candidate.inverse() * poses->at(loop->candidate));
	moveTo(*poses, T_loop);
	joinPlace(*loop);
	e.status += "closed, poses corrected";
	e.loopClosed = true;
}

void VisualOdometry::Impl::joinPlace(const LoopMeasurement& loop)
{
	// The new keyframe's features that matched the place now observe the
	// place's points: tracking goes on against the old map there, not against
	// the drifted copy the local map made of it.
	Keyframe& newest = window.back();
	const LandmarkMap place =
		placeAround(loop.candidate, newest.id - options.loop_min_separation, keyframeMap, options.loop_neighbours);
	for (const auto& m : loop.inlierMatches)
	{
		const auto o = std::find_if(newest.observations.begin(), newest.observations.end(),
			[&](const Observation& o) { return o.feature == m.feature; });
		if (o == newest.observations.end()) continue;
		const int id = nextLandmarkId++;
		landmarks[id] = place.at(m.landmark);
		landmarks[id].anchored = true;
		o->landmark = id;
	}
	forgetUnobservedLandmarks();
}

void VisualOdometry::Impl::moveTo(const std::map<int, Eigen::Isometry3d>& poses, const Eigen::Isometry3d& newestPose)
{
	// Each keyframe's correction D, T_cw(new) = T_cw(old) * D: a change of
	// the world frame that a frame tracked against the keyframe shares.
	std::map<int, Eigen::Isometry3d> corrections;
	for (const auto& [id, T] : poses) corrections[id] = keyframeMap.find(id)->T_cw.inverse() * T;
	// The local map moves rigidly with the frame that closed the loop (its
	// pose is where the next frames are tracked from), so that tracking goes
	// on against landmarks and window poses that agree with each other.
	const Eigen::Isometry3d D = T_cw.inverse() * newestPose;
	for (const auto& kf : window) corrections[kf.id] = D;
	const Eigen::Isometry3d Dinv = D.inverse();
	for (auto& [id, lm] : landmarks) lm.position = Dinv * lm.position;
	T_cw = T_cw * D;
	for (const auto& [id, c] : corrections) keyframeMap.updatePose(id, keyframeMap.find(id)->T_cw * c);
	// A frame whose keyframe has left the map moves with the next one kept.
	for (auto& frame : frames)
	{
		auto c = corrections.lower_bound(frame.keyframe);
		if (c == corrections.end()) c = std::prev(c);
		frame.T_cw = frame.T_cw * c->second;
	}
}
}  // namespace avm::odometry
