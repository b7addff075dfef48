#include "avm/pipeline/MappingPipeline.h"

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/system/CTicTac.h>
#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <future>
#include <map>
#include <sstream>

#include "avm/io/IniOptions.h"
#include "FrameSequence.h"
#include "JsonWriter.h"
#include "avm/detection/Detector.h"
#include "avm/detection/PersonRegion.h"
#include "avm/evaluation/TrajectoryEvaluation.h"
#include "avm/io/AtomicFile.h"
#include "avm/io/RawlogFrameReader.h"
#include "avm/io/Trajectory.h"
#include "avm/maps/CAdaptiveOctoMap.h"
#include "avm/odometry/VisualOdometry.h"
#include "avm/pipeline/MapPictures.h"
#include "avm/pipeline/StageTimes.h"

namespace avm::pipeline
{
namespace fs = std::filesystem;
using mrpt::obs::CObservation3DRangeScan;
using mrpt::poses::CPose3D;

PoseSource poseSourceFromString(const std::string& name)
{
	if (name == "vo") return PoseSource::VisualOdometry;
	if (name == "gt") return PoseSource::GroundTruth;
	throw std::invalid_argument("pose source must be 'vo' or 'gt', not '" + name + "'");
}

std::string toString(PoseSource source) { return source == PoseSource::GroundTruth ? "gt" : "vo"; }

void TPipelineOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
	const auto bad = [&](const std::string& key, const std::string& value, const std::string& why) {
		return std::invalid_argument("[" + s + "] " + key + " = " + value + ": " + why);
	};
	const std::string source = cfg.read_string(s, "pose_source", toString(poseSource));
	try
	{
		poseSource = poseSourceFromString(source);
	}
	catch (const std::invalid_argument&)
	{
		throw bad("pose_source", source, "must be vo or gt");
	}
	const int every = cfg.read_int(s, "detect_every_n", static_cast<int>(detectEveryN));
	if (every < 0) throw bad("detect_every_n", std::to_string(every), "must be >= 0 (0 = no detection)");
	detectEveryN = static_cast<unsigned>(every);
	asyncDetection = cfg.read_bool(s, "async_detection", asyncDetection);
	asyncMapping = cfg.read_bool(s, "async_mapping", asyncMapping);
	startAtGroundTruth = cfg.read_bool(s, "start_at_ground_truth", startAtGroundTruth);
	const int frames = cfg.read_int(s, "max_frames", static_cast<int>(maxFrames));
	if (frames < 0) throw bad("max_frames", std::to_string(frames), "must be >= 0 (0 = all)");
	maxFrames = static_cast<std::size_t>(frames);
	pictureSize = cfg.read_int(s, "picture_size", pictureSize);
	if (pictureSize != 0 && (pictureSize < 200 || pictureSize > 8000))
		throw bad("picture_size", std::to_string(pictureSize), "must be 0 (none) or 200..8000 px");
	const int replays = cfg.read_int(s, "repeat", static_cast<int>(repeat));
	if (replays < 1) throw bad("repeat", std::to_string(replays), "must be >= 1");
	repeat = static_cast<unsigned>(replays);
	const int ahead = cfg.read_int(s, "read_ahead_frames", static_cast<int>(readAheadFrames));
	if (ahead < 0 || ahead > 100) throw bad("read_ahead_frames", std::to_string(ahead), "must be 0..100 (0 = no reader thread)");
	readAheadFrames = static_cast<unsigned>(ahead);
	mapSection = cfg.read_string(s, "map_section", mapSection);
	if (mapSection.empty()) throw bad("map_section", "", "must name the map definition section");
}

void TPipelineOptions::saveToConfigFile(mrpt::config::CConfigFileBase& cfg, const std::string& s) const
{
	cfg.write(s, "pose_source", toString(poseSource));
	cfg.write(s, "detect_every_n", static_cast<int>(detectEveryN));
	cfg.write(s, "async_detection", asyncDetection);
	cfg.write(s, "async_mapping", asyncMapping);
	cfg.write(s, "start_at_ground_truth", startAtGroundTruth);
	cfg.write(s, "max_frames", static_cast<int>(maxFrames));
	cfg.write(s, "picture_size", pictureSize);
	cfg.write(s, "repeat", static_cast<int>(repeat));
	cfg.write(s, "read_ahead_frames", static_cast<int>(readAheadFrames));
	cfg.write(s, "map_section", mapSection);
}

