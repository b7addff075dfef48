// Checkpoints of the odometry: every number of the tracking state written
// bit-exact, read back whole and checked before it replaces the state.
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "StateStream.h"
#include "VisualOdometryImpl.h"

namespace avm::odometry
{
namespace
{
/** Layout version of the saveState stream; change it with the layout. */
constexpr std::uint8_t stateVersion = 7;

void writeEdges(mrpt::serialization::CArchive& out, const std::vector<PoseGraphEdge>& edges)
{
	out << std::uint32_t(edges.size());
	for (const auto& e : edges)
	{
		out << std::int32_t(e.from) << std::int32_t(e.to);
		writePose(out, e.T_to_from);
		out << e.sigmaTranslation << e.sigmaRotation << e.robust;
	}
}

/** Pose graph edges between keyframes of ids below nextKeyframe. */
std::vector<PoseGraphEdge> readEdges(mrpt::serialization::CArchive& in, int nextKeyframe)
{
	std::vector<PoseGraphEdge> edges;
	for (auto n = read<std::uint32_t>(in); n > 0; --n)
	{
		PoseGraphEdge& e = edges.emplace_back();
		e.from = read<std::int32_t>(in);
		e.to = read<std::int32_t>(in);
		e.T_to_from = readPose(in);
		e.sigmaTranslation = read<double>(in);
		e.sigmaRotation = read<double>(in);
		e.robust = read<bool>(in);
		if (e.from < 0 || e.to < 0 || e.from >= nextKeyframe || e.to >= nextKeyframe || !(e.sigmaTranslation > 0) ||
			!(e.sigmaRotation > 0))
			throw badState("corrupt odometry state (pose graph constraint)");
	}
	return edges;
}
}  // namespace

void VisualOdometry::Impl::saveState(mrpt::serialization::CArchive& out) const
{
	out << stateVersion;
	writePose(out, T_cw);
	writePose(out, velocity);
	out << velocityMeasured << std::uint32_t(recentDeviations.size());
	for (const double d : recentDeviations) out << d;
	out << std::int32_t(nextLandmarkId);
	// In id order, so that one state always gives the same bytes.
	std::vector<int> ids;
	ids.reserve(landmarks.size());
	for (const auto& [id, lm] : landmarks) ids.push_back(id);
	std::sort(ids.begin(), ids.end());
	out << std::uint32_t(ids.size());
	for (const int id : ids)
	{
		const Landmark& lm = landmarks.at(id);
		out << std::int32_t(id);
		write(out, lm.position.data(), 3);
		write(out, lm.descriptor.data(), lm.descriptor.size());
		out << lm.anchored;
	}
	out << std::uint32_t(window.size());
	for (const auto& kf : window)
	{
		out << std::int32_t(kf.id);
		out << std::uint64_t(kf.bestInliers) << std::uint32_t(kf.observations.size());
		for (const auto& o : kf.observations)
		{
			out << std::int32_t(o.landmark) << std::int32_t(o.feature);
			write(out, o.pixel.data(), 2);
			out << o.depth;
		}
	}
	out << std::int32_t(nextKeyframeId) << std::int32_t(lostFrames) << std::int32_t(lostFramesWithFeatures);
	keyframeMap.save(out);
	writeEdges(out, loops);
	out << std::uint64_t(frames.size());
	for (const auto& frame : frames)
	{
		out << std::int32_t(frame.keyframe);
		writePose(out, frame.T_cw);
		out << frame.timestamp;
	}
	out << std::int32_t(session.firstKeyframe) << std::uint64_t(session.firstFrame) << session.placing;
	writeEdges(out, session.placements);
	out << std::uint32_t(session.joined.size());
	for (const auto& [place, by] : session.joined) out << std::int32_t(place) << std::int32_t(by);
}

void VisualOdometry::Impl::loadState(mrpt::serialization::CArchive& in)
{
	// Everything is read and checked before any of it replaces the state.
	if (const auto version = read<std::uint8_t>(in); version != stateVersion)
		throw badState("odometry state of version " + std::to_string(version) + ", this build reads version " +
					   std::to_string(stateVersion));
	const Eigen::Isometry3d pose = readPose(in), motion = readPose(in);
	const bool motionMeasured = read<bool>(in);
	std::deque<double> deviations;
	for (auto n = read<std::uint32_t>(in); n > 0; --n)
		if (deviations.emplace_back(read<double>(in));
			!(deviations.back() >= 0) || deviations.size() > kDeviationHistory)
			throw badState("corrupt odometry state (motion deviations)");
	const int nextId = read<std::int32_t>(in);
	LandmarkMap map;
	for (auto n = read<std::uint32_t>(in); n > 0; --n)
	{
		const int id = read<std::int32_t>(in);
		Landmark lm;
		read(in, lm.position.data(), 3);
		read(in, lm.descriptor.data(), lm.descriptor.size());
		lm.anchored = read<bool>(in);
		if (id < 0 || id >= nextId || !lm.position.allFinite() || !map.emplace(id, lm).second)
			throw badState("corrupt odometry state (landmark " + std::to_string(id) + ")");
	}
	std::deque<Keyframe> keyframes;
	for (auto n = read<std::uint32_t>(in); n > 0; --n)
	{
		Keyframe& kf = keyframes.emplace_back();
		kf.id = read<std::int32_t>(in);
		kf.bestInliers = read<std::uint64_t>(in);
		for (auto m = read<std::uint32_t>(in); m > 0; --m)
		{
			Observation& o = kf.observations.emplace_back();
			o.landmark = read<std::int32_t>(in);
			o.feature = read<std::int32_t>(in);
			read(in, o.pixel.data(), 2);
			o.depth = read<double>(in);
			if (!map.count(o.landmark))
				throw badState("corrupt odometry state (a keyframe observes the unknown landmark " +
							   std::to_string(o.landmark) + ")");
		}
	}
	const int nextKeyframe = read<std::int32_t>(in);
	const int lost = read<std::int32_t>(in), lostWithFeatures = read<std::int32_t>(in);
	KeyframeMap places(options);
	places.load(in);
	std::vector<PoseGraphEdge> loopEdges = readEdges(in, nextKeyframe);
	std::vector<FramePose> framePoses;
	for (auto n = read<std::uint64_t>(in); n > 0; --n)
	{
		FramePose& frame = framePoses.emplace_back();
		frame.keyframe = read<std::int32_t>(in);
		frame.T_cw = readPose(in);
		frame.timestamp = read<double>(in);
		if (frame.keyframe < -1 || frame.keyframe >= nextKeyframe)
			throw badState("corrupt odometry state (frame of keyframe " + std::to_string(frame.keyframe) + ")");
		if (!std::isfinite(frame.timestamp)) throw badState("corrupt odometry state (frame timestamp)");
	}
	Session continued;
	continued.firstKeyframe = read<std::int32_t>(in);
	continued.firstFrame = read<std::uint64_t>(in);
	continued.placing = read<bool>(in);
	continued.placements = readEdges(in, nextKeyframe);
	for (auto n = read<std::uint32_t>(in); n > 0; --n)
	{
		const int place = read<std::int32_t>(in), by = read<std::int32_t>(in);
		if (place < 0 || by < place || by >= nextKeyframe || !continued.joined.emplace(place, by).second)
			throw badState("corrupt odometry state (joined place)");
	}
	if (continued.firstKeyframe < 0 || continued.firstKeyframe > nextKeyframe ||
		continued.firstFrame > framePoses.size())
		throw badState("corrupt odometry state (session start)");
	for (const auto& kf : keyframes)
		if (kf.id < 0 || kf.id >= nextKeyframe || !places.find(kf.id))
			throw badState("corrupt odometry state (keyframe id " + std::to_string(kf.id) + ")");
	if (lost < 0 || lostWithFeatures < 0 || lostWithFeatures > lost)
		throw badState("corrupt odometry state (lost frame counts)");
	T_cw = pose;
	velocity = motion;
	velocityMeasured = motionMeasured;
	recentDeviations = std::move(deviations);
	nextLandmarkId = nextId;
	landmarks = std::move(map);
	window = std::move(keyframes);
	nextKeyframeId = nextKeyframe;
	lostFrames = lost;
	lostFramesWithFeatures = lostWithFeatures;
	keyframeMap = std::move(places);
	loops = std::move(loopEdges);
	frames = std::move(framePoses);
	session = std::move(continued);
}
}  // namespace avm::odometry
