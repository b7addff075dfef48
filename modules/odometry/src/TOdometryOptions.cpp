#include <mrpt/config/CConfigFileBase.h>

#include "avm/io/IniKeys.h"
#include "avm/odometry/TOdometryOptions.h"

namespace avm::odometry
{
namespace
{
/** Features, matching and PnP. */
void addFrontEndKeys(io::IniKeys<TOdometryOptions>& keys)
{
	using O = TOdometryOptions;
	keys.number("num_features", &O::num_features, "", "features kept per frame after bucketing",
			{[](int v) { return v >= 50; }, "must be at least 50"})
		.number("pyramid_levels", &O::pyramid_levels, "", "ORB pyramid levels",
			{[](int v) { return v >= 1 && v <= 12; }, "must be 1..12"})
		.number("pyramid_scale", &O::pyramid_scale, "", "ORB scale factor between levels, (1, 2]",
			{[](double v) { return v > 1.0 && v <= 2.0; }, "must be in (1, 2]"})
		.number("fast_threshold", &O::fast_threshold, "grey levels", "ORB FAST threshold",
			{[](int v) { return v >= 1 && v <= 100; }, "must be 1..100"})
		.number("grid_cols", &O::grid_cols, "", "bucketing grid columns",
			{[](int v) { return v >= 1 && v <= 64; }, "must be 1..64"})
		.number("grid_rows", &O::grid_rows, "", "bucketing grid rows",
			{[](int v) { return v >= 1 && v <= 64; }, "must be 1..64"})
		.number(
			"min_depth", &O::min_depth, "m", "nearer depth rejected", {[](double v) { return v > 0; }, "must be > 0 m"})
		.number("max_depth", &O::max_depth, "m", "farther depth rejected")
		.check(
			"max_depth", [](const O& o) { return o.max_depth > o.min_depth; }, "must be > min_depth")
		.number("depth_edge_ratio", &O::depth_edge_ratio, "",
			"feature dropped when its 3x3 depth range exceeds this fraction of its depth",
			{[](double v) { return v > 0; }, "must be > 0"})
		.number("match_ratio", &O::match_ratio, "", "Lowe ratio best/second-best Hamming distance, (0, 1]",
			{[](double v) { return v > 0 && v <= 1; }, "must be in (0, 1]"})
		.number("max_hamming", &O::max_hamming, "bits", "largest accepted descriptor distance",
			{[](int v) { return v >= 1 && v <= 256; }, "must be 1..256"})
		.number("search_radius", &O::search_radius, "px", "search window around a landmark's predicted projection",
			{[](double v) { return v > 0; }, "must be > 0 px"})
		.number("ransac_reprojection", &O::ransac_reprojection, "px",
			"PnP RANSAC inlier threshold, also the final inlier test",
			{[](double v) { return v > 0; }, "must be > 0 px"})
		.number("ransac_iterations", &O::ransac_iterations, "", "PnP RANSAC iterations",
			{[](int v) { return v >= 1; }, "must be >= 1"})
		.number("min_inliers", &O::min_inliers, "", "fewer inliers = tracking lost",
			{[](int v) { return v >= 6; }, "must be >= 6 (PnP needs at least 4, plus margin)"});
}

/** The Ceres refinement, the window bundle adjustment and keyframes. */
void addBackEndKeys(io::IniKeys<TOdometryOptions>& keys)
{
	using O = TOdometryOptions;
	keys.number("huber_delta", &O::huber_delta, "px", "Huber loss width",
			{[](double v) { return v > 0; }, "must be > 0 px"})
		.number("depth_weight", &O::depth_weight, "",
			"weight of the depth residual fx*(z-d)/d [px] (depth noise is ~20x pixel noise); 0 = reprojection only",
			{[](double v) { return v >= 0; }, "must be >= 0"})
		.number("refine_iterations", &O::refine_iterations, "", "Ceres iterations of the per-frame refinement, 0 = off",
			{[](int v) { return v >= 0; }, "must be >= 0"})
		.number("refine_rounds", &O::refine_rounds, "",
			"refinements of a frame's pose: the first from PnP RANSAC's inliers, each further one from the matches "
			"within ransac_reprojection at the last refined pose",
			{[](int v) { return v >= 1; }, "must be >= 1"})
		.number("motion_prior_sigma", &O::motion_prior_sigma, "m",
			"standard deviation of a tracked frame's camera centre about where the constant-velocity model puts it, "
			"in the per-frame refinement; 0 = no prior. Needs keyframe_tracked_pose = true (else the prediction jumps "
			"at "
			"every keyframe)",
			{[](double v) { return v >= 0; }, "must be >= 0 m"})
		.number("motion_gate", &O::motion_gate, "",
			"a tracked frame whose camera centre is farther from the constant-velocity prediction than this many times "
			"the median distance of the last frames is bridged by the motion model as a lost frame is; 0 = off",
			{[](double v) { return v == 0 || v >= 2; }, "must be 0 (off) or at least 2"})
		.number("window_size", &O::window_size, "", "keyframes in the bundle adjustment, 0 = no BA",
			{[](int v) { return v == 0 || v >= 2; }, "must be 0 (off) or >= 2"})
		.number("ba_iterations", &O::ba_iterations, "", "Ceres iterations of one bundle adjustment",
			{[](int v) { return v >= 1; }, "must be >= 1"})
		.number("ba_max_landmarks", &O::ba_max_landmarks, "",
			"landmarks in one bundle adjustment, the most-viewed first, and as many of a joined place's anchored "
			"points; "
			"0 = all",
			{[](int v) { return v >= 0; }, "must be >= 0 (0 = all)"})
		.number("keyframe_translation", &O::keyframe_translation, "m",
			"motion from the last keyframe that makes a keyframe", {[](double v) { return v > 0; }, "must be > 0 m"})
		.number("keyframe_rotation", &O::keyframe_rotation, "deg",
			"rotation from the last keyframe that makes a keyframe",
			{[](double v) { return v > 0; }, "must be > 0 deg"})
		.number("keyframe_overlap", &O::keyframe_overlap, "",
			"keyframe when inliers fall below this share of the most the keyframe gave",
			{[](double v) { return v > 0 && v <= 1; }, "must be in (0, 1]"})
		.number("keyframe_tracked_pose", &O::keyframe_tracked_pose, "",
			"the frame that makes a keyframe keeps its tracked pose (true), or takes the pose the window bundle "
			"adjustment gives the keyframe (false)")
		.check(
			"motion_prior_sigma", [](const O& o) { return o.motion_prior_sigma == 0 || o.keyframe_tracked_pose; },
			"must be 0 unless keyframe_tracked_pose = true (the prediction would jump at every keyframe)");
}

/** The keyframe map, relocalisation and loop closing. */
void addPlaceKeys(io::IniKeys<TOdometryOptions>& keys)
{
	using O = TOdometryOptions;
	keys.number("map_max_keyframes", &O::map_max_keyframes, "",
			"keyframes kept for the whole run, about 70 kB each (descriptors, points, words); when full, the older of "
			"the two closest keyframes goes, >= 10",
			{[](int v) { return v >= 10; }, "must be >= 10"})
		.number("relocalisation_candidates", &O::relocalisation_candidates, "",
			"map keyframes a lost frame is checked against (descriptor matching, PnP RANSAC, Ceres refinement), most "
			"similar words first",
			{[](int v) { return v >= 1; }, "must be >= 1"})
		.number("relocalisation_min_inliers", &O::relocalisation_min_inliers, "",
			"inliers after the refinement that accept a relocalisation, >= min_inliers")
		.check(
			"relocalisation_min_inliers", [](const O& o) { return o.relocalisation_min_inliers >= o.min_inliers; },
			"must be >= min_inliers")
		.number("relocalisation_frames", &O::relocalisation_frames, "",
			"lost frames with enough features during which the old map is kept for relocalisation; then a new local "
			"map starts at the bridged pose",
			{[](int v) { return v >= 0; }, "must be >= 0"})
		.number("loop_closure", &O::loop_closure, "",
			"close loops: a new keyframe that sees an old keyframe's place again is measured against it, judged by "
			"the loop check (loop_sigma, odometry_sigma) and the keyframes move in a pose graph "
			"(Ceres)")
		.number("loop_min_separation", &O::loop_min_separation, "keyframes",
			"a loop candidate is at least this many keyframes older than the new keyframe",
			{[](int v) { return v >= 1; }, "must be >= 1"})
		.number("loop_candidates", &O::loop_candidates, "",
			"map keyframes a new keyframe is checked against for a loop, most similar words first; one within "
			"loop_neighbours of a candidate already measured is skipped",
			{[](int v) { return v >= 1; }, "must be >= 1"})
		.number("loop_neighbours", &O::loop_neighbours, "keyframes",
			"keyframes on each side of a loop candidate whose points, with the candidate's, the loop is measured "
			"against",
			{[](int v) { return v >= 0; }, "must be >= 0"})
		.number("loop_min_inliers", &O::loop_min_inliers, "", "inliers after the refinement that accept a loop")
		.check(
			"loop_min_inliers", [](const O& o) { return o.loop_min_inliers >= o.min_inliers; },
			"must be >= min_inliers")
		.number("loop_sigma", &O::loop_sigma, "m",
			"standard deviation of a loop's measured camera centre on each axis: the loop check's scale and the loop "
			"constraint's in the pose graph (the same number in rad for its rotation)",
			{[](double v) { return v > 0; }, "must be > 0"})
		.number("odometry_sigma", &O::odometry_sigma, "m",
			"standard deviation of the odometry between consecutive keyframes on each axis: how far the track may "
			"have drifted since a loop's candidate in the loop check, and the odometry constraint in the pose graph "
			"(the same number in rad for its rotation)",
			{[](double v) { return v > 0; }, "must be > 0"});
}

/** People walking through the view, and threads. */
void addPeopleAndRuntimeKeys(io::IniKeys<TOdometryOptions>& keys)
{
	using O = TOdometryOptions;
	keys.number("mask_people", &O::mask_people, "", "leave out features on detected people")
		.number("person_box_margin", &O::person_box_margin, "px", "added on every side of a person box",
			{[](int v) { return v >= 0; }, "must be >= 0 px"})
		.number("person_depth_band", &O::person_depth_band, "m",
			"in a box, pixels nearer than the person's median depth + this are masked; 0 = whole box",
			{[](double v) { return v >= 0; }, "must be >= 0 m"})
		.number("threads", &O::threads, "", "Ceres threads; OpenCV threads are set by the program",
			{[](int v) { return v >= 1; }, "must be >= 1"});
}

}  // namespace

io::IniKeys<TOdometryOptions> TOdometryOptions::iniKeys()
{
	io::IniKeys<TOdometryOptions> keys;
	addFrontEndKeys(keys);
	addBackEndKeys(keys);
	addPlaceKeys(keys);
	addPeopleAndRuntimeKeys(keys);
	return keys;
}
}  // namespace avm::odometry

template struct avm::io::CIniKeyOptions<avm::odometry::TOdometryOptions>;