namespace
{
constexpr const char* kPipelineSection = "pipeline";
constexpr const char* kOdometrySection = "odometry";
constexpr const char* kDetectionSection = "detection";

StageReport reportOf(const StageTimes& t)
{
	const auto s = t.summary();
	return {s.meanMs, s.medianMs, s.p95Ms, s.count};
}

/** A detection run on one frame: the boxes, and the frame they belong to
 *  (its depth is needed for the 3D regions, with the pose of that frame). */
struct DetectionResult
{
	std::size_t frameIndex = 0;
	double timestamp = 0;
	CObservation3DRangeScan::Ptr observation;
	std::vector<detection::Detection> persons;
	double milliseconds = 0;
};

void writeText(const fs::path& file, const std::string& text)
{
	io::writeFileAtomically(file, [&](const fs::path& tmp) {
		std::ofstream out(tmp);
		out << text;
		if (!out.flush()) throw std::runtime_error(file.string() + ": write failed");
	});
}

/** Temporaries of earlier runs that were killed while writing
 *  (".name.partial-PID.ext", see io::temporaryPathFor) whose process is gone. */
void removeStaleTemporaries(const fs::path& dir)
{
	for (const auto& e : fs::directory_iterator(dir))
	{
		const std::string name = e.path().filename().string();
		const auto at = name.find(".partial-");
		if (name.empty() || name[0] != '.' || at == std::string::npos) continue;
		const long pid = std::strtol(name.c_str() + at + 9, nullptr, 10);
		if (pid > 0 && !fs::exists("/proc/" + std::to_string(pid))) fs::remove_all(e.path());
	}
}

void checkWritable(const fs::path& dir)
{
	std::error_code ec;
	fs::create_directories(dir, ec);
	if (ec || !fs::is_directory(dir))
		throw std::runtime_error(dir.string() + ": cannot create the output folder (" + ec.message() + ")");
	const fs::path probe = io::temporaryPathFor(dir / "write-check.txt");
	std::ofstream(probe) << "avm";
	const bool ok = fs::exists(probe) && fs::file_size(probe, ec) == 3;
	fs::remove(probe, ec);
	if (!ok) throw std::runtime_error(dir.string() + ": output folder is not writable");
	removeStaleTemporaries(dir);
}

/** The adaptive map's sections: [<map>_adaptiveOctoMap_NN_creationOpts] etc. */
void warnUnknownMapKeys(
	const mrpt::config::CConfigFileBase& ini, const std::string& mapSection, mrpt::system::COutputLogger& log)
{
	// Keys MRPT's map initializer reads itself in every _creationOpts section.
	static const std::vector<std::string> generic = {
		"enableSaveAs3DObject", "enableObservationLikelihood", "enableObservationInsertion"};
	const CAdaptiveOctoMap defaults;
	const auto check = [&](const std::string& section, const mrpt::config::CLoadableOptions& opts, bool creation) {
		for (const auto& key : io::unknownKeys(ini, section, opts))
			if (!creation || std::find(generic.begin(), generic.end(), key) == generic.end())
				log.logStr(mrpt::system::LVL_WARN, "unknown key [" + section + "] " + key + " (ignored)\n");
	};
	const int count = ini.read_int(mapSection, "adaptiveOctoMap_count", 0);
	for (int i = 0; i < count; ++i)
	{
		char prefix[64];
		std::snprintf(prefix, sizeof(prefix), "%s_adaptiveOctoMap_%02d", mapSection.c_str(), i);
		const std::string p = prefix;
		check(p + "_creationOpts", defaults.creationOptions(), true);
		check(p + "_insertOpts", defaults.insertionOptions, false);
		check(p + "_likelihoodOpts", defaults.likelihoodOptions, false);
		check(p + "_renderOpts", defaults.renderingOptions, false);
	}
}

/** The visible leaves of both trees, for the pictures. */
std::vector<PictureVoxel> occupiedVoxels(const CAdaptiveOctoMap& map)
{
	std::vector<PictureVoxel> out;
	for (const auto tree : {Resolution::Low, Resolution::High})
		map.forEachLeaf(tree, [&](const TLeafVoxel& v) {
			if (v.occupied)
				out.push_back({mrpt::math::TPoint3Df(v.center), static_cast<float>(v.size), tree == Resolution::High});
		});
	return out;
}
}  // namespace

