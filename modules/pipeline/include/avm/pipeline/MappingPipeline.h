// The avm application as a library: every frame of a rawlog goes through
// odometry -> detection -> adaptive map, and the run ends in files a user
// opens (octovis, SceneViewer3D, TUM tools, a browser for the pictures).
//
//   frame (RawlogFrameReader, src/FrameSequence.h)
//     -> person boxes   (detector; every N frames, on a worker thread if async)
//     -> camera pose    (VisualOdometry with person boxes masked, or ground truth)
//     -> persons        (a box + its frame's depth and pose -> person track, region)
//     -> map            (CAdaptiveOctoMap, inside MRPT's CMultiMetricMap from [map])
//   one frame's steps: src/FrameProcessor.h; the files at the end: src/RunOutputs.h
// The loop only runs frames: what watches a run (the live view, the
// checkpoints) is an observer the program connects (avm/pipeline/FrameObserver.h).
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/system/COutputLogger.h>

#include <atomic>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "avm/io/IniKeyOptions.h"
#include "avm/io/TimingSummary.h"
#include "avm/pipeline/FrameObserver.h"

namespace avm::pipeline
{
enum class PoseSource
{
	VisualOdometry,  //!< "vo"
	GroundTruth      //!< "gt": the rawlog's CObservationRobotPose per frame
};
PoseSource poseSourceFromString(const std::string& name);  //!< throws on anything but vo/gt
std::string toString(PoseSource source);

/** When the map is made again from the rawlog at the trajectory's final poses. */
enum class MapRebuild
{
	Never,       //!< "never": the map keeps every frame where it was inserted
	AfterLoops,  //!< "after_loops": when the odometry closed a loop (it moved earlier poses)
	Always       //!< "always": every run (its cost, and a check of the replay)
};
MapRebuild mapRebuildFromString(const std::string& name);  //!< throws on anything but the three names
std::string toString(MapRebuild when);

/** Which frames the detector runs on. */
enum class DetectionSchedule
{
	Fixed,    //!< "fixed": every detect_every_n-th frame
	OnChange  //!< "on_change": when the view changed since the detector last looked (src/DetectionScheduler.h)
};
DetectionSchedule detectionScheduleFromString(const std::string& name);  //!< throws on anything but the two names
std::string toString(DetectionSchedule schedule);

/** Section [pipeline]. */
struct TPipelineOptions : public io::CIniKeyOptions<TPipelineOptions>
{
	PoseSource poseSource = PoseSource::VisualOdometry;  //!< pose_source
	/** Run the detector on every N-th frame; 0 turns detection off. With
	 *  the on_change schedule, the fewest frames between two runs. */
	unsigned detectEveryN = 3;
	DetectionSchedule detectionSchedule = DetectionSchedule::Fixed;  //!< detection_schedule
	/** on_change: the most frames between two runs, whatever changed. */
	unsigned detectMaxInterval = 6;
	/** on_change: the share of the image whose depth moved by more than
	 *  detectChangeDepth since the detector's last frame (seen from where
	 *  the camera is now) that runs it. */
	double detectMovedShare = 0.01;
	/** on_change: the share of the image newly in view since the detector's
	 *  last frame (outside it, or without depth there) that runs it. */
	double detectNewViewShare = 0.1;
	double detectChangeDepth = 0.2;  //!< [m] on_change: a depth difference that is a change
	/** Detection on a worker thread, beside odometry and mapping. */
	bool asyncDetection = true;
	/** A detection started at frame k is applied (odometry masks, persons,
	 *  regions) at frame k + this, waiting for it there if it is late: the
	 *  same rawlog gives the same run, threads or not. */
	unsigned detectionLagFrames = 2;
	/** A frame's map insertion on a worker thread while odometry processes the
	 *  next frame. The map is the same either way: regions are added, and
	 *  frames inserted, in the same order. */
	bool asyncMapping = true;
	/** Start odometry at the first frame's ground truth, when the rawlog has it
	 *  (so the odometry map and trajectory share the ground truth's world frame). */
	bool startAtGroundTruth = true;
	std::size_t maxFrames = 0;  //!< 0 = all frames
	/** Read the rawlog this many times in a row as one sequence (frame
	 *  indices and timestamps continued): the long-run test. */
	unsigned repeat = 1;
	int pictureSize = 1200;  //!< [px] width of the PNG pictures; 0 = none
	/** Frames decoded ahead on a reader thread; 0 reads on the loop's thread. */
	unsigned readAheadFrames = 4;
	/** Also build plain single-resolution OctoMaps (octomap's own
	 *  insertion, at both trees' resolutions) from the same frames and poses,
	 *  and compare (stats.json "reference"): a measurement mode, slow. The
	 *  program connects what builds them (avm/evaluation/ReferenceMapsObserver.h). */
	bool referenceMaps = false;
	/** [s] of run time between two checkpoints (OUTDIR/checkpoint.bin, what
	 *  avm-map --resume continues from); 0 = none. One is also written before
	 *  the first frame and after the last. Written by the CheckpointWriter
	 *  the program connects (avm/pipeline/CheckpointWriter.h). */
	double checkpointIntervalSeconds = 5;
	/** After a loop closure the map holds frames inserted at the drifted
	 *  poses of their time: at the end of the run, the map is cleared and
	 *  every mapped frame inserted again from the rawlog at its corrected
	 *  pose, persons and regions with it, in the run's order. */
	MapRebuild rebuildMap = MapRebuild::AfterLoops;
	/** The live view of the run (avm/viewer/LiveView.h), which the program
	 *  connects. */
	bool gui = false;
	double guiFps = 5.0;             //!< [Hz] most redraws a second
	std::string mapSection = "map";  //!< section with MRPT's map definition

