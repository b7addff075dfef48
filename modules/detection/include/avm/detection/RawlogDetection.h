// Running a detector over a rawlog: a labelled copy of the rawlog plus a text
// list of the detections.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "avm/detection/Detection.h"

namespace avm::detection
{
struct LabelRawlogSummary
{
	std::size_t frames = 0;            //!< RGB-D observations in the input
	std::size_t detectedFrames = 0;    //!< frames the detector ran on (every N-th)
	std::size_t framesWithPerson = 0;  //!< detected frames with at least one person
	std::size_t persons = 0;           //!< person detections in all frames
	std::vector<std::string> skipped;  //!< frames copied unlabelled, with the reason
	std::filesystem::path rawlog, imagesDir, detectionsFile;
};

/** Reads `in` entry by entry and writes every entry to `out`; RGB-D frames
 *  0, every, 2*every, ... go through the detector and get "person"
 *  pixelLabels (writePersonLabels), the others are copied unlabelled.
 *  External images are not copied: `<out stem>_Images` becomes a symbolic link
 *  to the input's images folder, so the labelled rawlog shows the same files.
 *  Also writes `<out without extension>_detections.txt`, one line per
 *  detection: `frame timestamp class score x y w h depth` (depth [m] = robust
 *  person depth, nan without depth). Outputs appear only when complete.
 *  Throws std::runtime_error naming the file on a missing, corrupt or
 *  truncated input, an output equal to the input, or an `<out stem>_Images`
 *  that exists and is not the input's images folder. progress(fraction 0..1)
 *  after every frame. The input's external images are read from MRPT's
 *  process-wide images folder, which the program points at the input's
 *  (io::useImagesFolderOf). */
LabelRawlogSummary labelRawlog(DetectorBase& detector, const std::filesystem::path& in,
	const std::filesystem::path& out, std::size_t every = 1, const std::function<void(double)>& progress = {});

/** One detection as text: `class score x y w h` (box in pixels, 1 decimal). */
std::string formatDetection(const Detection& d);

}  // namespace avm::detection