struct MappingPipeline::Impl
{
	mrpt::config::CConfigFileMemory ini;
	fs::path projectRoot;
	TPipelineOptions options;
	odometry::TOdometryOptions odometryOptions;
	detection::TDetectorOptions detectorOptions;
	mrpt::maps::TSetOfMetricMapInitializers mapDefinition;
	std::unique_ptr<detection::DetectorBase> detector;
	mrpt::maps::CMultiMetricMap::Ptr maps;
	std::shared_ptr<CAdaptiveOctoMap> adaptive;
};

MappingPipeline::MappingPipeline(const mrpt::config::CConfigFileBase& ini, const fs::path& projectRoot)
	: mrpt::system::COutputLogger("avm-map"), m_impl(std::make_unique<Impl>())
{
	auto& d = *m_impl;
	logging_enable_keep_record = true;  // for avm-map.log
	d.projectRoot = projectRoot;
	d.options.loadFromConfigFile(ini, kPipelineSection);
	d.odometryOptions.loadFromConfigFile(ini, kOdometrySection);
	d.detectorOptions.loadFromConfigFile(ini, kDetectionSection);
	d.mapDefinition.loadFromConfigFile(ini, d.options.mapSection);

	const auto warnUnknown = [&](const std::string& section, const mrpt::config::CLoadableOptions& opts) {
		for (const auto& key : io::unknownKeys(ini, section, opts))
			logStr(mrpt::system::LVL_WARN, "unknown key [" + section + "] " + key + " (ignored)\n");
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

	// OpenCV's thread count is process-wide: the ini's value for the detector
	// applies to the whole run.
	if (d.detectorOptions.threads > 0) cv::setNumThreads(d.detectorOptions.threads);
	if (d.options.detectEveryN > 0)
	{
		d.detector = detection::createDetector(d.detectorOptions, projectRoot);
		logStr(mrpt::system::LVL_INFO, "detector: " + d.detector->description() + "\n");
	}
	else
		logStr(mrpt::system::LVL_INFO, "detector: none (detect_every_n = 0)\n");

	// Fail on a missing map definition now, not after the first frame.
	d.maps = mrpt::maps::CMultiMetricMap::Create(d.mapDefinition);
	if (!d.maps->mapByClass<CAdaptiveOctoMap>())
		throw std::invalid_argument(
			"[" + d.options.mapSection + "] defines no adaptive map: add adaptiveOctoMap_count = 1");
}

MappingPipeline::~MappingPipeline() = default;

void MappingPipeline::setPoseSource(PoseSource source) { m_impl->options.poseSource = source; }

const CAdaptiveOctoMap& MappingPipeline::map() const { return *m_impl->adaptive; }

RunSummary MappingPipeline::run(
	const fs::path& rawlog, const fs::path& outDir, const std::atomic<bool>* stop,
	const std::function<void(double, std::size_t)>& progress)
{
	auto& d = *m_impl;
	const auto& opt = d.options;
	checkWritable(outDir);

	logStr(mrpt::system::LVL_INFO, "rawlog: " + rawlog.string() + ", poses: " + toString(opt.poseSource) + "\n");
	d.maps = mrpt::maps::CMultiMetricMap::Create(d.mapDefinition);
	d.adaptive = d.maps->mapByClass<CAdaptiveOctoMap>();
	// A switch at a fraction of the run needs the run's length.
	if (d.adaptive->insertionOptions.switchAtFraction >= 0 && d.adaptive->insertionOptions.expectedFrameCount == 0)
	{
		const std::size_t frames = io::countFrames(rawlog);
		d.adaptive->setExpectedFrameCount(opt.maxFrames ? std::min(opt.maxFrames, frames) : frames);
	}

	// The clock starts before the reader thread does: reading is part of the run.
	mrpt::system::CTicTac wallClock;
	const double cpuAtStart = processCpuSeconds();
	const StolenCpuTime stolenDuringRun;
	detail::FrameSequence frames(rawlog, opt.repeat, opt.readAheadFrames);

	std::optional<odometry::VisualOdometry> vo;
	StageTimes odometryTimes, detectionTimes, mapTimes;
	RunSummary summary;
	io::Trajectory trajectory, groundTruth;
	std::map<std::size_t, CPose3D> recentPoses;  // frame index -> pose, for late detections
	std::vector<cv::Rect> latestPersonBoxes;
	std::future<DetectionResult> pendingDetection;
	std::ostringstream detectionsText;
	detectionsText << "# frame timestamp class score x y w h | region min_x min_y min_z max_x max_y max_z [m]\n";

	const auto runDetector = [&d](std::size_t index, double t, CObservation3DRangeScan::Ptr obs) {
		DetectionResult r{index, t, obs, {}, 0};
		mrpt::system::CTicTac timer;
		r.persons = detection::personsOnly(d.detector->detect(io::colourImage(*obs)));
		r.milliseconds = timer.Tac() * 1e3;
		return r;
	};
	// Boxes mask the odometry at once; regions need the pose of their frame
	// and wait until no insertion is running (addRegions).
	std::vector<DetectionResult> detectionsWithoutRegions;
	const auto useBoxes = [&](DetectionResult r) {
		detectionTimes.add(r.milliseconds);
		++summary.detectionRuns;
		if (!r.persons.empty()) ++summary.framesWithPerson;
		latestPersonBoxes.clear();
		for (const auto& p : r.persons) latestPersonBoxes.push_back(cv::Rect(p.box));
		detectionsWithoutRegions.push_back(std::move(r));
	};
	const auto addRegions = [&](const DetectionResult& r) {
		const auto pose = recentPoses.find(r.frameIndex);
		const cv::Mat depth = r.persons.empty() ? cv::Mat() : io::depthInMetres(*r.observation);
		for (const auto& p : r.persons)
		{
			char line[256];
			std::snprintf(line, sizeof(line), "%zu %.6f %s %.3f %.1f %.1f %.1f %.1f", r.frameIndex, r.timestamp,
				p.className.c_str(), p.score, p.box.x, p.box.y, p.box.width, p.box.height);
			detectionsText << line;
			if (pose == recentPoses.end())
			{
				detectionsText << " | no pose for this frame\n";
				continue;
			}
			const auto region = detection::estimatePersonRegion(
				p, depth, r.observation->cameraParams, pose->second, d.detectorOptions);
			if (!region.box)
			{
				detectionsText << " | skipped: " << region.skipReason << "\n";
				continue;
			}
			d.adaptive->addHighResolutionRegion(*region.box);
			++summary.regions;
			const auto& b = *region.box;
			std::snprintf(line, sizeof(line), " | %.3f %.3f %.3f %.3f %.3f %.3f\n", b.min.x, b.min.y, b.min.z,
				b.max.x, b.max.y, b.max.z);
			detectionsText << line;
		}
	};
	const auto addWaitingRegions = [&] {
		for (const auto& r : detectionsWithoutRegions) addRegions(r);
		detectionsWithoutRegions.clear();
	};
	const auto collectDetection = [&](bool wait) {
		if (!pendingDetection.valid()) return;
		if (!wait && pendingDetection.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
		useBoxes(pendingDetection.get());
	};

	// The map insertion in flight (asynchronous mapping) and its frame.
	// Joined before anything else touches the map.
	std::future<double> pendingInsertion;  // its duration [ms]
	std::size_t insertingFrame = 0;
	const auto finishInsertion = [&] {
		if (!pendingInsertion.valid()) return;
		mapTimes.add(pendingInsertion.get());
		if (!summary.switchFrame && d.adaptive->isHighResolutionActive()) summary.switchFrame = insertingFrame;
	};

	while (!(stop && stop->load()))
	{
		if (opt.maxFrames && summary.frames >= opt.maxFrames) break;
		auto frame = frames.next();
		if (!frame) break;
		const auto& obs = frame->observation;
		const double t = frame->timestamp();

		// 1. Person boxes: on the worker thread, or here when synchronous.
		if (d.detector && frame->index % opt.detectEveryN == 0)
		{
			if (!opt.asyncDetection)
				useBoxes(runDetector(frame->index, t, obs));
			else
			{
				// Every N-th frame is detected: a detection still running
				// holds the loop up rather than being skipped.
				collectDetection(true);
				pendingDetection = std::async(std::launch::async, runDetector, frame->index, t, obs);
			}
		}

		// 2. Camera pose (optical frame in the world).
		CPose3D pose;
		if (opt.poseSource == PoseSource::GroundTruth)
		{
			if (!frame->groundTruth)
			{
				logFmt(mrpt::system::LVL_WARN, "frame %zu: no usable ground-truth pose, frame not mapped\n",
					frame->index);
				++summary.skippedFrames;
				continue;
			}
			pose = *frame->groundTruth;
		}
		else
		{
			if (!vo)
				vo.emplace(
					d.odometryOptions, opt.startAtGroundTruth && frame->groundTruth
										   ? *frame->groundTruth
										   : io::opticalToSensorPose().getOppositeScalar());
			mrpt::system::CTicTac timer;
			const auto estimate = vo->process(*obs, latestPersonBoxes);
			odometryTimes.add(timer.Tac() * 1e3);
			if (!estimate.tracked)
				logFmt(mrpt::system::LVL_WARN, "frame %zu: odometry lost (%s), pose bridged\n", frame->index,
					estimate.status.c_str());
			pose = estimate.pose;
		}
		if (!io::isFinite(pose))
		{
			logFmt(mrpt::system::LVL_WARN, "frame %zu: pose is not finite, frame not mapped\n", frame->index);
			++summary.skippedFrames;
			continue;
		}
		recentPoses[frame->index] = pose;
		while (recentPoses.size() > 64) recentPoses.erase(recentPoses.begin());
		if (frame->groundTruth) groundTruth.push_back({t, *frame->groundTruth});

		// 3. Regions of the detections that are ready, once the previous
		// frame is in the map: the same order as without a mapping thread.
		collectDetection(false);
		finishInsertion();
		addWaitingRegions();

		// 4. The map: on the worker thread while the next frame's odometry runs.
		const auto insert = [&maps = *d.maps, obs, pose] {
			mrpt::system::CTicTac timer;
			maps.insertObservation(*obs, pose);
			return timer.Tac() * 1e3;
		};
		insertingFrame = frame->index;
		pendingInsertion = std::async(opt.asyncMapping ? std::launch::async : std::launch::deferred, insert);
		if (!opt.asyncMapping) finishInsertion();

		trajectory.push_back({t, pose});
		++summary.frames;
		if (progress) progress(frames.progress(), summary.frames);
	}
	finishInsertion();
	collectDetection(true);
	addWaitingRegions();
	summary.seconds = wallClock.Tac();
	const double cpuSeconds = processCpuSeconds() - cpuAtStart;
	summary.stolenCpuShare = stolenDuringRun.stolen();
	frames.close();
	summary.interrupted = stop && stop->load();
	summary.skippedFrames += frames.skipped().size();
	if (summary.frames == 0)
	{
		std::string why = rawlog.string() + ": no frame could be mapped";
		if (!frames.skipped().empty()) why += " (" + frames.skipped().front() + ")";
		throw std::runtime_error(why);
	}
	summary.fps = summary.frames / std::max(summary.seconds, 1e-9);
	summary.cpuMsPerFrame = cpuSeconds * 1e3 / double(summary.frames);
	if (trajectory.size() > 1)
	{
		const double recorded = (trajectory.back().timestamp - trajectory.front().timestamp) *
								double(trajectory.size()) / double(trajectory.size() - 1);
		summary.realTimeFactor = recorded / std::max(summary.seconds, 1e-9);
	}
	summary.peakMemoryMb = peakMemoryMb();
	summary.odometry = reportOf(odometryTimes);
	summary.detection = reportOf(detectionTimes);
	summary.map = reportOf(mapTimes);
	if (opt.poseSource == PoseSource::VisualOdometry && groundTruth.size() >= 3)
		summary.ateRmse = evaluation::evaluateTrajectory(trajectory, groundTruth, {}).ate.rmse;

	// Outputs, each complete or absent.
	const auto low = d.adaptive->lowResolutionStats(), high = d.adaptive->highResolutionStats();
	d.adaptive->saveMetricMapRepresentationToFile((outDir / "map").string());
	io::writeTumTrajectory(
		outDir / "trajectory.txt", trajectory,
		"avm-map camera trajectory (" + toString(opt.poseSource) + "), optical frame, TUM format");
	writeText(outDir / "detections.txt", detectionsText.str());
	if (opt.pictureSize > 0)
	{
		MapPictureContent content;
		content.voxels = occupiedVoxels(*d.adaptive);
		content.trajectory = trajectory;
		content.regions = d.adaptive->highResolutionRegions();
		content.lowResolution = low.resolution;
		content.highResolution = high.resolution;
		drawTopView(content, outDir / "map_top.png", opt.pictureSize);
		drawPerspectiveView(content, outDir / "map_perspective.png", opt.pictureSize);
	}

	JsonWriter json;
	json.beginObject()
		.value("rawlog", rawlog.string())
		.value("pose_source", toString(opt.poseSource))
		.value("frames", summary.frames)
		.value("skipped_frames", summary.skippedFrames)
		.value("interrupted", summary.interrupted)
		.value("seconds", summary.seconds)
		.value("fps", summary.fps)
		.value("real_time_factor", summary.realTimeFactor)
		.value("peak_memory_mb", summary.peakMemoryMb)
		.value("cpu_ms_per_frame", summary.cpuMsPerFrame);
	if (summary.stolenCpuShare)
		json.value("cpu_stolen_percent", 100 * *summary.stolenCpuShare);
	else
		json.null("cpu_stolen_percent");
	json.beginArray("peak_memory_mb_per_replay");
	for (const double mb : frames.peakMemoryPerReplay()) json.element(mb);
	json.endArray();
	json.beginObject("stages");
	for (const auto& [name, s] :
		 {std::pair{"odometry", summary.odometry}, {"detection", summary.detection}, {"map", summary.map}})
		json.beginObject(name)
			.value("mean_ms", s.meanMs)
			.value("median_ms", s.medianMs)
			.value("p95_ms", s.p95Ms)
			.value("count", s.count)
			.endObject();
	json.endObject();
	json.beginObject("detection")
		.value("detector", d.detector ? d.detector->description() : std::string("none"))
		.value("every_n_frames", static_cast<int>(opt.detectEveryN))
		.value("asynchronous", opt.asyncDetection)
		.value("runs", summary.detectionRuns)
		.value("frames_with_person", summary.framesWithPerson)
		.endObject();
	if (summary.switchFrame)
		json.value("switch_frame", *summary.switchFrame);
	else
		json.null("switch_frame");
	json.beginObject("map");
	for (const auto& [name, s] : {std::pair{"low", low}, {"high", high}})
		json.beginObject(name)
			.value("resolution_m", s.resolution)
			.value("occupied_voxels", s.occupiedLeaves)
			.value("free_voxels", s.freeLeaves)
			.value("memory_bytes", s.memoryBytes)
			.value("bt_bytes", s.binaryBytes)
			.endObject();
	json.endObject();
	json.beginArray("regions");
	for (const auto& r : d.adaptive->highResolutionRegions())
	{
		json.beginObject().beginArray("min");
		for (double v : {r.min.x, r.min.y, r.min.z}) json.element(v);
		json.endArray().beginArray("max");
		for (double v : {r.max.x, r.max.y, r.max.z}) json.element(v);
		json.endArray().endObject();
	}
	json.endArray();
	if (summary.ateRmse)
		json.value("odometry_ate_rmse_m", *summary.ateRmse);
	else
		json.null("odometry_ate_rmse_m");
	json.endObject();
	writeText(outDir / "stats.json", json.str());

	logFmt(mrpt::system::LVL_INFO, "%zu frames in %.2f s (%.1f fps, real-time factor %.2f)%s\n", summary.frames,
		summary.seconds, summary.fps, summary.realTimeFactor, summary.interrupted ? ", interrupted" : "");
	writeText(outDir / "avm-map.log", getLogAsString() + frames.log());
	return summary;
}
}  // namespace avm::pipeline