	/** Every key: name, member, unit, description, check. */
	static io::IniKeys<TPipelineOptions> iniKeys();
};

struct RunSummary
{
	std::size_t frames = 0;         //!< frames mapped
	std::size_t skippedFrames = 0;  //!< frames the reader or the pose left out
	bool interrupted = false;       //!< stopped by the caller (Ctrl-C)
	double seconds = 0, fps = 0;
	double realTimeFactor = 0;               //!< recorded duration / processing time
	std::optional<std::size_t> switchFrame;  //!< first frame mapped at high resolution
	std::size_t detectionRuns = 0, framesWithPerson = 0;
	/** Detector runs started, by what started them (DetectionScheduler's
	 *  causes: "every_n", or on_change's "first", "interval", "moved",
	 *  "new_view", "no_pose"). */
	std::map<std::string, std::size_t> detectionsStartedBy;
	std::size_t regions = 0;        //!< person sightings that placed a region
	std::size_t persons = 0;        //!< person tracks confirmed as persons (track_min_sightings)
	std::optional<double> ateRmse;  //!< [m] odometry vs ground truth, when both exist
	/** Loops the odometry closed: each moved the trajectory's earlier poses. */
	std::size_t loopsClosed = 0;
	/** The map made again at the final poses ([pipeline] rebuild_map): what it cost. */
	struct MapRebuildCost
	{
		std::size_t frames = 0;  //!< frames inserted again
		double seconds = 0;      //!< wall time, the rawlog read again included
		double cpuSeconds = 0;   //!< of the process (all threads)
	};
	std::optional<MapRebuildCost> mapRebuild;
	double peakMemoryMb = 0;   //!< [MiB] peak resident memory of the process
	double cpuMsPerFrame = 0;  //!< [ms] CPU time of the run (all threads) per frame mapped
	/** [0..1] share of the machine's CPU time a hypervisor took during the run. */
	std::optional<double> stolenCpuShare;
	/** detection: the detector's own time; detectionWait: how long the loop
	 *  waited for a detection that was due. */
	io::TimingSummary odometry, detection, detectionWait, map;
	/** CPU time of the map stage (insertion and region updates), on the
	 *  threads that did it: the work, whatever else ran on the cores. */
	io::TimingSummary mapCpu;
	/** CPU time of the odometry on the loop's thread: its work, where the
	 *  odometry's wall-clock time also counts the detector's and the map's
	 *  threads taking the core meanwhile (all of avm-map on one core). */
	io::TimingSummary odometryCpu;
	/** CPU time of a detector run on the thread that ran it (with [detection]
	 *  threads = 1, all of the detector's work). */
	io::TimingSummary detectionCpu;
	/** Writing the checkpoints (count, mean ...): their cost. */
	io::TimingSummary checkpoint;
	/** A resumed run: the last frame its checkpoint had processed. */
	std::optional<std::size_t> resumedAfterFrame;
	/** A run that continued a finished one (MappingPipeline::continueRun):
	 *  its frames are looked up in the earlier sessions' map until one is
	 *  placed there; those before are counted here, not mapped. */
	struct Continuation
	{
		std::filesystem::path previous;    //!< the output folder of the run it continued
		std::size_t session = 2;           //!< this run's place in the chain of sessions (the first run is 1)
		std::size_t posesBefore = 0;       //!< the earlier sessions' poses, at the front of trajectory.txt
		std::size_t detectionsBefore = 0;  //!< the earlier sessions' person boxes, at the front of detections.txt
		std::size_t firstFrameIndex = 0;   //!< this run's frames are numbered on from the earlier sessions'
		std::size_t unplacedFrames = 0;    //!< frames before the first one placed in the earlier sessions' map
		std::optional<std::size_t> placedAtFrame;  //!< the first frame placed
	};
	std::optional<Continuation> continuation;
};

/** The run a checkpoint or a session belongs to: what `avm-map --resume
 *  OUTDIR` needs to make the pipeline again, and what `avm-map --continue
 *  PREV` takes its configuration from. */
struct CheckpointedRun
{
	std::string ini;               //!< the configuration the run read, --set values included
	std::filesystem::path rawlog;  //!< absolute
	PoseSource poseSource = PoseSource::VisualOdometry;
};
/** The finished run whose output folder is `previous`, from its session
 *  (session.bin: the checkpoint of the finished run, what continueRun
 *  starts from). Throws std::runtime_error in one line naming the file when
 *  the folder holds none (an interrupted run: resume it first), or the file
 *  is damaged, foreign or of another version. */
CheckpointedRun readSessionRun(const std::filesystem::path& previous);

class MappingPipeline : public mrpt::system::COutputLogger
{
   public:
	/** Reads and checks the whole configuration and loads the detector: a bad
	 *  value, an unknown pose source or a model that will not load throws here,
	 *  before any frame is read. Relative paths (the model) resolve against
	 *  projectRoot. Unknown keys and sections are warned about. */
	MappingPipeline(const mrpt::config::CConfigFileBase& ini, const std::filesystem::path& projectRoot);
	~MappingPipeline() override;
	MappingPipeline(const MappingPipeline&) = delete;
	MappingPipeline& operator=(const MappingPipeline&) = delete;

