// Converts a TUM RGB-D layout folder into an MRPT rawlog of
// CObservation3DRangeScan (+ CObservationRobotPose ground truth).
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <utility>
#include <string>
#include <vector>

#include "avm/io/TumDataset.h"

namespace avm::io
{
struct TumConversionOptions
{
	RgbdCameraModel camera;           //!< intrinsics and depth scale
	double maxTimeDifference = 0.02;  //!< [s] RGB/depth association tolerance
	bool embedImages = false;         //!< colour inside the rawlog (raw pixels) instead of <out>_Images/
	/** gzip level of the rawlog, 1..9; 0 = a plain file. Plain with embedded
	 *  images is the fastest to replay (no inflate, no PNG decoding) at ~1.5 MB
	 *  a 640x480 frame. */
	int compressionLevel = 1;
	/** Pose of the camera optical frame in the ground-truth body frame;
	 *  identity when the ground truth is already the camera's. */
	mrpt::poses::CPose3D groundTruthBodyToCamera;
	bool useGroundTruth = true;  //!< read groundtruth.txt when present
	/** Leave out the frames before the ground truth's first pose and after
	 *  its last (listed in the summary's `skipped`), instead of failing on
	 *  them: real sequences often start before the motion capture does. A
	 *  frame inside the span that the ground truth does not cover (a gap)
	 *  still fails. Needs groundtruth.txt. */
	bool trimToGroundTruth = false;
	/** Only the frames first..last (0-based, of the trimmed sequence with
	 *  trimToGroundTruth, whose ground truth it reads even without
	 *  useGroundTruth): one session of a robot's runs cut from a sequence. */
	std::optional<std::pair<std::size_t, std::size_t>> frames;
};

struct TumConversionSummary
{
	std::size_t frames = 0;
	std::vector<std::string> skipped;  //!< pairs left out, with the reason (trimToGroundTruth's too)
	bool withGroundTruth = false;
	std::filesystem::path rawlog, imagesDir, groundTruthFile;
};

/** Writes `outRawlog` (and `<stem>_Images/`, `<stem>_groundtruth.txt`); an
 *  options.compressionLevel outside 0..9 throws std::invalid_argument. Every
 *  output appears only when complete; on error (std::runtime_error naming the
 *  file and line) none is left behind and earlier outputs are untouched.
 *  progress(done, total) is called after every frame. */
TumConversionSummary convertTumToRawlog(const std::filesystem::path& datasetDir, const std::filesystem::path& outRawlog,
	const TumConversionOptions& options, const std::function<void(std::size_t, std::size_t)>& progress = {});
}  // namespace avm::io
