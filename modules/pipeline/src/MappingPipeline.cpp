#include "avm/pipeline/MappingPipeline.h"

#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/system/CTicTac.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <utility>

#include "Checkpoint.h"
#include "FrameProcessor.h"
#include "FrameSequence.h"
#include "KeyframeSimplemap.h"
#include "ProcessUsage.h"
#include "RunOutputs.h"
#include "avm/detection/Detector.h"
#include "avm/evaluation/TrajectoryEvaluation.h"
#include "avm/io/ErrorMessage.h"
#include "avm/io/IniKeys.h"
#include "avm/io/IniOptions.h"
#include "avm/io/RawlogFrameReader.h"
#include "avm/io/RunFolder.h"
#include "avm/io/TimingSummary.h"
#include "avm/plugin/CAdaptiveOctoMap.h"
#include "avm/odometry/VisualOdometry.h"

namespace avm::pipeline
{
namespace fs = std::filesystem;

namespace
{
constexpr const char* kPipelineSection = "pipeline";
constexpr const char* kOdometrySection = "odometry";
constexpr const char* kDetectionSection = "detection";

/** The adaptive map's sections: [<map>_adaptiveOctoMap_NN_creationOpts] etc. */
void warnUnknownMapKeys(
	const mrpt::config::CConfigFileBase& ini, const std::string& mapSection, mrpt::system::COutputLogger& log)
{
	// Keys MRPT's map initializer reads itself in every _creationOpts section.
	static const std::vector<std::string> generic = {
		"enableSaveAs3DObject", "enableObservationLikelihood", "enableObservationInsertion"};
	const CAdaptiveOctoMap defaults;
	// A section may feed two options structs (_insertOpts: the map's and the
	// person layer's): a key is unknown when none of them reads it.
	const auto check = [&](const std::string& section,
						   std::initializer_list<const mrpt::config::CLoadableOptions*> readers, bool creation)
	{
		auto unknown = io::unknownKeys(ini, section, **readers.begin());
		for (const auto* reader : readers)
		{
			const auto notRead = io::unknownKeys(ini, section, *reader);
			const auto read = [&](const std::string& k)
			{ return std::find(notRead.begin(), notRead.end(), k) == notRead.end(); };
			unknown.erase(std::remove_if(unknown.begin(), unknown.end(), read), unknown.end());
		}
		for (const auto& key : unknown)
			if (!creation || std::find(generic.begin(), generic.end(), key) == generic.end())
				log.logStr(mrpt::system::LVL_WARN, io::unknownKeyWarning(section, key) + "\n");
	};
	const int count = ini.read_int(mapSection, "adaptiveOctoMap_count", 0);
	for (int i = 0; i < count; ++i)
	{
		char prefix[64];
		std::snprintf(prefix, sizeof(prefix), "%s_adaptiveOctoMap_%02d", mapSection.c_str(), i);
		const std::string p = prefix;
		check(p + "_creationOpts", {&defaults.creationOptions()}, true);
		check(p + "_insertOpts", {&defaults.insertionOptions, &defaults.personOptions}, false);
		check(p + "_likelihoodOpts", {&defaults.likelihoodOptions}, false);
		check(p + "_renderOpts", {&defaults.renderingOptions}, false);
	}
}

/** The maps of the [map_section] definition; throws when it holds no adaptive map. */
mrpt::maps::CMultiMetricMap::Ptr createMaps(
	const mrpt::maps::TSetOfMetricMapInitializers& definition, const std::string& section)
{
	auto maps = mrpt::maps::CMultiMetricMap::Create(definition);
	if (!maps->mapByClass<CAdaptiveOctoMap>())
		throw std::invalid_argument("[" + section + "] defines no adaptive map: add adaptiveOctoMap_count = 1");
	return maps;
}

/** What a run cost, from before the first frame is read. */
struct RunCost
{
	double seconds = 0, cpuSeconds = 0;    //!< wall time; the process's CPU time (all threads)
	std::optional<double> stolenCpuShare;  //!< the machine's CPU time a hypervisor took
};

class RunClock
{
   public:
	/** `before`: what the run had cost before it was resumed. */
	explicit RunClock(const detail::CheckpointProgress& before = {}) : m_before(before) {}
	RunCost read() const
	{
		return {m_before.seconds + m_wall.Tac(), m_before.cpuSeconds + processCpuSeconds() - m_cpuAtStart,
			m_stolen.stolen()};
	}