	void setPoseSource(PoseSource source);
	/** `observer` is told of every run from now on (avm/pipeline/FrameObserver.h:
	 *  the live view, the checkpoints), after the ones connected before it;
	 *  it must outlive the runs. Without observers a run writes no
	 *  checkpoint and shows nothing. */
	void addObserver(FrameObserver& observer);

	/** The OpenCV worker threads [detection] threads asks for (0 = OpenCV's
	 *  default). OpenCV's thread count is process-wide, so the program sets
	 *  it (cv::setNumThreads), not the library. */
	int openCvThreads() const;
	/** [pipeline] as read: what the program's observers are made from
	 *  (gui, checkpoint_interval_s). */
	const TPipelineOptions& options() const;

	/** Maps the rawlog and writes every output into outDir (created if
	 *  needed; checked for writing first). `stop` is polled once per frame:
	 *  when set, the run ends early and saves what was mapped. Throws on bad
	 *  input (missing or corrupt rawlog, no usable frame), leaving no outputs.
	 *  External images are read from MRPT's process-wide images folder, which
	 *  the program points at the rawlog's first (io::useImagesFolderOf).
	 *  progress(fractionOfFile, framesDone) is called after every frame. */
	RunSummary run(const std::filesystem::path& rawlog, const std::filesystem::path& outDir,
		const std::atomic<bool>* stop = nullptr, const std::function<void(double, std::size_t)>& progress = {});

	/** Continues the run whose checkpoint is `checkpoint` (written by a
	 *  CheckpointWriter; this pipeline made from its configuration:
	 *  CheckpointWriter::checkpointedRun) to the end of its rawlog, and writes
	 *  every output into outDir: the same map and trajectory as a run that was
	 *  never stopped. The rawlog is read again from its start; the frames
	 *  already mapped only restart the detections that were pending. Throws on
	 *  a missing or damaged checkpoint. */
	RunSummary resume(const std::filesystem::path& checkpoint, const std::filesystem::path& outDir,
		const std::atomic<bool>* stop = nullptr, const std::function<void(double, std::size_t)>& progress = {});

	/** Maps `rawlog` as the next session of the finished run whose output
	 *  folder is `previous` (read, never written): the run starts with its
	 *  maps, persons and keyframes, looks its frames up among all its
	 *  keyframes until one is placed (the frames before are counted in
	 *  RunSummary::continuation, not mapped) and maps on in its world frame;
	 *  outDir gets the outputs of all the sessions together (trajectory.txt,
	 *  persons.csv, the map) and a session of its own, which a next run can
	 *  continue. This pipeline's configuration must map at the earlier
	 *  sessions' resolutions (readSessionRun(previous).ini by default), and
	 *  the rawlog come from their camera. Throws, writing nothing, when
	 *  `previous` holds no finished run, the two differ, outDir is `previous`,
	 *  or no frame is ever placed. */
	RunSummary continueRun(const std::filesystem::path& previous, const std::filesystem::path& rawlog,
		const std::filesystem::path& outDir, const std::atomic<bool>* stop = nullptr,
		const std::function<void(double, std::size_t)>& progress = {});

	/** The map of the last run. */
	const CAdaptiveOctoMap& map() const;

   private:
	/** How a run starts: from nothing, from outDir's checkpoint, or from a finished run's session. */
	struct Start;
	RunSummary runFrames(const std::filesystem::path& rawlog, const std::filesystem::path& outDir, const Start& start,
		const std::atomic<bool>* stop, const std::function<void(double, std::size_t)>& progress);

	struct Impl;
	std::unique_ptr<Impl> m_impl;
};
}  // namespace avm::pipeline
