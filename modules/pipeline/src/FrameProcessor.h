// One frame's way through avm-map, in the order of the README's data flow:
//
//   process(frame)
//     1. startDetection / applyDueDetections   person boxes (detector, lagged)
//     2. estimatePose                           odometry or ground truth
//     3. updatePersons                          persons and their regions
//     4. insert                                 the frame's region step (regions
//                                               ended, free-only boxes), then the
//                                               map (on the mapping thread)
//
// Threads: a detection runs on a worker (async_detection) and is applied
// detection_lag_frames after its frame, whether it finished early or late; a
// frame's insertion runs on a worker (async_mapping) beside the next frame's
// steps 1-2. Persons and regions touch the map only once the insertion in
// flight has finished, so the map is the same with threads or without.
#pragma once

#include <mrpt/img/TCamera.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/COutputLogger.h>
#include <mrpt/system/CTicTac.h>

#include <cstddef>
#include <deque>
#include <filesystem>
#include <functional>
#include <future>
#include <map>
#include <optional>
#include <set>
#include <vector>

#include "avm/detection/Detector.h"
#include "avm/io/RgbdFrame.h"
#include "avm/io/TimingSummary.h"
#include "avm/io/Trajectory.h"
#include "avm/plugin/CAdaptiveOctoMap.h"
#include "avm/odometry/VisualOdometry.h"
#include "avm/pipeline/FrameObserver.h"
#include "avm/pipeline/MappingPipeline.h"
#include "DetectionScheduler.h"

namespace avm::pipeline::detail
{
/** One person box of a detection run and what the map made of it. */
struct PersonDetectionRecord
{
	std::size_t frameIndex = 0;
	double timestamp = 0;
	detection::Detection person;
	/** Nothing when the frame had no pose (it was not mapped). */
	std::optional<persons::PersonObservation> seen;
};

/** Durations of each stage, frame by frame [ms]. */
struct StageSamples
{
	io::TimingSamples odometry, detection, detectionWait, map, mapCpu, odometryCpu, detectionCpu;
};

class FrameProcessor
{
   public:
	/** `detector` may be null (no detection). Everything given must outlive
	 *  the processor. */
	FrameProcessor(const TPipelineOptions& options, const odometry::TOdometryOptions& odometryOptions,
		detection::DetectorBase* detector, mrpt::maps::CMultiMetricMap& maps, mrpt::system::COutputLogger& log);
	~FrameProcessor();  //!< waits for the work in flight
	FrameProcessor(const FrameProcessor&) = delete;
	FrameProcessor& operator=(const FrameProcessor&) = delete;

	/** Steps 1-4 for one frame. False when the frame has no usable pose and
	 *  is not mapped (counted in skippedFrames). */
	bool process(const io::RgbdFrame& frame);

	/** After the last frame: the insertion in flight, the detections still
	 *  due and their persons. */
	void finish();
	/** After finish(): the map started over by `startOver` (cleared, or a
	 *  continued session's restored to the earlier sessions' map) and made
	 *  again from the frames `nextFrame` gives (the rawlog read again from
	 *  its start), each of this session's mapped
	 *  frame inserted at its pose in trajectory() (corrected by the loops
	 *  closed), persons and regions observed as in the run and in its order:
	 *  at unchanged poses, the same map byte for byte. Updates the persons of
	 *  personDetections(), regions and switchFrame. Throws std::runtime_error
	 *  when the frames end before the trajectory's last. */
	RunSummary::MapRebuildCost rebuildMap(
		const std::function<std::optional<io::RgbdFrame>()>& nextFrame, const std::function<void()>& startOver);
	/** The observers told of each frame before and after its insertion
	 *  (FrameObserver::onFrameMapped, onFrameInserted) and of the map
	 *  rebuild's start (onMapStartedOver); they must outlive the processor. */
	void watchedBy(const std::vector<FrameObserver*>& observers);

