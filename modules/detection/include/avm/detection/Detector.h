// The detector factory: an ONNX YOLO model through cv::dnn, or OpenCV's HOG
// people detector when no model file is set.
#pragma once

#include <filesystem>
#include <memory>

#include "avm/detection/Detection.h"
#include "avm/detection/TDetectorOptions.h"

namespace avm::detection
{
/** A detector for the options. A relative `model` is resolved against
 *  `root` (the project root; empty = the working folder). Throws
 *  std::runtime_error naming the model file when it is missing (and saying to
 *  run scripts/get-data.sh), cannot be loaded as ONNX, or has an output
 *  layout that is unknown or not the one `layout` names; std::invalid_argument
 *  for invalid options (and for the HOG detector, classes without "person"). */
std::unique_ptr<DetectorBase> createDetector(const TDetectorOptions& options, const std::filesystem::path& root = {});
}  // namespace avm::detection
