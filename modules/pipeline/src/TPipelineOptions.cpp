// [pipeline]: TPipelineOptions' keys, and the names of its choices.
#include <cstdint>

#include "avm/io/EnumNames.h"
#include "avm/io/IniKeys.h"
#include "avm/pipeline/MappingPipeline.h"

namespace avm::pipeline
{
namespace
{
const io::EnumNames<PoseSource>& poseSourceNames()
{
	static const io::EnumNames<PoseSource> names(
		"pose source", {{PoseSource::VisualOdometry, "vo"}, {PoseSource::GroundTruth, "gt"}});
	return names;
}

const io::EnumNames<MapRebuild>& mapRebuildNames()
{
	static const io::EnumNames<MapRebuild> names("map rebuild",
		{{MapRebuild::Never, "never"}, {MapRebuild::AfterLoops, "after_loops"}, {MapRebuild::Always, "always"}});
	return names;
}
const io::EnumNames<DetectionSchedule>& detectionScheduleNames()
{
	static const io::EnumNames<DetectionSchedule> names(
		"detection schedule", {{DetectionSchedule::Fixed, "fixed"}, {DetectionSchedule::OnChange, "on_change"}});
	return names;
}
}  // namespace

PoseSource poseSourceFromString(const std::string& name) { return poseSourceNames().parse(name); }

std::string toString(PoseSource source) { return poseSourceNames().name(source); }

MapRebuild mapRebuildFromString(const std::string& name) { return mapRebuildNames().parse(name); }

std::string toString(MapRebuild when) { return mapRebuildNames().name(when); }

DetectionSchedule detectionScheduleFromString(const std::string& name) { return detectionScheduleNames().parse(name); }

std::string toString(DetectionSchedule schedule) { return detectionScheduleNames().name(schedule); }

io::IniKeys<TPipelineOptions> TPipelineOptions::iniKeys()
{
	using O = TPipelineOptions;
	io::IniKeys<O> keys;
	keys.choice(
			"pose_source", &O::poseSource, poseSourceFromString, [](PoseSource p) { return toString(p); },
			"vo (visual odometry) | gt (the rawlog's ground truth)", "must be vo or gt")
		.number<int>("detect_every_n", &O::detectEveryN, "",
			"run the detector on every N-th frame (on_change: at most this often); 0 = no detection",
			{[](int v) { return v >= 0; }, "must be >= 0 (0 = no detection)"})
		.choice(
			"detection_schedule", &O::detectionSchedule, detectionScheduleFromString,
			[](DetectionSchedule s) { return toString(s); },
			"fixed (every detect_every_n-th frame) | on_change (every detect_every_n-th frame where the view changed "
			"since the detector's last frame: detect_moved_share, detect_new_view_share; else every "
			"detect_max_interval-th)",
			"must be fixed or on_change")
		.number<int>("detect_max_interval", &O::detectMaxInterval, "frames",
			"on_change: the most frames between two detector runs; >= detect_every_n",
			{[](int v) { return v >= 1 && v <= 30; }, "must be 1..30 frames"})
		.check(
			"detect_max_interval", [](const O& o) { return o.detectMaxInterval >= o.detectEveryN; },
			"must be >= detect_every_n")
		.number("detect_moved_share", &O::detectMovedShare, "0..1",
			"on_change: the share of the image whose depth differs by more than detect_change_depth from the "
			"detector's last frame seen from the camera's predicted pose that runs the detector (someone walking in, "
			"or walking on)",
			{[](double v) { return v > 0 && v <= 1; }, "must be in (0, 1]"})
		.number("detect_new_view_share", &O::detectNewViewShare, "0..1",
			"on_change: the share of the image newly in view since the detector's last frame (outside that frame, "
			"or without depth there) that runs the detector (the camera turned)",
			{[](double v) { return v > 0 && v <= 1; }, "must be in (0, 1]"})
		.number("detect_change_depth", &O::detectChangeDepth, "m",
			"on_change: a pixel's depth changed when it differs by more than this from all four nearest of the "
			"detector's last frame",
			{[](double v) { return v > 0 && v <= 10; }, "must be in (0, 10] m"})
		.number("async_detection", &O::asyncDetection, "",
			"detector on a worker thread beside odometry and mapping; same run either way")
		.number<int>("detection_lag_frames", &O::detectionLagFrames, "frames",
			"a detection started at frame k is applied (odometry masks, persons, regions) at frame k + this, the loop "
			"waiting for it if late: the same rawlog always gives the same run",
			{[](int v) { return v >= 0 && v <= 30; }, "must be 0..30 frames"})
		.number("async_mapping", &O::asyncMapping, "",
			"a frame's map insertion on a worker thread while odometry processes the next; same map either way")
		.number("start_at_ground_truth", &O::startAtGroundTruth, "",
			"odometry starts at the first frame's ground truth, if any")
		.number<std::int64_t>("max_frames", &O::maxFrames, "", "frames to map; 0 = all",
			{[](std::int64_t v) { return v >= 0; }, "must be >= 0 (0 = all)"})
		.number<int>("read_ahead_frames", &O::readAheadFrames, "",
			"frames read and decoded ahead on a reader thread; 0 = read on the main loop's thread",
			{[](int v) { return v >= 0 && v <= 100; }, "must be 0..100 (0 = no reader thread)"})
		.number<int>("repeat", &O::repeat, "",
			"read the rawlog this many times as one sequence, indices and times continued (long runs)",
			{[](int v) { return v >= 1; }, "must be >= 1"})
		.number("picture_size", &O::pictureSize, "px", "width of map_top.png / map_perspective.png; 0 = none",
			{[](int v) { return v == 0 || (v >= 200 && v <= 8000); }, "must be 0 (none) or 200..8000 px"})
		.number("gui", &O::gui, "",
			"open the live 3D view (MRPT windows; avm-map --gui sets it); closing it ends the run as Ctrl-C does")
		.number("gui_fps", &O::guiFps, "Hz", "most redraws, and map snapshots, a second with gui = true, (0, 60]",
			{[](double v) { return v > 0 && v <= 60; }, "out of range (0, 60]"})
		.text("map_section", &O::mapSection, "section with the MRPT map definition",
			{[](const std::string& v) { return !v.empty(); }, "must name the map definition section"})
		.number("checkpoint_interval_s", &O::checkpointIntervalSeconds, "s",
			"run time between two checkpoints (OUTDIR/checkpoint.bin, what avm-map --resume OUTDIR continues from; "
			"also one before the first frame and one after the last); 0 = none",
			{[](double v) { return v >= 0 && v <= 86400; }, "must be 0 (no checkpoints) .. 86400 s"})
		.choice(
			"rebuild_map", &O::rebuildMap, mapRebuildFromString, [](MapRebuild w) { return toString(w); },
			"at the end of the run, clear the map and insert every mapped frame again from the rawlog at its final "
			"pose (persons and regions with it): never | after_loops (when the odometry closed a loop, so the map "
			"follows the corrected trajectory) | always (its cost; a replay check)",
			"must be never, after_loops or always")
		.number("reference_maps", &O::referenceMaps, "",
			"also build single-resolution OctoMaps (octomap's own insertion, both resolutions) from the same frames "
			"and poses and compare (stats.json \"reference\"): a measurement mode, slow");
	return keys;
}
}  // namespace avm::pipeline

template struct avm::io::CIniKeyOptions<avm::pipeline::TPipelineOptions>;