	// Checkpoints (src/Checkpoint.h) are taken between two frames.
	/** Once the persons of every applied detection are in the map: after a
	 *  frame without a pose they wait for the next frame's. */
	bool readyForCheckpoint() const { return m_detectionsWithoutPersons.empty(); }
	/** What a resumed run needs to go on as this one would (not the map),
	 *  after finishing the insertion in flight. */
	void saveState(mrpt::serialization::CArchive& out);
	/** Before the first frame: the state saveState() wrote. Throws
	 *  std::runtime_error on a stream it did not write. */
	void loadState(mrpt::serialization::CArchive& in);
	/** A resumed run reads its rawlog from the start again: a frame the
	 *  checkpointed run had processed is not processed twice; its detection
	 *  is started again if it had not been applied yet (the detector gives the
	 *  same boxes). False, doing nothing, for the frames after the checkpoint. */
	bool resumeThrough(const io::RgbdFrame& frame);
	/** The last frame given to process(), or restored by loadState(). */
	std::optional<std::size_t> lastFrame() const { return m_lastFrame; }

	/** After loadState() of a finished run's session (the output folder
	 *  `previous`): the start of the next session. The earlier sessions'
	 *  poses, person records and map stay; the counts and stage times start
	 *  again; the odometry looks the next frames up in the earlier keyframe
	 *  map (VisualOdometry::continueSession), and frames are numbered on from
	 *  the last one. Throws std::runtime_error when the session has no
	 *  keyframes to place frames in (it was mapped at ground-truth poses)
	 *  and this run's poses come from the odometry. */
	void continueSession(const std::filesystem::path& previous);
	/** The camera of the first frame processed (of the first session). */
	const std::optional<mrpt::img::TCamera>& camera() const { return m_camera; }

	/** frames, skippedFrames, switchFrame, detectionRuns, framesWithPerson,
	 *  regions so far. */
	const RunSummary& counts() const { return m_counts; }
	const StageSamples& stages() const { return m_stages; }
	const io::Trajectory& trajectory() const { return m_trajectory; }
	/** Per pose of trajectory(): false when the odometry had lost the track
	 *  and the pose is bridged by its motion model. */
	const std::vector<bool>& trackedPoses() const { return m_trackedPoses; }
	/** Per pose of trajectory(): the frame made an odometry keyframe (with
	 *  ground-truth poses: it moved keyframe_translation or turned
	 *  keyframe_rotation since the last such frame), the frames a session
	 *  hands on (keyframes.simplemap). */
	const std::vector<bool>& keyframePoses() const { return m_keyframePoses; }
	/** The frames' ground truth, where the rawlog has it. */
	const io::Trajectory& groundTruth() const { return m_groundTruth; }
	const std::vector<PersonDetectionRecord>& personDetections() const { return m_personDetections; }

   private:
	/** A detection run on one frame: the boxes, and the frame they belong to
	 *  (its depth is needed for the persons, with the pose of that frame). */
	struct DetectionResult
	{
		std::size_t frameIndex = 0;
		double timestamp = 0;
		mrpt::obs::CObservation3DRangeScan::Ptr observation;
		std::vector<detection::Detection> persons;
		double milliseconds = 0;
		double cpuMilliseconds = 0;  //!< of the thread that ran the detector
	};
	/** A detection started at frame k, applied at k + detection_lag_frames. */
	struct PendingDetection
	{
		std::size_t applyAt;
		std::future<DetectionResult> result;
	};
	/** What one frame's map work took: insertion, plus the person and region
	 *  updates that came before it. */
	struct MapWork
	{
		double wallMs = 0;
		double cpuMs = 0;  //!< of the threads that did it
	};

