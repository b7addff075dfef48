#include <mrpt/config/CConfigFileBase.h>

#include <cmath>

#include "avm/io/ErrorMessage.h"
#include "avm/io/IniOptions.h"
#include "avm/odometry/TOdometryOptions.h"

namespace avm::odometry
{
namespace
{
// One list of (key, member) drives load and save, so both see the same key set.
template <typename Options, typename Visitor>
void forEachKey(Options& o, Visitor&& v)
{
	v("num_features", o.num_features);
	v("pyramid_levels", o.pyramid_levels);
	v("pyramid_scale", o.pyramid_scale);
	v("fast_threshold", o.fast_threshold);
	v("grid_cols", o.grid_cols);
	v("grid_rows", o.grid_rows);
	v("min_depth", o.min_depth);
	v("max_depth", o.max_depth);
	v("depth_edge_ratio", o.depth_edge_ratio);
	v("match_ratio", o.match_ratio);
	v("max_hamming", o.max_hamming);
	v("search_radius", o.search_radius);
	v("ransac_reprojection", o.ransac_reprojection);
	v("ransac_iterations", o.ransac_iterations);
	v("min_inliers", o.min_inliers);
	v("huber_delta", o.huber_delta);
	v("depth_weight", o.depth_weight);
	v("refine_iterations", o.refine_iterations);
	v("window_size", o.window_size);
	v("ba_iterations", o.ba_iterations);
	v("ba_max_landmarks", o.ba_max_landmarks);
	v("keyframe_translation", o.keyframe_translation);
	v("keyframe_rotation", o.keyframe_rotation);
	v("keyframe_overlap", o.keyframe_overlap);
	v("map_max_keyframes", o.map_max_keyframes);
	v("relocalisation_candidates", o.relocalisation_candidates);
	v("relocalisation_min_inliers", o.relocalisation_min_inliers);
	v("relocalisation_frames", o.relocalisation_frames);
	v("mask_people", o.mask_people);
	v("person_box_margin", o.person_box_margin);
	v("person_depth_band", o.person_depth_band);
	v("threads", o.threads);
}
}  // namespace

void TOdometryOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
	// io's reader, not MRPT's read_int: "abc" or an empty value is an error
	// of its own, not a 0 that validate() would report as a wrong number.
	forEachKey(*this, [&](const char* key, auto& value) { value = io::readIniValue(cfg, section, key, value); });
	validate(section);
}

void TOdometryOptions::saveToConfigFile(mrpt::config::CConfigFileBase& cfg, const std::string& section) const
{
	forEachKey(*this, [&](const char* key, const auto& value) { cfg.write(section, key, value); });
}

void TOdometryOptions::validate(const std::string& section) const
{
	const auto require = [&](bool ok, const char* key, double value, const char* why) {
		if (!ok || !std::isfinite(value)) throw io::iniValueError(section, key, value, why);
	};
	require(num_features >= 50, "num_features", num_features, "must be at least 50");
	require(pyramid_levels >= 1 && pyramid_levels <= 12, "pyramid_levels", pyramid_levels, "must be 1..12");
	require(pyramid_scale > 1.0 && pyramid_scale <= 2.0, "pyramid_scale", pyramid_scale, "must be in (1, 2]");
	require(fast_threshold >= 1 && fast_threshold <= 100, "fast_threshold", fast_threshold, "must be 1..100");
	require(grid_cols >= 1 && grid_cols <= 64, "grid_cols", grid_cols, "must be 1..64");
	require(grid_rows >= 1 && grid_rows <= 64, "grid_rows", grid_rows, "must be 1..64");
	require(min_depth > 0, "min_depth", min_depth, "must be > 0 m");
	require(max_depth > min_depth, "max_depth", max_depth, "must be > min_depth");
	require(depth_edge_ratio > 0, "depth_edge_ratio", depth_edge_ratio, "must be > 0");
	require(match_ratio > 0 && match_ratio <= 1, "match_ratio", match_ratio, "must be in (0, 1]");
	require(max_hamming >= 1 && max_hamming <= 256, "max_hamming", max_hamming, "must be 1..256");
	require(search_radius > 0, "search_radius", search_radius, "must be > 0 px");
	require(ransac_reprojection > 0, "ransac_reprojection", ransac_reprojection, "must be > 0 px");
	require(ransac_iterations >= 1, "ransac_iterations", ransac_iterations, "must be >= 1");
	require(min_inliers >= 6, "min_inliers", min_inliers, "must be >= 6 (PnP needs at least 4, plus margin)");
	require(huber_delta > 0, "huber_delta", huber_delta, "must be > 0 px");
	require(depth_weight >= 0, "depth_weight", depth_weight, "must be >= 0");
	require(refine_iterations >= 0, "refine_iterations", refine_iterations, "must be >= 0");
	require(window_size == 0 || window_size >= 2, "window_size", window_size, "must be 0 (off) or >= 2");
	require(ba_iterations >= 1, "ba_iterations", ba_iterations, "must be >= 1");
	require(ba_max_landmarks >= 0, "ba_max_landmarks", ba_max_landmarks, "must be >= 0 (0 = all)");
	require(keyframe_translation > 0, "keyframe_translation", keyframe_translation, "must be > 0 m");
	require(keyframe_rotation > 0, "keyframe_rotation", keyframe_rotation, "must be > 0 deg");
	require(keyframe_overlap > 0 && keyframe_overlap <= 1, "keyframe_overlap", keyframe_overlap, "must be in (0, 1]");
	require(map_max_keyframes >= 10, "map_max_keyframes", map_max_keyframes, "must be >= 10");
	require(relocalisation_candidates >= 1, "relocalisation_candidates", relocalisation_candidates, "must be >= 1");
	require(relocalisation_min_inliers >= min_inliers, "relocalisation_min_inliers", relocalisation_min_inliers,
		"must be >= min_inliers");
	require(relocalisation_frames >= 0, "relocalisation_frames", relocalisation_frames, "must be >= 0");
	require(person_box_margin >= 0, "person_box_margin", person_box_margin, "must be >= 0 px");
	require(person_depth_band >= 0, "person_depth_band", person_depth_band, "must be >= 0 m");
	require(threads >= 1, "threads", threads, "must be >= 1");
}
}  // namespace avm::odometry
