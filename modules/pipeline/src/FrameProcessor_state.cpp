// A FrameProcessor's part of a checkpoint: everything but the map that a
// resumed run needs to go on exactly as the killed one would have: the
// counts and stage times, trajectory, person records, the poses lagging
// detections will need, the odometry's mask and state, the detection
// schedule's last look, and which frames' detections were still pending
// (they are run again, not stored).
#include <mrpt/poses/CPose3D.h>

#include <stdexcept>

#include "FrameProcessor.h"
#include "avm/io/PointArchive.h"

namespace avm::pipeline::detail
{
using mrpt::serialization::CArchive;

namespace
{
constexpr std::uint8_t kStateVersion = 7;

void write(CArchive& out, const io::TimingSamples& t) { out << t.samples(); }
void read(CArchive& in, io::TimingSamples& t)
{
	std::vector<double> samples;
	in >> samples;
	t = io::TimingSamples(std::move(samples));
}
void write(CArchive& out, std::size_t n) { out.WriteAs<std::uint64_t>(n); }
std::size_t readSize(CArchive& in) { return static_cast<std::size_t>(in.ReadAs<std::uint64_t>()); }

/** An optional as a presence byte and, when present, what `put` writes. */
template <typename T, typename Put>
void writeOptional(CArchive& out, const std::optional<T>& value, Put put)
{
	out.WriteAs<std::uint8_t>(value.has_value());
	if (value) put(*value);
}
template <typename T, typename Get>
void readOptional(CArchive& in, std::optional<T>& value, Get get)
{
	value.reset();
	if (in.ReadAs<std::uint8_t>()) get(value.emplace());
}

void write(CArchive& out, const io::Trajectory& poses)
{
	write(out, poses.size());
	for (const auto& p : poses) out << p.timestamp << p.pose;
}
void read(CArchive& in, io::Trajectory& poses)
{
	poses.resize(readSize(in));
	for (auto& p : poses) in >> p.timestamp >> p.pose;
}

void write(CArchive& out, const mrpt::img::TCamera& c)
{
	out.WriteAs<std::uint32_t>(c.ncols);
	out.WriteAs<std::uint32_t>(c.nrows);
	out << c.fx() << c.fy() << c.cx() << c.cy();
}
void read(CArchive& in, mrpt::img::TCamera& c)
{
	c.ncols = in.ReadAs<std::uint32_t>();
	c.nrows = in.ReadAs<std::uint32_t>();
	double fx, fy, cx, cy;
	in >> fx >> fy >> cx >> cy;
	c.fx(fx);
	c.fy(fy);
	c.cx(cx);
	c.cy(cy);
}

void write(CArchive& out, const RunSummary::Continuation& c)
{
	out << c.previous.string();
	for (const std::size_t n : {c.session, c.posesBefore, c.detectionsBefore, c.firstFrameIndex, c.unplacedFrames})
		write(out, n);
	writeOptional(out, c.placedAtFrame, [&](std::size_t i) { write(out, i); });
}
void read(CArchive& in, RunSummary::Continuation& c)
{
	std::string previous;
	in >> previous;
	c.previous = previous;
	for (std::size_t* n : {&c.session, &c.posesBefore, &c.detectionsBefore, &c.firstFrameIndex, &c.unplacedFrames})
		*n = readSize(in);
	readOptional(in, c.placedAtFrame, [&](std::size_t& i) { i = readSize(in); });
}

void write(CArchive& out, const PersonDetectionRecord& r)
{
	write(out, r.frameIndex);
	out << r.timestamp;
	const auto& d = r.person;
	out << d.box.x << d.box.y << d.box.width << d.box.height << static_cast<std::int32_t>(d.classId) << d.className
		<< d.score;
	writeOptional(out, r.seen,
		[&](const persons::PersonObservation& seen)
		{
			writeOptional(out, seen.sighting,
				[&](const persons::PersonSighting& s)
				{
					io::writePoint(out, s.position);
					io::writeBox(out, s.box);
					write(out, s.points);
					out << s.depth;
				});
			out << seen.personId;
			writeOptional(out, seen.regionBox, [&](const mrpt::math::TBoundingBox& b) { io::writeBox(out, b); });
			out << seen.skipReason;
		});
}
void read(CArchive& in, PersonDetectionRecord& r)
{
	r.frameIndex = readSize(in);
	in >> r.timestamp;
	auto& d = r.person;
	in >> d.box.x >> d.box.y >> d.box.width >> d.box.height;
	d.classId = in.ReadAs<std::int32_t>();
	in >> d.className >> d.score;
	readOptional(in, r.seen,
		[&](persons::PersonObservation& seen)
		{
			readOptional(in, seen.sighting,
				[&](persons::PersonSighting& s)
				{
					io::readPoint(in, s.position);
					io::readBox(in, s.box);
					s.points = readSize(in);
					in >> s.depth;
				});
			in >> seen.personId;
			readOptional(in, seen.regionBox, [&](mrpt::math::TBoundingBox& b) { io::readBox(in, b); });
			in >> seen.skipReason;
		});
}
}  // namespace

void FrameProcessor::saveState(CArchive& out)
{
	if (!readyForCheckpoint()) throw std::logic_error("FrameProcessor::saveState: persons still to observe");
	finishInsertion();
	out.WriteAs<std::uint8_t>(kStateVersion);
	writeOptional(out, m_lastFrame, [&](std::size_t i) { write(out, i); });
	const auto& c = m_counts;
	write(out, c.frames);
	write(out, c.skippedFrames);
	writeOptional(out, c.switchFrame, [&](std::size_t i) { write(out, i); });
	write(out, c.detectionRuns);
	write(out, c.framesWithPerson);
	write(out, c.regions);
	write(out, c.loopsClosed);
	write(out, c.detectionsStartedBy.size());
	for (const auto& [cause, runs] : c.detectionsStartedBy)
	{
		out << cause;
		write(out, runs);
	}
	for (const auto* t : {&m_stages.odometry, &m_stages.detection, &m_stages.detectionWait, &m_stages.map,
			 &m_stages.mapCpu, &m_stages.odometryCpu, &m_stages.detectionCpu})
		write(out, *t);
	write(out, m_trajectory);
	for (const bool tracked : m_trackedPoses) out.WriteAs<std::uint8_t>(tracked);
	for (const bool keyframe : m_keyframePoses) out.WriteAs<std::uint8_t>(keyframe);
	writeOptional(out, m_camera, [&](const mrpt::img::TCamera& c) { write(out, c); });
	writeOptional(out, c.continuation, [&](const RunSummary::Continuation& s) { write(out, s); });
	write(out, m_groundTruth);
	write(out, m_personDetections.size());
	for (const auto& r : m_personDetections) write(out, r);
	write(out, m_recentPoses.size());
	for (const auto& [index, pose] : m_recentPoses)
	{
		write(out, index);
		out << pose;
	}
	write(out, m_latestPersonBoxes.size());
	for (const auto& b : m_latestPersonBoxes)
		out << static_cast<std::int32_t>(b.x) << static_cast<std::int32_t>(b.y) << static_cast<std::int32_t>(b.width)
			<< static_cast<std::int32_t>(b.height);
	m_detectionScheduler.saveState(out);
	out << m_personWork.wallMs << m_personWork.cpuMs;
	write(out, m_pendingDetections.size());
	for (const auto& p : m_pendingDetections) write(out, p.applyAt - m_options.detectionLagFrames);
	out.WriteAs<std::uint8_t>(m_odometry.has_value());
	if (m_odometry) m_odometry->saveState(out);
}

void FrameProcessor::loadState(CArchive& in)
{
	if (m_lastFrame) throw std::logic_error("FrameProcessor::loadState: frames were processed already");
	if (const auto version = in.ReadAs<std::uint8_t>(); version != kStateVersion)
		throw std::runtime_error(
			"unknown run state version " + std::to_string(version) + " (written by another avm version)");
	readOptional(in, m_lastFrame, [&](std::size_t& i) { i = readSize(in); });
	auto& c = m_counts;
	c.frames = readSize(in);
	c.skippedFrames = readSize(in);
	readOptional(in, c.switchFrame, [&](std::size_t& i) { i = readSize(in); });
	c.detectionRuns = readSize(in);
	c.framesWithPerson = readSize(in);
	c.regions = readSize(in);
	c.loopsClosed = readSize(in);
	c.detectionsStartedBy.clear();
	for (std::size_t n = readSize(in); n > 0; --n)
	{
		std::string cause;
		in >> cause;
		c.detectionsStartedBy[cause] = readSize(in);
	}
	for (auto* t : {&m_stages.odometry, &m_stages.detection, &m_stages.detectionWait, &m_stages.map, &m_stages.mapCpu,
			 &m_stages.odometryCpu, &m_stages.detectionCpu})
		read(in, *t);
	read(in, m_trajectory);
	m_trackedPoses.resize(m_trajectory.size());
	for (std::size_t i = 0; i < m_trackedPoses.size(); ++i) m_trackedPoses[i] = in.ReadAs<std::uint8_t>() != 0;
	m_keyframePoses.resize(m_trajectory.size());
	for (std::size_t i = 0; i < m_keyframePoses.size(); ++i) m_keyframePoses[i] = in.ReadAs<std::uint8_t>() != 0;
	readOptional(in, m_camera, [&](mrpt::img::TCamera& camera) { read(in, camera); });
	readOptional(in, c.continuation, [&](RunSummary::Continuation& s) { read(in, s); });
	read(in, m_groundTruth);
	m_personDetections.resize(readSize(in));
	for (auto& r : m_personDetections) read(in, r);
	m_recentPoses.clear();
	for (std::size_t n = readSize(in); n > 0; --n)
	{
		const std::size_t index = readSize(in);
		in >> m_recentPoses[index];
	}
	m_latestPersonBoxes.resize(readSize(in));
	for (auto& b : m_latestPersonBoxes)
	{
		b.x = in.ReadAs<std::int32_t>();
		b.y = in.ReadAs<std::int32_t>();
		b.width = in.ReadAs<std::int32_t>();
		b.height = in.ReadAs<std::int32_t>();
	}
	m_detectionScheduler.loadState(in);
	in >> m_personWork.wallMs >> m_personWork.cpuMs;
	m_detectionsToRestart.clear();
	for (std::size_t n = readSize(in); n > 0; --n) m_detectionsToRestart.insert(readSize(in));
	m_odometry.reset();
	if (in.ReadAs<std::uint8_t>())
	{
		m_odometry.emplace(m_odometryOptions);
		m_odometry->loadState(in);
	}
}

bool FrameProcessor::resumeThrough(const io::RgbdFrame& frame)
{
	if (!m_lastFrame || frame.index > *m_lastFrame) return false;
	if (m_detectionsToRestart.erase(frame.index)) runDetector(frame);
	return true;
}
}  // namespace avm::pipeline::detail
