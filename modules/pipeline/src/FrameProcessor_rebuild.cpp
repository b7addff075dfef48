// The map made again at the end of a run ([pipeline] rebuild_map). After a
// loop closure the map holds each frame where it was inserted, at the drifted
// pose of its time; the trajectory has moved. The frames are read again from
// the rawlog (not kept: the run's memory stays bounded) and go through the
// run's own per-frame path (applyDueDetections, mapFrame, finish) with two
// other sources: the poses are the trajectory's, and each detection is the
// run's boxes of its frame, replayed instead of detected. Only the poses
// differ, so the map, regions and persons follow the corrected trajectory,
// and at unchanged poses nothing differs at all.
#include <mrpt/system/CTicTac.h>

#include <map>
#include <stdexcept>
#include <utility>

#include "FrameProcessor.h"
#include "ProcessUsage.h"

namespace avm::pipeline::detail
{
RunSummary::MapRebuildCost FrameProcessor::rebuildMap(
	const std::function<std::optional<io::RgbdFrame>()>& nextFrame, const std::function<void()>& startOver)
{
	finishInsertion();
	mrpt::system::CTicTac timer;
	const double cpuAtStart = processCpuSeconds();
	// The rebuild changes the map and what is made of it, not the run's
	// figures: detections, frames and stage times stay the run's.
	const RunSummary runCounts = m_counts;
	const StageSamples runStages = m_stages;
	startOver();
	for (auto* o : m_observers) o->onMapStartedOver();
	// A continued session's frames go again on top of the earlier sessions',
	// whose poses no loop of this session moved.
	const std::size_t firstPose = runCounts.continuation ? runCounts.continuation->posesBefore : 0;
	const std::size_t firstRecord = runCounts.continuation ? runCounts.continuation->detectionsBefore : 0;
	m_counts.regions = 0;
	// An earlier session's switch stays in its map.
	if (!m_adaptive.hasSwitched()) m_counts.switchFrame.reset();

	// The run's detections with persons, by frame: a detection's records are
	// consecutive, one per person, in the order its persons were observed.
	std::map<std::size_t, DetectionResult> detections;
	for (const auto& r :
		std::vector(m_personDetections.begin() + std::ptrdiff_t(firstRecord), m_personDetections.end()))
	{
		auto& d = detections[r.frameIndex];
		d.frameIndex = r.frameIndex;
		d.timestamp = r.timestamp;
		d.persons.push_back(r.person);
	}
	m_personDetections.resize(firstRecord);
	m_recentPoses.clear();
	const auto replay = [this](DetectionResult d)
	{
		const std::size_t applyAt = d.frameIndex + m_options.detectionLagFrames;
		m_pendingDetections.push_back({applyAt, std::async(std::launch::deferred, [d = std::move(d)] { return d; })});
	};

	std::size_t mapped = firstPose;
	while (mapped < m_trajectory.size())
	{
		const auto frame = nextFrame();
		if (!frame)
			throw std::runtime_error("rebuilding the map: the rawlog ended before the frame of time " +
									 std::to_string(m_trajectory[mapped].timestamp) + ", which the run mapped");
		if (const auto d = detections.find(frame->index); d != detections.end())
		{
			d->second.observation = frame->observation;
			replay(std::move(d->second));
			detections.erase(d);
		}
		applyDueDetections(frame->index);
		// The trajectory has the frames that were mapped, in order, with the
		// timestamps the same reader gave them.
		if (frame->timestamp() != m_trajectory[mapped].timestamp) continue;
		mapFrame(*frame, m_trajectory[mapped++].pose, false);
	}
	// The detections of frames after the last mapped one: no pose sees them,
	// as in the run.
	for (auto& d : detections) replay(std::move(d.second));
	finish();

	const auto regions = m_counts.regions;
	const auto switchFrame = m_counts.switchFrame;
	m_counts = runCounts;
	m_counts.regions = regions;
	m_counts.switchFrame = switchFrame;
	m_stages = runStages;
	return {mapped - firstPose, timer.Tac(), processCpuSeconds() - cpuAtStart};
}
}  // namespace avm::pipeline::detail