	// 1. Person boxes.
	/** The detector on the frame, when the schedule has it run there. */
	void startDetection(const io::RgbdFrame& frame);
	void runDetector(const io::RgbdFrame& frame);
	/** The detections due at frameIndex (waiting for them): their boxes mask
	 *  the odometry from now on, their persons wait for updatePersons. */
	void applyDueDetections(std::size_t frameIndex);
	// 2. Camera pose (optical frame in the world); nothing when not usable.
	std::optional<mrpt::poses::CPose3D> estimatePose(const io::RgbdFrame& frame);
	/** After the odometry closed a loop or placed the frames it bridged
	 *  through a loss: the earlier poses as it has them now. */
	void takeCorrectedTrajectory(std::size_t frameIndex);
	/** Whether the frame at `pose` is a keyframe of a run at ground-truth
	 *  poses: the odometry's spacing, keyframe_translation or keyframe_rotation. */
	bool spacedFromLastKeyframe(const mrpt::poses::CPose3D& pose) const;
	/** A loop the odometry verified at this frame, and the loop check's verdict, to the log. */
	void reportLoop(std::size_t frameIndex);
	// 3. Persons and their regions, once the previous frame is in the map.
	void updatePersons();
	void observePersons(const DetectionResult& detection);
	/** One detection's persons into the map, seen from `pose`: what it made of each. */
	std::vector<persons::PersonObservation> seePersons(const mrpt::obs::CObservation3DRangeScan& obs,
		const mrpt::poses::CPose3D& pose, const std::vector<detection::Detection>& persons, std::size_t frameIndex);
	/** Steps 3-4, the run's and the map rebuild's: the persons of the
	 *  detections due, seen from their frames' poses, then the frame inserted
	 *  at `pose`; `shown`: the observers are told of it. */
	void mapFrame(const io::RgbdFrame& frame, const mrpt::poses::CPose3D& pose, bool shown);
	// 4. The map.
	void insert(const io::RgbdFrame& frame, const mrpt::poses::CPose3D& pose);
	/** FrameObserver::onFrameMapped: the frame, before its insertion. */
	void tellObservers(const io::RgbdFrame& frame, const mrpt::poses::CPose3D& pose) const;
	void finishInsertion();

	const TPipelineOptions& m_options;
	const odometry::TOdometryOptions& m_odometryOptions;
	detection::DetectorBase* m_detector;
	mrpt::maps::CMultiMetricMap& m_maps;
	CAdaptiveOctoMap& m_adaptive;
	mrpt::system::COutputLogger& m_log;
	DetectionScheduler m_detectionScheduler;

	std::optional<odometry::VisualOdometry> m_odometry;  // started at the first frame
	RunSummary m_counts;
	StageSamples m_stages;
	io::Trajectory m_trajectory, m_groundTruth;
	std::vector<bool> m_trackedPoses, m_keyframePoses;  // per pose of m_trajectory
	std::optional<mrpt::img::TCamera> m_camera;
	std::vector<PersonDetectionRecord> m_personDetections;

	std::map<std::size_t, mrpt::poses::CPose3D> m_recentPoses;  // frame index -> pose, for lagging detections
	std::vector<cv::Rect> m_latestPersonBoxes;                  // the odometry's mask
	std::vector<DetectionResult> m_detectionsWithoutPersons;    // applied, persons not yet observed
	MapWork m_personWork;  // person updates since the last insertion: counted in the next one
	std::vector<FrameObserver*> m_observers;
	bool m_showsFeatures = false;                 // an observer shows the odometry's features
	odometry::OdometryEstimate m_lastEstimate;    // its features, for the observers
	std::optional<std::size_t> m_lastFrame;       // the last frame given to process()
	std::set<std::size_t> m_detectionsToRestart;  // after loadState: frames whose detection was pending

	// Last, so that they are joined first: the work in flight uses the above.
	std::deque<PendingDetection> m_pendingDetections;
	std::future<MapWork> m_pendingInsertion;
	std::size_t m_insertingFrame = 0;
	mrpt::obs::CObservation3DRangeScan::Ptr m_insertingObservation;  // for the observers, once inserted
	mrpt::poses::CPose3D m_insertingPose;
};
}  // namespace avm::pipeline::detail
