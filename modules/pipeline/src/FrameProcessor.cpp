#include "FrameProcessor.h"

#include <mrpt/core/bits_math.h>
#include <mrpt/system/CTicTac.h>

#include <Eigen/Geometry>

#include <limits>
#include <stdexcept>
#include <utility>

#include "avm/detection/PersonLabels.h"
#include "avm/io/ThreadCpuTime.h"

namespace avm::pipeline::detail
{
using mrpt::obs::CObservation3DRangeScan;
using mrpt::poses::CPose3D;

namespace
{
/** Poses kept for detections that arrive late: well over any detection lag. */
constexpr std::size_t kRecentPoses = 64;
}  // namespace

FrameProcessor::FrameProcessor(const TPipelineOptions& options, const odometry::TOdometryOptions& odometryOptions,
	detection::DetectorBase* detector, mrpt::maps::CMultiMetricMap& maps, mrpt::system::COutputLogger& log)
	: m_options(options),
	  m_odometryOptions(odometryOptions),
	  m_detector(detector),
	  m_maps(maps),
	  m_adaptive(*maps.mapByClass<CAdaptiveOctoMap>()),
	  m_log(log),
	  m_detectionScheduler(options)
{
}

FrameProcessor::~FrameProcessor() = default;

bool FrameProcessor::process(const io::RgbdFrame& frame)
{
	m_lastFrame = frame.index;
	if (!m_camera) m_camera = frame.observation->cameraParams;
	startDetection(frame);
	applyDueDetections(frame.index);
	const auto pose = estimatePose(frame);
	if (!pose)
	{
		if (m_lastEstimate.placed) ++m_counts.skippedFrames;
		return false;
	}
	const bool groundTruthPoses = m_options.poseSource == PoseSource::GroundTruth;
	if (auto& c = m_counts.continuation; c && !c->placedAtFrame)
	{
		c->placedAtFrame = frame.index;
		m_log.logFmt(mrpt::system::LVL_INFO, "frame %zu: %s, after %zu frames not placed\n", frame.index,
			groundTruthPoses ? "at its ground-truth pose in the earlier sessions' world"
							 : m_lastEstimate.status.c_str(),
			c->unplacedFrames);
	}
	if (frame.groundTruth) m_groundTruth.push_back({frame.timestamp(), *frame.groundTruth});
	m_keyframePoses.push_back(groundTruthPoses ? spacedFromLastKeyframe(*pose) : m_lastEstimate.keyframe);
	m_trajectory.push_back({frame.timestamp(), *pose});
	m_trackedPoses.push_back(groundTruthPoses || m_lastEstimate.tracked);
	mapFrame(frame, *pose, true);
	++m_counts.frames;
	return true;
}

void FrameProcessor::mapFrame(const io::RgbdFrame& frame, const CPose3D& pose, bool shown)
{
	m_recentPoses[frame.index] = pose;
	while (m_recentPoses.size() > kRecentPoses) m_recentPoses.erase(m_recentPoses.begin());
	finishInsertion();
	updatePersons();
	if (shown && !m_observers.empty()) tellObservers(frame, pose);
	insert(frame, pose);
}

void FrameProcessor::tellObservers(const io::RgbdFrame& frame, const CPose3D& pose) const
{
	// The boxes of the latest detection, with the person each was taken for.
	std::vector<DetectedPerson> latest;
	for (auto it = m_personDetections.rbegin();
		 it != m_personDetections.rend() && it->frameIndex == m_personDetections.back().frameIndex; ++it)
	{
		const auto& b = it->person.box;
		latest.push_back(
			{b.x, b.y, b.x + b.width, b.y + b.height, it->seen ? it->seen->personId : 0u, it->person.score});
	}
	std::vector<mrpt::img::TPixelCoordf> features, masked;
	for (const auto& p : m_lastEstimate.features) features.emplace_back(p.x, p.y);
	for (const auto& p : m_lastEstimate.maskedFeatures) masked.emplace_back(p.x, p.y);
	const MappedFrame mapped{frame, pose, m_counts.frames, m_adaptive, m_trajectory, m_counts.switchFrame,
		{{"odometry", m_stages.odometry.meanMs()}, {"detection", m_stages.detection.meanMs()},
			{"map", m_stages.map.meanMs()}},
		latest, features, masked};
	for (auto* o : m_observers) o->onFrameMapped(mapped);
}

void FrameProcessor::watchedBy(const std::vector<FrameObserver*>& observers)
{
	m_observers = observers;
	m_showsFeatures = false;
	for (const auto* o : observers) m_showsFeatures = m_showsFeatures || o->showsFeatures();
}

void FrameProcessor::finish()
{
	finishInsertion();
	applyDueDetections(std::numeric_limits<std::size_t>::max());
	updatePersons();
}

void FrameProcessor::startDetection(const io::RgbdFrame& frame)
{
	if (!m_detector) return;
	const auto cause = m_detectionScheduler.due(frame.index, *frame.observation, m_recentPoses);
	if (!cause) return;
	++m_counts.detectionsStartedBy[*cause];
	runDetector(frame);
}

void FrameProcessor::runDetector(const io::RgbdFrame& frame)
{
	const auto detect = [detector = m_detector, index = frame.index, t = frame.timestamp(), obs = frame.observation]
	{
		DetectionResult r{index, t, obs, {}, 0, 0};
		mrpt::system::CTicTac timer;
		const double cpu = io::threadCpuMs();
		r.persons = detection::personsOnly(detector->detect(io::colourImage(*obs)));
		r.milliseconds = timer.Tac() * 1e3;
		r.cpuMilliseconds = io::threadCpuMs() - cpu;
		return r;
	};
	// On the worker thread, or deferred to when it is due: applied
	// detection_lag_frames later either way, so the same rawlog always gives
	// the same odometry masks, person tracks and map.
	m_pendingDetections.push_back({frame.index + m_options.detectionLagFrames,
		std::async(m_options.asyncDetection ? std::launch::async : std::launch::deferred, detect)});
}

void FrameProcessor::applyDueDetections(std::size_t frameIndex)
{
	while (!m_pendingDetections.empty() && m_pendingDetections.front().applyAt <= frameIndex)
	{
		mrpt::system::CTicTac wait;
		DetectionResult r = m_pendingDetections.front().result.get();
		m_pendingDetections.pop_front();
		m_stages.detectionWait.add(wait.Tac() * 1e3);
		m_stages.detection.add(r.milliseconds);
		m_stages.detectionCpu.add(r.cpuMilliseconds);
		++m_counts.detectionRuns;
		if (!r.persons.empty()) ++m_counts.framesWithPerson;
		m_latestPersonBoxes.clear();
		for (const auto& p : r.persons) m_latestPersonBoxes.push_back(cv::Rect(p.box));
		m_detectionsWithoutPersons.push_back(std::move(r));
	}
}

std::optional<CPose3D> FrameProcessor::estimatePose(const io::RgbdFrame& frame)
{
	CPose3D pose;
	if (m_options.poseSource == PoseSource::GroundTruth)
	{
		if (!frame.groundTruth)
		{
			m_log.logFmt(
				mrpt::system::LVL_WARN, "frame %zu: no usable ground-truth pose, frame not mapped\n", frame.index);
			return std::nullopt;
		}
		pose = *frame.groundTruth;
	}
	else
	{
		if (!m_odometry)
			m_odometry.emplace(m_odometryOptions, m_options.startAtGroundTruth && frame.groundTruth
													  ? *frame.groundTruth
													  : io::opticalToSensorPose().getOppositeScalar());
		m_odometry->reportFeatures(m_showsFeatures);
		mrpt::system::CTicTac timer;
		const double cpu = io::threadCpuMs();
		m_lastEstimate = m_odometry->process(*frame.observation, m_latestPersonBoxes);
		m_stages.odometry.add(timer.Tac() * 1e3);
		m_stages.odometryCpu.add(io::threadCpuMs() - cpu);
		if (!m_lastEstimate.placed)
		{
			++m_counts.continuation->unplacedFrames;
			m_log.logFmt(mrpt::system::LVL_INFO, "frame %zu: %s\n", frame.index, m_lastEstimate.status.c_str());
			return std::nullopt;
		}
		if (!m_lastEstimate.tracked)
			m_log.logFmt(mrpt::system::LVL_WARN, "frame %zu: odometry lost (%s), pose bridged\n", frame.index,
				m_lastEstimate.status.c_str());
		if (m_lastEstimate.loop) reportLoop(frame.index);
		if (m_lastEstimate.loopClosed || m_lastEstimate.bridgedFramesPlaced > 0) takeCorrectedTrajectory(frame.index);
		pose = m_lastEstimate.pose;
	}
	if (!io::isFinite(pose))
	{
		m_log.logFmt(mrpt::system::LVL_WARN, "frame %zu: pose is not finite, frame not mapped\n", frame.index);
		return std::nullopt;
	}
	return pose;
}

bool FrameProcessor::spacedFromLastKeyframe(const CPose3D& pose) const
{
	for (std::size_t i = m_keyframePoses.size(); i-- > 0;)
		if (m_keyframePoses[i])
		{
			const CPose3D moved = pose - m_trajectory[i].pose;
			const Eigen::Matrix3d R = moved.getRotationMatrix().asEigen();
			return moved.norm() > m_odometryOptions.keyframe_translation ||
				   mrpt::RAD2DEG(Eigen::AngleAxisd(R).angle()) > m_odometryOptions.keyframe_rotation;
		}
	return true;
}

void FrameProcessor::continueSession(const std::filesystem::path& previous)
{
	if (m_options.poseSource == PoseSource::VisualOdometry && !m_odometry)
		throw std::runtime_error(
			"it was mapped at ground-truth poses and holds no keyframes to place this run's frames in (continue it "
			"with --poses gt)");
	RunSummary::Continuation next;
	next.previous = previous;
	next.session = m_counts.continuation ? m_counts.continuation->session + 1 : 2;
	next.posesBefore = m_trajectory.size();
	next.detectionsBefore = m_personDetections.size();
	next.firstFrameIndex = m_lastFrame ? *m_lastFrame + 1 : 0;
	// The earlier sessions' map, poses and persons stay; what this run costs
	// and counts starts again. The switch to high resolution is the map's.
	const auto switchFrame = m_counts.switchFrame;
	m_counts = {};
	m_counts.switchFrame = switchFrame;
	m_counts.continuation = next;
	m_stages = {};
	m_recentPoses.clear();
	m_latestPersonBoxes.clear();
	m_detectionScheduler.forgetLastLook();
	m_personWork = {};
	if (m_odometry) m_odometry->continueSession();
}

void FrameProcessor::takeCorrectedTrajectory(std::size_t frameIndex)
{
	// The odometry has a pose for every frame it saw, this one included; the
	// trajectory has one for each of the earlier ones (a VO pose is never
	// left out).
	const auto corrected = m_odometry->trajectory();
	if (corrected.size() != m_trajectory.size() + 1)
	{
		m_log.logFmt(mrpt::system::LVL_WARN,
			"frame %zu: earlier poses moved, but the odometry has %zu poses for %zu frames: trajectory left as it "
			"was\n",
			frameIndex, corrected.size(), m_trajectory.size() + 1);
		return;
	}
	for (std::size_t i = 0; i < m_trajectory.size(); ++i) m_trajectory[i].pose = corrected[i];
	if (m_lastEstimate.bridgedFramesPlaced > 0)
		m_log.logFmt(mrpt::system::LVL_INFO,
			"frame %zu: odometry back after %zu lost frames, their poses placed between the last tracked one and "
			"this one\n",
			frameIndex, m_lastEstimate.bridgedFramesPlaced);
	if (!m_lastEstimate.loopClosed) return;
	++m_counts.loopsClosed;
	m_log.logFmt(mrpt::system::LVL_INFO, "frame %zu: loop closed, the trajectory so far corrected\n", frameIndex);
}

void FrameProcessor::reportLoop(std::size_t frameIndex)
{
	// Every verified loop and what the loop check made of it, so that a user
	// sees why a loop did or did not move the trajectory.
	const auto& status = m_lastEstimate.status;
	const auto at = status.find("loop with");
	m_log.logFmt(mrpt::system::LVL_INFO, "frame %zu, against frame %zu: %s\n", frameIndex,
		m_lastEstimate.loop->candidateFrame, status.substr(at == std::string::npos ? 0 : at).c_str());
}

void FrameProcessor::updatePersons()
{
	for (const auto& r : m_detectionsWithoutPersons) observePersons(r);
	m_detectionsWithoutPersons.clear();
}

void FrameProcessor::observePersons(const DetectionResult& r)
{
	if (r.persons.empty()) return;
	const auto pose = m_recentPoses.find(r.frameIndex);
	std::vector<persons::PersonObservation> seen;
	mrpt::system::CTicTac timer;
	const double cpu = io::threadCpuMs();
	if (pose != m_recentPoses.end()) seen = seePersons(*r.observation, pose->second, r.persons, r.frameIndex);
	// Persons and their regions are map work: they count in the next
	// insertion's time.
	m_personWork.wallMs += timer.Tac() * 1e3;
	m_personWork.cpuMs += io::threadCpuMs() - cpu;
	for (std::size_t i = 0; i < r.persons.size(); i++)
	{
		PersonDetectionRecord record{r.frameIndex, r.timestamp, r.persons[i], std::nullopt};
		if (!seen.empty())
		{
			record.seen = seen[i];
			if (seen[i].regionBox) ++m_counts.regions;
		}
		m_personDetections.push_back(std::move(record));
	}
}

std::vector<persons::PersonObservation> FrameProcessor::seePersons(const CObservation3DRangeScan& obs,
	const CPose3D& pose, const std::vector<detection::Detection>& persons, std::size_t frameIndex)
{
	const cv::Size size(static_cast<int>(obs.rangeImage.cols()), static_cast<int>(obs.rangeImage.rows()));
	std::vector<persons::PixelSet> pixels;
	for (const auto& p : persons) pixels.push_back(detection::personPixels(p, size));
	return m_adaptive.observePersons(obs, pose, pixels, frameIndex);
}

void FrameProcessor::insert(const io::RgbdFrame& frame, const CPose3D& pose)
{
	// The frame's region step, once a frame and map work like the persons'
	// (step 3): the insertion then takes its free-only boxes as they are.
	mrpt::system::CTicTac timer;
	const double cpu = io::threadCpuMs();
	m_adaptive.prepareRegions(*frame.observation, pose);
	m_personWork.wallMs += timer.Tac() * 1e3;
	m_personWork.cpuMs += io::threadCpuMs() - cpu;
	const auto work = [&maps = m_maps, obs = frame.observation, pose, persons = std::exchange(m_personWork, {})]
	{
		mrpt::system::CTicTac timer;
		const double cpu = io::threadCpuMs();
		maps.insertObservation(*obs, pose);
		return MapWork{timer.Tac() * 1e3 + persons.wallMs, io::threadCpuMs() - cpu + persons.cpuMs};
	};
	m_insertingFrame = frame.index;
	m_insertingObservation = frame.observation;
	m_insertingPose = pose;
	m_pendingInsertion = std::async(m_options.asyncMapping ? std::launch::async : std::launch::deferred, work);
	if (!m_options.asyncMapping) finishInsertion();
}

void FrameProcessor::finishInsertion()
{
	if (!m_pendingInsertion.valid()) return;
	const auto work = m_pendingInsertion.get();
	m_stages.map.add(work.wallMs);
	m_stages.mapCpu.add(work.cpuMs);
	if (!m_counts.switchFrame && m_adaptive.hasSwitched()) m_counts.switchFrame = m_insertingFrame;
	// Before anything else changes the map: the free-only boxes are this insertion's.
	const InsertedFrame inserted{*m_insertingObservation, m_insertingPose, m_adaptive.lastFreeOnlyBoxes(), m_adaptive};
	for (auto* o : m_observers) o->onFrameInserted(inserted);
	m_insertingObservation.reset();
}
}  // namespace avm::pipeline::detail
