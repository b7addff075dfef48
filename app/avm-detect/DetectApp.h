// The parts of avm-detect that are not argument parsing: drawing detections,
// the progress bar, the summary it prints, and the detector benchmark.
#pragma once

#include <opencv2/core/mat.hpp>

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "avm/detection/Detection.h"
#include "avm/detection/RawlogDetection.h"
#include "avm/io/TimingSummary.h"

namespace avm::apps::detect
{
/** A copy of the image with each detection's box, class and score drawn. */
cv::Mat drawDetections(const cv::Mat& bgr, const std::vector<detection::Detection>& detections);

/** Writes an image atomically; the format follows the extension. */
void writeImage(const std::filesystem::path& file, const cv::Mat& image);

/** The summary avm-detect prints after a rawlog pass. */
std::string summaryText(const detection::LabelRawlogSummary& summary);

/** The colour images of the first `maxFrames` RGB-D frames of a rawlog (0 = all). */
std::vector<cv::Mat> loadColourImages(const std::filesystem::path& rawlog, std::size_t maxFrames = 0);

struct DetectorBenchmark
{
	int threads = 0;  //!< OpenCV threads the program had set
	std::size_t framesWithPerson = 0, persons = 0;
	io::TimingSummary times;  //!< of detect(), one sample a frame
};

/** Times detector.detect() on each image, after one warm-up call, with the
 *  OpenCV threads the caller set (`threads` is only recorded). */
DetectorBenchmark benchmarkDetector(detection::DetectorBase& detector, const std::vector<cv::Mat>& images, int threads);

/** A markdown table of benchmark rows. */
std::string benchmarkTable(const std::vector<DetectorBenchmark>& rows);
}  // namespace avm::apps::detect
