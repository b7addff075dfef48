// The pieces of avm-detect that are not argument parsing: reading the
// [detection] section of an ini, drawing detections, printing a benchmark.
#pragma once

#include <opencv2/core/mat.hpp>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "avm/detection/Detection.h"
#include "avm/detection/RawlogDetection.h"
#include "avm/detection/TDetectorOptions.h"

namespace avm::detection
{
/** Options from `section` of an ini file. Throws std::runtime_error naming a
 *  missing file, std::invalid_argument naming "[section] key" for a bad
 *  value. Keys of the section that TDetectorOptions does not know go to
 *  `unknownKeys` (likely typos). */
TDetectorOptions loadDetectorOptions(
	const std::filesystem::path& ini, const std::string& section, std::vector<std::string>& unknownKeys);

/** A copy of the image with each detection's box, class and score drawn. */
cv::Mat drawDetections(const cv::Mat& bgr, const std::vector<Detection>& detections);

/** Writes an image atomically; the format follows the extension. */
void writeImage(const std::filesystem::path& file, const cv::Mat& image);

/** A progress callback drawing a bar on stderr: redrawn on a terminal, only
 *  the final bar otherwise; nothing when disabled. */
std::function<void(double)> progressBar(bool enabled);

/** The summary avm-detect prints after a rawlog pass. */
std::string summaryText(const LabelRawlogSummary& summary);

/** A markdown table of benchmark rows. */
std::string benchmarkTable(const std::vector<DetectorBenchmark>& rows);
}  // namespace avm::detection
