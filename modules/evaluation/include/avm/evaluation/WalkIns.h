// How soon a run's detector finds a person who walks into view, against a
// reference run of the same rawlog whose detector looked at every frame
// ([pipeline] detect_every_n = 1): what a schedule that skips frames
// ([pipeline] detection_schedule) costs in frames.
//
// A walk-in is the first box of a person of the reference (its person ids)
// that no reference box of the frames just before overlaps: someone new in
// view, not a person the tracker lost and found again. The run finds it at
// the first frame from then on where its detector gave a box overlapping the
// person's reference box of that frame. Both runs read the same images and
// the detector gives the same boxes for the same image, so a run that looked
// at that frame has the reference's box.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <vector>

namespace avm::evaluation
{
struct WalkIn
{
	std::size_t frame = 0;  //!< the frame the reference first found the person at
	unsigned person = 0;    //!< the reference's person id
	/** Frames of the second from `frame` on (30 at 30 Hz) the reference had
	 *  their box on: a person seen on a few only is found by luck. */
	std::size_t framesSeen = 0;
	std::optional<std::size_t> foundAt;  //!< the run's first frame with the person's box; none: never
};

/** The reference's walk-ins, each with the frame the run found it at, in
 *  frame order. `run` and `reference` are avm-map output folders
 *  (detections.txt). Throws std::runtime_error naming a detections.txt that
 *  is missing or has a line it cannot read. */
std::vector<WalkIn> walkInsFound(const std::filesystem::path& run, const std::filesystem::path& reference);
}  // namespace avm::evaluation
