// The map made again at the end of a run ([pipeline] rebuild_map). After a
// loop closure the map holds each frame where it was inserted, at the drifted
// pose of its time; the trajectory has moved. The frames are read again from
// the rawlog (not kept: the run's memory stays bounded) and go through the
// map's calls of the run in the run's order: a detection's persons before the
// insertion of the first mapped frame at or after its frame + lag, the rest
// at the end. Only the poses differ, so the map, regions and persons follow
// the corrected trajectory, and at unchanged poses nothing differs at all.
#include <mrpt/system/CTicTac.h>

#include <limits>
#include <map>
#include <stdexcept>

#include "FrameProcessor.h"
#include "ProcessUsage.h"

namespace avm::pipeline::detail
{
RunSummary::MapRebuildCost FrameProcessor::rebuildMap(const std::function<std::optional<io::RgbdFrame>()>& nextFrame)
{
	finishInsertion();
	mrpt::system::CTicTac timer;
	const double cpuAtStart = processCpuSeconds();
	m_maps.clear();
	if (m_reference) m_reference->clear();
	m_counts.regions = 0;
	m_counts.switchFrame.reset();

	// A detection's records are consecutive, one per person, in the order
	// its persons were observed.
	struct Detection
	{
		std::vector<PersonDetectionRecord*> records;
		std::vector<detection::Detection> persons;
		mrpt::obs::CObservation3DRangeScan::Ptr observation;  // once its frame is read again
	};
	std::map<std::size_t, Detection> detections;
	for (auto& r : m_personDetections)
	{
		auto& d = detections[r.frameIndex];
		d.records.push_back(&r);
		d.persons.push_back(r.person);
	}
	std::map<std::size_t, mrpt::poses::CPose3D> mappedPoses;  // frame index -> its final pose
	const auto observeDetectionsDue = [&](std::size_t frameIndex)
	{
		for (auto it = detections.begin();
			 it != detections.end() && it->first + m_options.detectionLagFrames <= frameIndex;
			 it = detections.erase(it))
		{
			auto& d = it->second;
			const auto pose = mappedPoses.find(it->first);
			std::vector<persons::PersonObservation> seen;
			if (pose != mappedPoses.end() && d.observation)
				seen = seePersons(*d.observation, pose->second, d.persons, it->first);
			for (std::size_t i = 0; i < d.records.size(); ++i)
			{
				d.records[i]->seen.reset();
				if (seen.empty()) continue;
				d.records[i]->seen = seen[i];
				if (seen[i].regionBox) ++m_counts.regions;
			}
		}
	};

	std::size_t mapped = 0;
	while (mapped < m_trajectory.size())
	{
		const auto frame = nextFrame();
		if (!frame)
			throw std::runtime_error("rebuilding the map: the rawlog ended before the frame of time " +
									 std::to_string(m_trajectory[mapped].timestamp) + ", which the run mapped");
		if (const auto d = detections.find(frame->index); d != detections.end())
			d->second.observation = frame->observation;
		// The trajectory has the frames that were mapped, in order, with the
		// timestamps the same reader gave them.
		if (frame->timestamp() != m_trajectory[mapped].timestamp) continue;
		const auto& pose = m_trajectory[mapped++].pose;
		mappedPoses[frame->index] = pose;
		observeDetectionsDue(frame->index);
		m_maps.insertObservation(*frame->observation, pose);
		if (m_reference) m_reference->insert(*frame->observation, pose);
		if (!m_counts.switchFrame && m_adaptive.hasSwitched()) m_counts.switchFrame = frame->index;
	}
	observeDetectionsDue(std::numeric_limits<std::size_t>::max());
	return {mapped, timer.Tac(), processCpuSeconds() - cpuAtStart};
}
}  // namespace avm::pipeline::detail
