#include "RunOutputs.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "avm/persons/PersonColour.h"
#include "avm/io/AtomicFile.h"
#include "avm/io/RunFolder.h"
#include "avm/persons/PersonShapesPly.h"
#include "avm/persons/PersonsCsv.h"
#include "avm/pipeline/MapPictures.h"

namespace avm::pipeline::detail
{
namespace fs = std::filesystem;

namespace
{
struct TreeStats
{
	CAdaptiveOctoMap::TTreeStats low, high;
};

void writeText(const fs::path& file, const std::string& text)
{
	io::writeFileAtomically(file,
		[&](const fs::path& tmp)
		{
			std::ofstream out(tmp);
			out << text;
			if (!out.flush()) throw std::runtime_error(file.string() + ": write failed");
		});
}

/** detections.txt: one line per person box, with the person and region it
 *  gave, or why none. */
std::string detectionsText(const std::vector<PersonDetectionRecord>& detections)
{
	std::ostringstream out;
	out << "# frame timestamp class score x y w h | person id, region min_x min_y min_z max_x max_y max_z [m]\n";
	for (const auto& d : detections)
	{
		const auto& p = d.person;
		char line[256];
		std::snprintf(line, sizeof(line), "%zu %.6f %s %.3f %.1f %.1f %.1f %.1f", d.frameIndex, d.timestamp,
			p.className.c_str(), p.score, p.box.x, p.box.y, p.box.width, p.box.height);
		out << line;
		if (!d.seen)
			out << " | no pose for this frame\n";
		else if (!d.seen->regionBox)
			out << " | skipped: " << d.seen->skipReason << "\n";
		else
		{
			const auto& b = *d.seen->regionBox;
			std::snprintf(line, sizeof(line), " | %u %.3f %.3f %.3f %.3f %.3f %.3f\n", d.seen->personId, b.min.x,
				b.min.y, b.min.z, b.max.x, b.max.y, b.max.z);
			out << line;
		}
	}
	return out.str();
}

/** map_top.png and map_perspective.png. */
void drawPictures(const io::RunFolder& run, const io::Trajectory& trajectory, const CAdaptiveOctoMap& map,
	const TreeStats& trees, int size)
{
	MapPictureContent content;
	for (const auto tree : {Resolution::Low, Resolution::High})
		map.forEachLeaf(tree,
			[&](const TLeafVoxel& v)
			{
				if (v.occupied)
					content.voxels.push_back(
						{mrpt::math::TPoint3Df(v.center), static_cast<float>(v.size), tree == Resolution::High});
			});
	content.trajectory = trajectory;
	for (const auto& r : map.highResolutionRegions())
		content.regions.insert(content.regions.end(), r.boxes.begin(), r.boxes.end());
	for (const auto& t : map.confirmedPersons()) content.persons.push_back({t.id, t.position, t.shape});
	content.lowResolution = trees.low.resolution;
	content.highResolution = trees.high.resolution;
	drawTopView(content, run.topPicture(), size);
	drawPerspectiveView(content, run.perspectivePicture(), size);
}

void writeStages(io::JsonWriter& json, const RunSummary& summary)
{
	json.beginObject("stages");
	for (const auto& [name, s] : {std::pair{"odometry", summary.odometry}, {"detection", summary.detection},
			 {"detection_wait", summary.detectionWait}, {"map", summary.map}, {"map_cpu", summary.mapCpu},
			 {"odometry_cpu", summary.odometryCpu}, {"detection_cpu", summary.detectionCpu},
			 {"checkpoint", summary.checkpoint}})
		json.beginObject(name)
			.value("mean_ms", s.meanMs)
			.value("median_ms", s.medianMs)
			.value("p95_ms", s.p95Ms)
			.value("count", s.count)
			.endObject();
	json.endObject();
}

void writePoint(io::JsonWriter& json, const char* name, const mrpt::math::TPoint3D& p)
{
	json.beginArray(name);
	for (double v : {p.x, p.y, p.z}) json.element(v);
	json.endArray();
}

void writeRegionsAndPersons(io::JsonWriter& json, const CAdaptiveOctoMap& map)
{
	json.value("region_lifetime", toString(map.insertionOptions.regionLifetime));
	json.beginArray("regions");
	for (const auto& r : map.highResolutionRegions())
	{
		json.beginObject().value("person", static_cast<std::size_t>(r.regionId)).beginArray("boxes");
		for (const auto& b : r.boxes)
		{
			json.beginObject();
			writePoint(json, "min", b.min);
			writePoint(json, "max", b.max);
			json.endObject();
		}
		json.endArray().endObject();
	}
	json.endArray();
	json.beginArray("persons");
	for (const auto& t : map.confirmedPersons())
	{
		json.beginObject()
			.value("id", static_cast<std::size_t>(t.id))
			.value("first_frame", t.firstFrame)
			.value("last_frame", t.lastFrame)
			.value("first_time", t.firstTime)
			.value("last_time", t.lastTime)
			.value("sightings", t.sightings);
		writePoint(json, "position", t.position);
		writePoint(json, "box_min", t.box.min);
		writePoint(json, "box_max", t.box.max);
		json.endObject();
	}
	json.endArray();
}

/** stats.json: the summary, the map's trees, regions and persons, what the observers measured. */
std::string statsJson(const RunSummary& summary, const RunRecord& record, const CAdaptiveOctoMap& map,
	const TreeStats& trees, const std::function<void(io::JsonWriter&)>& observersStats)
{
	const auto& opt = *record.options;
	io::JsonWriter json;
	json.beginObject()
		.value("rawlog", record.rawlog.string())
		.value("pose_source", toString(opt.poseSource))
		.value("frames", summary.frames)
		.value("skipped_frames", summary.skippedFrames)
		.value("interrupted", summary.interrupted)
		.value("seconds", summary.seconds)
		.value("fps", summary.fps)
		.value("real_time_factor", summary.realTimeFactor)
		.value("peak_memory_mb", summary.peakMemoryMb)
		.value("cpu_ms_per_frame", summary.cpuMsPerFrame);
	json.value(
		"cpu_stolen_percent", summary.stolenCpuShare ? std::optional(100 * *summary.stolenCpuShare) : std::nullopt);
	json.beginArray("peak_memory_mb_per_replay");
	for (const double mb : record.peakMemoryPerReplay) json.element(mb);
	json.endArray();
	writeStages(json, summary);
	json.value("checkpoint_interval_s", opt.checkpointIntervalSeconds);
	json.value("resumed_after_frame", summary.resumedAfterFrame);
	if (const auto& c = summary.continuation)
		json.beginObject("continuation")
			.value("previous", c->previous.string())
			.value("session", c->session)
			.value("poses_before", c->posesBefore)
			.value("first_frame_index", c->firstFrameIndex)
			.value("unplaced_frames", c->unplacedFrames)
			.value("placed_at_frame", c->placedAtFrame)
			.endObject();
	json.beginObject("detection")
		.value("detector", record.detector)
		.value("schedule", toString(opt.detectionSchedule))
		.value("every_n_frames", static_cast<int>(opt.detectEveryN));
	if (opt.detectionSchedule == DetectionSchedule::OnChange)
		json.value("max_interval_frames", static_cast<int>(opt.detectMaxInterval));
	json.value("asynchronous", opt.asyncDetection)
		.value("lag_frames", static_cast<int>(opt.detectionLagFrames))
		.value("runs", summary.detectionRuns)
		.value("frames_with_person", summary.framesWithPerson);
	json.beginObject("started_by");
	for (const auto& [cause, runs] : summary.detectionsStartedBy) json.value(cause, runs);
	json.endObject().endObject();
	json.value("switch_frame", summary.switchFrame);
	json.beginObject("map");
	for (const auto& [name, s] : {std::pair{"low", trees.low}, {"high", trees.high}})
		json.beginObject(name)
			.value("resolution_m", s.resolution)
			.value("occupied_voxels", s.occupiedLeaves)
			.value("free_voxels", s.freeLeaves)
			.value("memory_bytes", s.memoryBytes)
			.value("bt_bytes", s.binaryBytes)
			.endObject();
	json.endObject();
	writeRegionsAndPersons(json, map);
	observersStats(json);
	json.value("odometry_ate_rmse_m", summary.ateRmse);
	json.value("odometry_loops_closed", summary.loopsClosed);
	json.beginObject("map_rebuild")
		.value("when", toString(opt.rebuildMap))
		.value("done", summary.mapRebuild.has_value());
	if (summary.mapRebuild)
		json.value("frames", summary.mapRebuild->frames)
			.value("seconds", summary.mapRebuild->seconds)
			.value("cpu_seconds", summary.mapRebuild->cpuSeconds);
	json.endObject();
	json.endObject();
	return json.str();
}

/** One line per pose of trajectory.txt: its timestamp and whether the
 *  odometry tracked it (1) or bridged it by its motion model (0). */
std::string trajectoryStatusText(const io::Trajectory& poses, const std::vector<bool>& tracked)
{
	std::string text =
		"# avm-map: per pose of trajectory.txt, timestamp and tracked (1) or bridged by the motion model after a "
		"tracking loss (0)\n";
	char line[64];
	for (std::size_t i = 0; i < poses.size(); ++i)
	{
		std::snprintf(line, sizeof(line), "%.6f %d\n", poses[i].timestamp, int(tracked.at(i)));
		text += line;
	}
	return text;
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
}  // namespace

void writeRunOutputs(const fs::path& outDir, const RunSummary& summary, const RunRecord& record,
	const CAdaptiveOctoMap& map, const std::function<void(io::JsonWriter&)>& observersStats)
{
	const io::RunFolder run(outDir);
	const TreeStats trees{map.lowResolutionStats(), map.highResolutionStats()};
	map.saveMetricMapRepresentationToFile(run.mapPrefix());
	// A TUM file lists its poses in time order, which sessions mapped in
	// another order than they were recorded do not have.
	io::Trajectory poses;
	std::vector<bool> tracked;
	for (const auto i : io::timeOrder(record.trajectory))
	{
		poses.push_back(record.trajectory[i]);
		tracked.push_back(record.trackedPoses.at(i));
	}
	io::writeTumTrajectory(run.trajectory(), poses,
		"avm-map camera trajectory (" + toString(record.options->poseSource) + "), optical frame, TUM format");
	writeText(run.trajectoryStatus(), trajectoryStatusText(poses, tracked));
	writeText(run.detections(), detectionsText(record.personDetections));
	const auto persons = map.confirmedPersons();
	writeText(run.persons(), persons::personsCsvText(persons));
	writeText(run.personShapes(), persons::personShapesPlyText(persons, persons::kPersonColour));
	if (record.options->pictureSize > 0) drawPictures(run, record.trajectory, map, trees, record.options->pictureSize);
	writeText(run.stats(), statsJson(summary, record, map, trees, observersStats));
	writeText(run.log(), record.log);
}

void prepareOutputFolder(const fs::path& dir)
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
}  // namespace avm::pipeline::detail