   private:
	detail::CheckpointProgress m_before;
	mrpt::system::CTicTac m_wall;
	double m_cpuAtStart = processCpuSeconds();
	StolenCpuTime m_stolen;
};

/** The configuration as ini text, for the checkpoint: a resumed run reads
 *  exactly what the killed one read. */
std::string iniText(const mrpt::config::CConfigFileBase& ini)
{
	std::string text;
	std::vector<std::string> sections, keys;
	ini.getAllSections(sections);
	for (const auto& section : sections)
	{
		text += "[" + section + "]\n";
		ini.getAllKeys(section, keys);
		for (const auto& key : keys) text += key + " = " + ini.read_string(section, key, "") + "\n";
	}
	return text;
}

/** The run between two frames, as its observers see it; it writes the
 *  checkpoints they ask for. */
class RunBetweenFrames : public RunState
{
   public:
	RunBetweenFrames(fs::path outDir, CheckpointedRun run, bool resumed, const RunClock& clock, std::string logBefore,
		const mrpt::system::COutputLogger& log, const mrpt::maps::CMultiMetricMap& maps,
		detail::FrameProcessor& processor)
		: m_outDir(std::move(outDir)),
		  m_run(std::move(run)),
		  m_resumed(resumed),
		  m_clock(clock),
		  m_logBefore(std::move(logBefore)),
		  m_log(log),
		  m_maps(maps),
		  m_processor(processor)
	{
	}
	bool resumed() const override { return m_resumed; }
	std::optional<std::size_t> lastFrame() const override { return m_processor.lastFrame(); }
	bool canCheckpoint() const override { return m_processor.readyForCheckpoint(); }
	void writeCheckpoint(const fs::path& file) override
	{
		mrpt::system::CTicTac timer;
		write(file);
		m_times.add(timer.Tac() * 1e3);
	}
	/** The finished run's session: its last checkpoint, kept as what a next run continues. */
	void writeSession() { write(io::RunFolder(m_outDir).session()); }
	const io::TimingSamples& checkpointTimes() const { return m_times; }

   private:
	void write(const fs::path& file)
	{
		const RunCost cost = m_clock.read();
		detail::writeCheckpoint(
			file, m_run, {cost.seconds, cost.cpuSeconds, m_logBefore + m_log.getLogAsString()}, m_maps, m_processor);
	}

