// Settings of the RGB-D visual odometry (front end: features, matching, PnP;
// back end: Ceres refinement and sliding-window bundle adjustment).
#pragma once

#include <string>

#include "avm/io/IniKeyOptions.h"

namespace avm::odometry
{
struct TOdometryOptions : public io::CIniKeyOptions<TOdometryOptions>
{
	// --- front end: features
	int num_features = 1000;     //!< ORB features kept per frame (after bucketing)
	int pyramid_levels = 4;      //!< ORB pyramid levels
	double pyramid_scale = 1.2;  //!< ORB scale factor between levels
	int fast_threshold = 12;     //!< ORB FAST threshold (grey levels)
	int grid_cols = 8;           //!< bucketing grid columns
	int grid_rows = 6;           //!< bucketing grid rows
	double min_depth = 0.3;      //!< [m] nearer depth is rejected
	double max_depth = 6.0;      //!< [m] farther depth is rejected
	/** A feature is on a depth edge (rejected) when its 3x3 depth range exceeds this fraction of its depth. */
	double depth_edge_ratio = 0.05;
	// --- front end: matching and PnP
	double match_ratio = 0.8;          //!< Lowe ratio: best / second-best Hamming distance
	int max_hamming = 64;              //!< largest accepted descriptor distance (bits)
	double search_radius = 20.0;       //!< [px] window around a landmark's predicted projection
	double ransac_reprojection = 3.0;  //!< [px] PnP RANSAC inlier threshold
	int ransac_iterations = 100;       //!< PnP RANSAC iterations
	int min_inliers = 20;              //!< fewer inliers than this = tracking lost
	// --- back end
	double huber_delta = 1.0;  //!< [px] Huber loss width of the reprojection residual
	/** Weight of the depth residual fx*(z-d)/d [px] beside the reprojection error (0 = off). */
	double depth_weight = 0.05;
	int refine_iterations = 10;  //!< Ceres iterations of the per-frame pose refinement
	/** Refinements of a frame's pose against fixed points. The first starts
	 *  from PnP RANSAC's inliers, chosen at PnP's pose; each further one from
	 *  the matches that reproject within ransac_reprojection at the last
	 *  refined pose, a better one. With one round, a frame's pose swings by
	 *  millimetres with the inliers RANSAC happened to pick; four rounds need
	 *  ba_max_landmarks 500 to pay off. */
	int refine_rounds = 4;
	/** [m] Standard deviation of a tracked frame's camera centre about where
	 *  the constant-velocity model puts it, in the per-frame refinement (0 =
	 *  off): PnP alone gets the motion from one frame to the next wrong by
	 *  about a centimetre (a small turn and a sideways shift look alike),
	 *  where the true camera moves smoothly. Needs keyframe_tracked_pose. */
	double motion_prior_sigma = 0.005;
	/** A tracked frame whose camera centre lies farther from the
	 *  constant-velocity prediction than this many times the median of the
	 *  recent frames' distances is not trusted: its pose is bridged by the
	 *  motion model, as a lost frame's, and placed once the track agrees
	 *  again (0 = off). A person filling the view leaves a few features that
	 *  can agree on a wrong pose; a camera does not jump by ten times its
	 *  usual deviation from one frame to the next. */
	double motion_gate = 8.0;
	int window_size = 12;   //!< keyframes in the sliding-window bundle adjustment (0 = no BA)
	int ba_iterations = 8;  //!< Ceres iterations of one bundle adjustment
	/** Landmarks in one bundle adjustment, the most-viewed first, and as many
	 *  anchored points (0 = all). */
	int ba_max_landmarks = 500;
	// --- keyframes
	double keyframe_translation = 0.08;  //!< [m] motion from the last keyframe that makes a keyframe
	double keyframe_rotation = 8.0;      //!< [deg] rotation from the last keyframe that makes a keyframe
	/** A keyframe is made when the tracked share of the last keyframe's landmarks falls below this. */
	double keyframe_overlap = 0.6;
	/** The frame that makes a keyframe keeps its tracked pose; else it takes
	 *  the one the window bundle adjustment gives the keyframe, which the
	 *  next frames' landmarks (placed from the tracked pose) disagree with. */
	bool keyframe_tracked_pose = true;
	// --- keyframe map (kept through tracking loss) and relocalisation
	/** Keyframes kept for the whole run (about 70 kB each); beyond, the most redundant goes. */
	int map_max_keyframes = 300;
	/** Map keyframes a lost frame is checked against (PnP + refinement), most similar first. */
	int relocalisation_candidates = 3;
	int relocalisation_min_inliers = 50;  //!< inliers after the refinement that accept a relocalisation
	/** Lost frames with features during which the old map is kept for relocalisation; then a new local map
	 *  starts at the bridged pose. */
	int relocalisation_frames = 10;
	// --- loop closing
	/** Verified revisits of old keyframes correct the drift (loop check, pose
	 *  graph). The check closes a loop only on drift beyond what two agreeing
	 *  loops can err together, so where the odometry has not drifted that far
	 *  the run is the one without loop closing (doc/decisions.md, "Loop
	 *  closing is on in ini/default.ini"). */
	bool loop_closure = true;
	/** A loop candidate is at least this many keyframes older than the new one. */
	int loop_min_separation = 15;
	int loop_candidates = 3;    //!< map keyframes a new keyframe is checked against, most similar words first
	int loop_neighbours = 2;    //!< keyframes on each side of a candidate whose points the loop is measured against
	int loop_min_inliers = 80;  //!< inliers after the refinement that accept a loop
	/** [m] Standard deviation of a loop's measured camera centre on each axis
	 *  (and [rad] of its rotation): the loop check's scale (a loop moves the
	 *  keyframes only when the drift it shows is beyond it) and the loop
	 *  constraint's in the pose graph. Measured on Bonn: a loop's error
	 *  against the ground truth is 2.7-3.5 cm on average, a per-axis sigma of
	 *  1.7-2.2 cm (doc/decisions.md, "One loop sigma for all loops"). */
	double loop_sigma = 0.02;
	/** [m] Standard deviation of the odometry between consecutive keyframes
	 *  on each axis (and [rad]): how far the track may have drifted since a
	 *  loop's candidate (a loop beyond that and its own error is refused), and
	 *  the odometry constraint in the pose graph. */
	double odometry_sigma = 0.01;
	// --- dynamic people
	bool mask_people = true;  //!< ignore features inside person boxes
	/** [px] Added on every side of a person box: avm-map hands the odometry
	 *  boxes 3-6 frames old (detection every 3rd frame, applied
	 *  detection_lag_frames later), and a walking person moves meanwhile. */
	int person_box_margin = 30;
	/** [m] Inside a box, pixels nearer than the person's median depth plus this are masked (0 = the
	 *  whole box). */
	double person_depth_band = 0.5;
	// --- runtime
	int threads = 1;  //!< Ceres threads (OpenCV threads are the caller's: cv::setNumThreads)

	/** Every key: name, member, unit, description, check. */
	static io::IniKeys<TOdometryOptions> iniKeys();
};
}  // namespace avm::odometry
