// Loop closing in the odometry: a new keyframe measured against an old
// place (map/LoopClosing.h), the pose graph's correction applied to the map
// keyframes, the local map and every frame, and the place joined.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <unordered_map>

#include "VisualOdometryImpl.h"
#include "avm/io/RgbdFrame.h"

namespace avm::odometry
{
void VisualOdometry::Impl::closeLoop(const FrameFeatures& f, OdometryEstimate& e)
{
	mrpt::system::CTimeLoggerEntry timer(stageTimer, "6 loop closing");
	const Keyframe& newest = window.back();
	const auto loop = measureLoop(f, T_cw, newest.id - options.loop_min_separation, keyframeMap, frontend, backend,
		options, [this](int keyframe) { return inJoinedPlace(keyframe); });
	if (!loop) return;
	const Eigen::Isometry3d T_candidate = keyframeMap.find(loop->candidate)->T_cw;
	e.loop = LoopReport{frameThatMade(loop->candidate), loop->inliers, toPose(T_candidate * loop->T_cw.inverse()),
		toPose(T_candidate * T_cw.inverse())};
	char said[120];
	std::snprintf(said, sizeof(said), "; loop with keyframe %d (%zu inliers, %.2f deg): ", loop->candidate,
		loop->inliers, loop->rotation);
	e.status += said;
	const auto outcome = considerLoop(*loop);
	e.status += outcome.said;
	e.loopClosed = outcome.closed;
}

VisualOdometry::LoopOutcome VisualOdometry::Impl::considerLoop(const LoopMeasurement& measured)
{
	const Keyframe& newest = window.back();
	loops.erase(std::remove_if(loops.begin(), loops.end(),
					[&](const PoseGraphEdge& l) { return !keyframeMap.find(l.from) || !keyframeMap.find(l.to); }),
		loops.end());
	const KeyframePoses tracked = trackedPoses();
	// The loop measured the camera against the place at the keyframe map's
	// poses; the trajectory has the candidate elsewhere, and the camera
	// relative to it is what the loop knows.
	LoopMeasurement loop = measured;
	loop.T_cw = measured.T_cw * keyframeMap.find(loop.candidate)->T_cw.inverse() * tracked.at(loop.candidate);
	const LoopJudgement judged = judgeLoop(loop, newest.id, loops, tracked, options);
	if (judged.verdict == LoopVerdict::Refused) return {false, "refused, " + judged.why};
	loops.push_back(loopEdge(loop, newest.id, tracked, options));
	if (judged.verdict == LoopVerdict::Unconfirmed) return {false, "kept, not confirmed (" + judged.why + ")"};
	if (judged.verdict == LoopVerdict::WithinOwnError)
	{
		// A continued session that sees an earlier session's place again, as
		// the track has it: tracking goes on against that place's points, so
		// that the session stays in the earlier sessions' map instead of
		// drifting beside it within the loops' error.
		const bool earlierSession = loop.candidate < session.firstKeyframe;
		if (earlierSession)
		{
			joinPlace(loop, newest.id - options.loop_min_separation);
			session.joined[loop.candidate] = newest.id;
		}
		return {false, std::string("kept, within the loops' own error") +
						   (earlierSession ? ", the earlier session's place joined" : "") + " (" + judged.why + ")"};
	}
	auto poses = closeLoops(tracked, loops, session.placements, session.firstKeyframe - 1, options);
	if (!poses) return {false, "kept, the pose graph found no solution"};
	// The earlier sessions' keyframes stay where they were: not even a
	// rounding of their poses.
	poses->erase(poses->begin(), poses->lower_bound(session.firstKeyframe));
	moveTo(tracked, *poses);
	joinPlace(loop, newest.id - options.loop_min_separation);
	return {true, "closed, poses corrected (" + judged.why + ")"};
}

std::size_t VisualOdometry::Impl::frameThatMade(int keyframe) const
{
	// The frame that made a keyframe is the first tracked against it.
	return std::size_t(
		std::find_if(frames.begin(), frames.end(), [&](const FramePose& p) { return p.keyframe == keyframe; }) -
		frames.begin());
}

VisualOdometry::LoopOutcome VisualOdometry::Impl::offerLoop(std::size_t oldFrame, const mrpt::poses::CPose3D& measured)
{
	if (window.empty() || frameThatMade(window.back().id) + 1 != frames.size())
		throw std::logic_error("offerLoop: the last frame processed did not make a keyframe");
	if (oldFrame >= frames.size() || frameThatMade(frames[oldFrame].keyframe) != oldFrame ||
		!keyframeMap.find(frames[oldFrame].keyframe))
		throw std::invalid_argument(
			"offerLoop: frame " + std::to_string(oldFrame) + " made no keyframe that the keyframe map still holds");
	if (!io::isFinite(measured)) throw std::invalid_argument("offerLoop: the measured pose is not finite");
	LoopMeasurement loop;
	loop.candidate = frames[oldFrame].keyframe;
	loop.T_cw = toIsometry(measured).inverse() * keyframeMap.find(loop.candidate)->T_cw;
	return considerLoop(measuredFrom(std::move(loop), T_cw));
}

void VisualOdometry::Impl::joinPlace(const LoopMeasurement& loop, int newestPlaceKeyframe)
{
	// The new keyframe's features that matched the place now observe the
	// place's points: tracking goes on against the old map there, not against
	// the drifted copy the local map made of it.
	if (loop.inlierMatches.empty()) return;
	Keyframe& newest = window.back();
	const LandmarkMap place = placeAround(loop.candidate, newestPlaceKeyframe, keyframeMap, options.loop_neighbours);
	// The place's points stand where the keyframe map has the candidate; the
	// loop was measured, and the graph has moved the trajectory, relative to
	// the candidate's trajectory pose, which the window bundle adjustment's
	// offset sets apart from it by centimetres: anchored there, the points
	// would pull the window away from the poses the graph gave it.
	const Eigen::Isometry3d toTrajectory =
		trackedPoses().at(loop.candidate).inverse() * keyframeMap.find(loop.candidate)->T_cw;
	// The local map's copy of a point the place holds is replaced by the
	// place's in the whole window, not only in the newest keyframe: kept
	// beside it, the copy would be one more point to project and match every
	// frame until its keyframes leave the window.
	std::unordered_map<int, int> replacedBy;
	for (const auto& m : loop.inlierMatches)
	{
		const auto o = std::find_if(newest.observations.begin(), newest.observations.end(),
			[&](const Observation& o) { return o.feature == m.feature; });
		if (o == newest.observations.end()) continue;
		const int id = nextLandmarkId++;
		landmarks[id] = place.at(m.landmark);
		landmarks[id].position = toTrajectory * landmarks[id].position;
		landmarks[id].anchored = true;
		replacedBy.emplace(o->landmark, id);
		o->landmark = id;
	}
	for (auto& keyframe : window)
		for (auto& o : keyframe.observations)
			if (const auto r = replacedBy.find(o.landmark); r != replacedBy.end()) o.landmark = r->second;
	forgetUnobservedLandmarks();
}

bool VisualOdometry::Impl::inJoinedPlace(int keyframe) const
{
	for (const auto& [place, by] : session.joined)
		if (by >= window.front().id && std::abs(keyframe - place) <= options.loop_neighbours) return true;
	return false;
}

KeyframePoses VisualOdometry::Impl::trackedPoses() const
{
	KeyframePoses poses;
	// The frame that made a keyframe is the first tracked against it; the
	// newest keyframe may be the current frame's, not in `frames` yet.
	for (const auto& frame : frames)
		if (keyframeMap.find(frame.keyframe)) poses.emplace(frame.keyframe, frame.T_cw);
	for (const auto& [id, kf] : keyframeMap.keyframes())
		if (!poses.count(id)) poses.emplace(id, id == window.back().id ? T_cw : kf.T_cw);
	return poses;
}

void VisualOdometry::Impl::moveTo(const KeyframePoses& from, const KeyframePoses& to)
{
	// Each keyframe's correction D, T_cw(new) = T_cw(old) * D: a change of
	// the world frame that a frame tracked against the keyframe shares, and
	// the keyframe map's pose of the keyframe with it.
	std::map<int, Eigen::Isometry3d> corrections;
	for (const auto& [id, T] : to) corrections[id] = from.at(id).inverse() * T;
	// The window's keyframes take the graph's poses like every other: the
	// graph weighs the loop against the odometry, the loop alone is a single
	// measurement. A landmark moves with the newest window keyframe that
	// observes it, the current frame with the newest keyframe, so that
	// tracking goes on against landmarks that agree with the poses they are
	// seen from.
	const Eigen::Isometry3d& newest = corrections.at(window.back().id);
	std::map<int, const Eigen::Isometry3d*> landmarkCorrection;
	for (const auto& kf : window)
		for (const auto& o : kf.observations)
			if (o.landmark >= 0) landmarkCorrection[o.landmark] = &corrections.at(kf.id);
	for (auto& [id, lm] : landmarks)
	{
		const auto c = landmarkCorrection.find(id);
		lm.position = (c == landmarkCorrection.end() ? newest : *c->second).inverse() * lm.position;
	}
	T_cw = T_cw * newest;
	for (const auto& [id, c] : corrections) keyframeMap.updatePose(id, keyframeMap.find(id)->T_cw * c);
	// A frame whose keyframe has left the map moves with the next one kept;
	// the earlier sessions' frames do not move.
	for (auto frame = frames.begin() + std::ptrdiff_t(session.firstFrame); frame != frames.end(); ++frame)
	{
		auto c = corrections.lower_bound(frame->keyframe);
		if (c == corrections.end()) c = std::prev(c);
		frame->T_cw = frame->T_cw * c->second;
	}
}
}  // namespace avm::odometry