	fs::path m_outDir;
	CheckpointedRun m_run;
	bool m_resumed;
	const RunClock& m_clock;
	std::string m_logBefore;  // a resumed run's log before its checkpoint
	const mrpt::system::COutputLogger& m_log;
	const mrpt::maps::CMultiMetricMap& m_maps;
	detail::FrameProcessor& m_processor;
	io::TimingSamples m_times;
};

/** The index of the run's first frame: a continued session numbers its
 *  frames on from the earlier sessions'. */
std::size_t firstFrameIndex(const detail::FrameProcessor& processor)
{
	const auto& continuation = processor.counts().continuation;
	return continuation ? continuation->firstFrameIndex : 0;
}

/** Throws, naming the files, when the rawlog's camera is not the one the
 *  earlier sessions were mapped with: their keyframes' points and the new
 *  frames' would not agree. */
void checkSameCamera(const fs::path& rawlog, const mrpt::img::TCamera& earlier, const fs::path& session)
{
	io::RawlogFrameReader reader(rawlog, false);
	const auto frame = reader.next();
	if (!frame) return;  // the run says what is wrong with the rawlog
	const auto& c = frame->observation->cameraParams;
	const auto near = [](double a, double b) { return std::abs(a - b) <= 1e-6 * std::max(std::abs(a), 1.0); };
	if (c.ncols == earlier.ncols && c.nrows == earlier.nrows && near(c.fx(), earlier.fx()) &&
		near(c.fy(), earlier.fy()) && near(c.cx(), earlier.cx()) && near(c.cy(), earlier.cy()))
		return;
	const auto describe = [](const mrpt::img::TCamera& k)
	{
		char text[128];
		std::snprintf(text, sizeof(text), "%ux%u, fx %.3f fy %.3f cx %.3f cy %.3f", k.ncols, k.nrows, k.fx(), k.fy(),
			k.cx(), k.cy());
		return std::string(text);
	};
	throw std::runtime_error(rawlog.string() + ": its camera (" + describe(c) + ") is not the one " + session.string() +
							 " was mapped with (" + describe(earlier) + "): a continued run needs the same camera");
}

/** [pipeline] rebuild_map, at the end of a run: what it cost, or nothing when
 *  it was not due (or the run was interrupted). */
std::optional<RunSummary::MapRebuildCost> rebuildMap(const TPipelineOptions& opt, const fs::path& rawlog,
	detail::FrameProcessor& processor, bool interrupted, const std::function<void()>& startOver,
	mrpt::system::COutputLogger& log)
{
	const std::size_t loops = processor.counts().loopsClosed;
	if (opt.rebuildMap == MapRebuild::Never || (opt.rebuildMap == MapRebuild::AfterLoops && loops == 0))
		return std::nullopt;
	if (interrupted)
	{
		log.logFmt(mrpt::system::LVL_WARN,
			"the run was interrupted: the map is not rebuilt at the final poses (%zu loops closed)\n", loops);
		return std::nullopt;
	}
	log.logFmt(mrpt::system::LVL_INFO, "rebuilding the map at the final poses (%zu loops closed): reading %s again\n",
		loops, rawlog.c_str());
	detail::FrameSequence frames(rawlog, opt.repeat, opt.readAheadFrames, firstFrameIndex(processor));
	const auto cost = processor.rebuildMap([&frames] { return frames.next(); }, startOver);
	log.logFmt(mrpt::system::LVL_INFO, "map rebuilt: %zu frames in %.2f s (%.2f s CPU)\n", cost.frames, cost.seconds,
		cost.cpuSeconds);
	return cost;
}
/** Maps the frames until the rawlog ends, `maxFrames` are mapped (0: no
 *  limit) or `stop` is set; false when an observer ended the run instead
 *  (the view's window was closed). */
bool mapFrames(std::size_t maxFrames, detail::FrameSequence& frames, detail::FrameProcessor& processor,
	const std::vector<FrameObserver*>& observers, RunState& run, const std::atomic<bool>* stop,
	const std::function<void(double, std::size_t)>& progress)
{
	const auto betweenFrames = [&]
	{
		bool goOn = true;
		for (auto* o : observers) goOn = o->betweenFrames(run) && goOn;
		return goOn;
	};
	if (!betweenFrames()) return false;
	while (!(stop && stop->load()))
	{
		const auto frame = frames.next();
		if (!frame) break;
		// A resumed run goes through the frames its checkpoint had processed
		// (restarting their pending detections) even when they were the last
		// max_frames allows.
		if (processor.resumeThrough(*frame)) continue;
		if (maxFrames && processor.counts().frames >= maxFrames) break;
		if (processor.process(*frame) && progress) progress(frames.progress(), processor.counts().frames);
		if (!betweenFrames()) return false;
	}
	return true;
}
}  // namespace

struct MappingPipeline::Impl
{
	TPipelineOptions options;
	odometry::TOdometryOptions odometryOptions;
	detection::TDetectorOptions detectorOptions;
	mrpt::maps::TSetOfMetricMapInitializers mapDefinition;
	std::unique_ptr<detection::DetectorBase> detector;
	/** The maps of the last run; made (and checked) by the constructor for the first one. */
	mrpt::maps::CMultiMetricMap::Ptr maps;
	bool mapsUsed = false;
	std::string iniText;                    //!< the configuration, for checkpoints
	std::vector<FrameObserver*> observers;  //!< addObserver(), in its order

