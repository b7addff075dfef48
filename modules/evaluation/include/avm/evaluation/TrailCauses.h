// Where a map's trail comes from: for each trail voxel (occupied in
// the map, free in one yardstick's reference), which pixels ended in it, frame
// by frame, and for a person pixel (one the yardstick cuts) whether the map's own
// person regions held its point then (its detections.txt: the region box of
// each detection, applied detection_lag_frames later, followed for the
// region's horizon; not carried by the person's velocity, so an
// approximation of the run's free-only boxes). A diagnostic: a voxel with a
// person pixel outside the regions is put by the first such frame.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "avm/evaluation/TrailShare.h"

namespace avm::evaluation
{
enum class TrailCause
{
	NoEndpoint,         //!< no pixel ended in it (detail folded into the low tree)
	BeforeFirstRegion,  //!< a person pixel outside the run's regions then, before the person's first region
	BetweenRegions,     //!< ... before a later region of the person covered the voxel (lag, missed detections)
	NeverInRegion,      //!< ... and no region box of the run ever covered the voxel
	PastRegion,         //!< person pixels whose rays passed through a region box (boxes: the background in them)
	InsideRegion,       //!< person pixels, each inside a region box then (not carried there, or still)
	OtherPixelsOnly,    //!< only pixels the yardstick does not cut: the map kept what octomap cleared
	Count
};

std::string describe(TrailCause cause);

struct TrailCauseCount
{
	std::size_t voxels = 0;
	double m3 = 0;
	double withOtherPixelsM3 = 0;  //!< of m3: pixels the yardstick does not cut ended there too
};

struct TrailCauses
{
	std::string map;
	Yardstick yardstick = Yardstick::PersonMask;  //!< whose reference the trail is of
	std::vector<TrailCauseCount> counts = std::vector<TrailCauseCount>(static_cast<std::size_t>(TrailCause::Count));
	/** Frames from a BeforeFirstRegion voxel's first person pixel to the
	 *  region that came after it, one entry per voxel. */
	std::vector<std::size_t> framesBeforeRegion;
};

/** The trail of the avm-map output `avmDir` (-p gt, the frames of `options`)
 *  against the references of `yardstick`, by cause. `lagFrames`: the run's
 *  detection_lag_frames; `horizon` [s]: how long a region box follows its
 *  person unseen (region_end_after_s). Throws std::runtime_error naming the
 *  file on missing or unreadable outputs. */
TrailCauses explainTrails(const TrailOptions& options, const std::filesystem::path& avmDir, const TrailReference& high,
	const TrailReference& low, std::size_t lagFrames, double horizon, Yardstick yardstick);

std::string toMarkdown(const TrailCauses& causes);
}  // namespace avm::evaluation