	/** Fresh maps for a run of `rawlog`. */
	CAdaptiveOctoMap& startMaps(const fs::path& rawlog);
	/** The maps and processor (made from this configuration) as the finished
	 *  run in `previous` left them, at the start of a next session of `rawlog`. */
	void continueSession(const fs::path& previous, const fs::path& rawlog, detail::FrameProcessor& processor,
		mrpt::system::COutputLogger& log);
	/** A finished run's keyframes.simplemap and session.bin. */
	void handOn(const fs::path& rawlog, const fs::path& outDir, const detail::FrameProcessor& processor,
		RunBetweenFrames& state, mrpt::system::COutputLogger& log) const;
	RunSummary summarise(
		const detail::FrameProcessor& processor, const detail::FrameSequence& frames, const RunCost& cost) const;
};

CAdaptiveOctoMap& MappingPipeline::Impl::startMaps(const fs::path& rawlog)
{
	if (std::exchange(mapsUsed, true)) maps = createMaps(mapDefinition, options.mapSection);
	auto& map = *maps->mapByClass<CAdaptiveOctoMap>();
	// A switch at a fraction of the run needs the run's length.
	if (map.insertionOptions.switchAtFraction >= 0 && map.insertionOptions.expectedFrameCount == 0)
	{
		const std::size_t frames = io::countFrames(rawlog);
		map.setExpectedFrameCount(options.maxFrames ? std::min(options.maxFrames, frames) : frames);
	}
	return map;
}

RunSummary MappingPipeline::Impl::summarise(
	const detail::FrameProcessor& processor, const detail::FrameSequence& frames, const RunCost& cost) const
{
	RunSummary summary = processor.counts();
	summary.seconds = cost.seconds;
	summary.stolenCpuShare = cost.stolenCpuShare;
	summary.skippedFrames += frames.skipped().size();
	summary.fps = summary.frames / std::max(summary.seconds, 1e-9);
	summary.cpuMsPerFrame = cost.cpuSeconds * 1e3 / double(summary.frames);
	const auto& trajectory = processor.trajectory();
	if (trajectory.size() > 1)
	{
		const double recorded = (trajectory.back().timestamp - trajectory.front().timestamp) *
								double(trajectory.size()) / double(trajectory.size() - 1);
		summary.realTimeFactor = recorded / std::max(summary.seconds, 1e-9);
	}
	summary.peakMemoryMb = peakMemoryMb();
	const auto& stages = processor.stages();
	summary.odometry = stages.odometry.summary();
	summary.detection = stages.detection.summary();
	summary.detectionWait = stages.detectionWait.summary();
	summary.map = stages.map.summary();
	summary.mapCpu = stages.mapCpu.summary();
	summary.odometryCpu = stages.odometryCpu.summary();
	summary.detectionCpu = stages.detectionCpu.summary();
	summary.persons = maps->mapByClass<CAdaptiveOctoMap>()->confirmedPersons().size();
	// Of all the sessions' poses, under one alignment, when this run's poses
	// have ground truth: a continued session whose rawlog has none has none
	// of its own to be judged by (the sessions may have been recorded in any
	// order, so by the poses' times, not their places in the trajectory).
	const auto gt = io::inTimeOrder(processor.groundTruth());
	const std::size_t firstPose = summary.continuation ? summary.continuation->posesBefore : 0;
	const io::Trajectory thisRun(trajectory.begin() + std::min(firstPose, trajectory.size()), trajectory.end());
	const evaluation::TEvaluationOptions matching;
	const bool judged = evaluation::associateByTimestamp(thisRun, gt, matching.maxTimeDifference).size() >= 3;
	if (options.poseSource == PoseSource::VisualOdometry && judged)
		summary.ateRmse = evaluation::evaluateTrajectory(trajectory, gt, matching).ate.rmse;
	return summary;
}

MappingPipeline::MappingPipeline(const mrpt::config::CConfigFileBase& ini, const fs::path& projectRoot)
	: mrpt::system::COutputLogger("avm-map"), m_impl(std::make_unique<Impl>())
{
	auto& d = *m_impl;
	logging_enable_keep_record = true;  // for avm-map.log
	d.iniText = iniText(ini);
	d.options.loadFromConfigFile(ini, kPipelineSection);
	d.odometryOptions.loadFromConfigFile(ini, kOdometrySection);
	d.detectorOptions.loadFromConfigFile(ini, kDetectionSection);
	d.mapDefinition.loadFromConfigFile(ini, d.options.mapSection);

	const auto warnUnknown = [&](const std::string& section, const mrpt::config::CLoadableOptions& opts)
	{
		for (const auto& key : io::unknownKeys(ini, section, opts))
			logStr(mrpt::system::LVL_WARN, io::unknownKeyWarning(section, key) + "\n");
	};
	warnUnknown(kPipelineSection, d.options);
	warnUnknown(kOdometrySection, d.odometryOptions);
	warnUnknown(kDetectionSection, d.detectorOptions);
	warnUnknownMapKeys(ini, d.options.mapSection, *this);
	std::vector<std::string> sections;
	ini.getAllSections(sections);
	for (const auto& s : sections)
	{
		const bool known = s == kPipelineSection || s == kOdometrySection || s == kDetectionSection ||
						   s.rfind(d.options.mapSection, 0) == 0;
		if (!known) logStr(mrpt::system::LVL_WARN, "unknown section [" + s + "] (ignored)\n");
	}

	if (d.options.detectEveryN > 0)
	{
		d.detector = detection::createDetector(d.detectorOptions, projectRoot);
		const auto& o = d.options;
		const std::string when = o.detectionSchedule == DetectionSchedule::OnChange
									 ? "where the view changed, every " + std::to_string(o.detectEveryN) + " to " +
										   std::to_string(o.detectMaxInterval) + " frames"
								 : o.detectEveryN == 1 ? "on every frame"
													   : "every " + std::to_string(o.detectEveryN) + " frames";
		logStr(mrpt::system::LVL_INFO, "detector: " + d.detector->description() + ", " + when + "\n");
	}
	else
		logStr(mrpt::system::LVL_INFO, "detector: none (detect_every_n = 0)\n");

	// A missing map definition fails now, not after the first frame.
	d.maps = createMaps(d.mapDefinition, d.options.mapSection);
}

MappingPipeline::~MappingPipeline() = default;

void MappingPipeline::addObserver(FrameObserver& observer) { m_impl->observers.push_back(&observer); }

void MappingPipeline::setPoseSource(PoseSource source) { m_impl->options.poseSource = source; }

int MappingPipeline::openCvThreads() const { return m_impl->detectorOptions.threads; }

const TPipelineOptions& MappingPipeline::options() const { return m_impl->options; }

const CAdaptiveOctoMap& MappingPipeline::map() const { return *m_impl->maps->mapByClass<CAdaptiveOctoMap>(); }

struct MappingPipeline::Start
{
	enum class From
	{
		Nothing,     //!< a new run
		Checkpoint,  //!< the checkpoint `file`: the run resumed
		Session      //!< the finished run in the output folder `file`: its next session
	} from = From::Nothing;
	fs::path file;
};

RunSummary MappingPipeline::run(const fs::path& rawlog, const fs::path& outDir, const std::atomic<bool>* stop,
	const std::function<void(double, std::size_t)>& progress)
{
	return runFrames(rawlog, outDir, {}, stop, progress);
}

RunSummary MappingPipeline::resume(const fs::path& checkpoint, const fs::path& outDir, const std::atomic<bool>* stop,
	const std::function<void(double, std::size_t)>& progress)
{
	const auto checkpointed = detail::readCheckpointedRun(checkpoint);
	setPoseSource(checkpointed.poseSource);
	return runFrames(checkpointed.rawlog, outDir, {Start::From::Checkpoint, checkpoint}, stop, progress);
}

RunSummary MappingPipeline::continueRun(const fs::path& previous, const fs::path& rawlog, const fs::path& outDir,
	const std::atomic<bool>* stop, const std::function<void(double, std::size_t)>& progress)
{
	std::error_code ignored;
	if (fs::weakly_canonical(outDir, ignored) == fs::weakly_canonical(previous, ignored))
		throw std::invalid_argument(outDir.string() +
									": the output folder is the run being continued, which a continuation only "
									"reads: give the continued run a folder of its own");
	return runFrames(rawlog, outDir, {Start::From::Session, previous}, stop, progress);
}

void MappingPipeline::Impl::continueSession(const fs::path& previous, const fs::path& rawlog,
	detail::FrameProcessor& processor, mrpt::system::COutputLogger& log)
{
	const fs::path session = detail::sessionFile(previous);
	if (!fs::exists(io::RunFolder(previous).keyframes()))
		throw std::runtime_error(
			io::RunFolder(previous).keyframes().string() + ": missing (a finished run writes it beside its session)");
	auto& map = *maps->mapByClass<CAdaptiveOctoMap>();
	const auto configured = map.creationOptions();
	mrpt::system::CTicTac timer;
	detail::readSession(previous, *maps, processor);
	const double loadSeconds = timer.Tac();
	const auto& earlier = map.creationOptions();
	if (earlier.low.resolution != configured.low.resolution || earlier.high.resolution != configured.high.resolution)
		throw std::runtime_error(
			session.string() + ": its map is at " + std::to_string(earlier.low.resolution) + " / " +
			std::to_string(earlier.high.resolution) + " m (low / high), the configuration's at " +
			std::to_string(configured.low.resolution) + " / " + std::to_string(configured.high.resolution) +
			" m: a continued run maps at the earlier sessions' resolutions");
	try
	{
		processor.continueSession(previous);
	}
	catch (const std::runtime_error& e)
	{
		throw std::runtime_error(session.string() + ": " + e.what());
	}
	if (processor.camera()) checkSameCamera(rawlog, *processor.camera(), session);
	log.logFmt(mrpt::system::LVL_INFO,
		"continuing %s (session %zu): %zu poses, %zu persons, loaded in %.2f s; frames numbered from %zu\n",
		previous.c_str(), processor.counts().continuation->session, processor.trajectory().size(),
		map.personTracks().size(), loadSeconds, firstFrameIndex(processor));
}

void MappingPipeline::Impl::handOn(const fs::path& rawlog, const fs::path& outDir,
	const detail::FrameProcessor& processor, RunBetweenFrames& state, mrpt::system::COutputLogger& log) const
{
	mrpt::system::CTicTac timer;
	const io::RunFolder run(outDir);
	const auto& continuation = processor.counts().continuation;
	detail::FrameSequence frames(rawlog, options.repeat, options.readAheadFrames, firstFrameIndex(processor));
	const std::size_t keyframes = detail::writeKeyframeSimplemap(run.keyframes(),
		continuation ? std::optional(io::RunFolder(continuation->previous).keyframes()) : std::nullopt,
		processor.trajectory(), processor.keyframePoses(), continuation ? continuation->posesBefore : 0,
		[&frames] { return frames.next(); });
	log.logFmt(mrpt::system::LVL_INFO, "%s: %zu keyframes; writing %s\n", run.keyframes().filename().c_str(), keyframes,
		run.session().filename().c_str());
	state.writeSession();
	log.logFmt(mrpt::system::LVL_INFO, "handed on in %.2f s: %s %.1f MB, %s %.1f MB\n", timer.Tac(),
		run.session().filename().c_str(), double(fs::file_size(run.session())) / 1e6,
		run.keyframes().filename().c_str(), double(fs::file_size(run.keyframes())) / 1e6);
}

RunSummary MappingPipeline::runFrames(const fs::path& rawlog, const fs::path& outDir, const Start& start,
	const std::atomic<bool>* stop, const std::function<void(double, std::size_t)>& progress)
{
	auto& d = *m_impl;
	const auto& opt = d.options;
	const bool resume = start.from == Start::From::Checkpoint;
	detail::prepareOutputFolder(outDir);
	logStr(mrpt::system::LVL_INFO, "rawlog: " + rawlog.string() + ", poses: " + toString(opt.poseSource) + "\n");
	auto& map = d.startMaps(rawlog);
	detail::FrameProcessor processor(opt, d.odometryOptions, d.detector.get(), *d.maps, *this);
	detail::CheckpointProgress before;
	std::optional<std::size_t> resumedAfter;
	if (resume)
	{
		before = detail::readCheckpoint(start.file, *d.maps, processor);
		resumedAfter = processor.lastFrame();
		logFmt(mrpt::system::LVL_INFO, "resumed from %s: %zu frames mapped before\n", start.file.c_str(),
			processor.counts().frames);
	}
	if (start.from == Start::From::Session) d.continueSession(start.file, rawlog, processor, *this);
	// How the map rebuild starts over: cleared, or a continued session's
	// reloaded with the earlier sessions' map.
	const auto& continuation = processor.counts().continuation;
	std::function<void()> startOver = [&] { d.maps->clear(); };
	if (continuation)
		startOver = [&, previous = continuation->previous]
		{
			detail::FrameProcessor earlier(opt, d.odometryOptions, nullptr, *d.maps, *this);
			detail::readSession(previous, *d.maps, earlier);
		};
	processor.watchedBy(d.observers);
	// The clock starts before the reader thread does: reading is part of the run.
	const RunClock clock(before);
	RunBetweenFrames state(outDir, {d.iniText, fs::absolute(rawlog), opt.poseSource}, resume, clock, before.log, *this,
		*d.maps, processor);
	// A missing rawlog fails here.
	detail::FrameSequence frames(rawlog, opt.repeat, opt.readAheadFrames, firstFrameIndex(processor));
	try
	{
		const bool endedByObserver = !mapFrames(opt.maxFrames, frames, processor, d.observers, state, stop, progress);
		for (auto* o : d.observers) o->onFramesEnded(state);
		processor.finish();
		frames.close();
		if (continuation && !continuation->placedAtFrame)
			throw std::runtime_error(rawlog.string() + ": none of its " + std::to_string(continuation->unplacedFrames) +
									 " frames was placed among the keyframes of " + continuation->previous.string() +
									 " (do they see a place it saw?): nothing merged, no outputs written");
		if (processor.counts().frames == 0)
			throw std::runtime_error(rawlog.string() + ": no frame could be mapped" +
									 (frames.skipped().empty() ? "" : " (" + frames.skipped().front() + ")"));
		const bool interrupted = (stop && stop->load()) || endedByObserver;
		const auto rebuild = rebuildMap(opt, rawlog, processor, interrupted, startOver, *this);
		RunSummary summary = d.summarise(processor, frames, clock.read());
		summary.interrupted = interrupted;
		summary.mapRebuild = rebuild;
		summary.checkpoint = state.checkpointTimes().summary();
		summary.resumedAfterFrame = resumedAfter;
		logFmt(mrpt::system::LVL_INFO, "%zu frames in %.2f s (%.1f fps, real-time factor %.2f)%s\n", summary.frames,
			summary.seconds, summary.fps, summary.realTimeFactor, summary.interrupted ? ", interrupted" : "");
		// What a next run continues, of a finished run only.
		if (!interrupted) d.handOn(rawlog, outDir, processor, state, *this);
		detail::RunRecord record{rawlog, &opt, d.detector ? d.detector->description() : std::string("none"),
			processor.trajectory(), processor.trackedPoses(), processor.personDetections(),
			frames.peakMemoryPerReplay(), before.log + getLogAsString() + frames.log()};
		const FinishedRun finished{summary, map, processor.trajectory(), processor.lastFrame()};
		detail::writeRunOutputs(outDir, summary, record, map,
			[&](io::JsonWriter& stats)
			{
				for (auto* o : d.observers) o->writeStats(finished, stats);
			});
		for (auto* o : d.observers) o->onRunFinished(finished);
		return summary;
	}
	catch (...)
	{
		for (auto* o : d.observers) o->onRunFailed(state);
		throw;
	}
}
}  // namespace avm::pipeline
