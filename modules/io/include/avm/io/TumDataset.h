// The TUM RGB-D folder layout (rgb.txt, depth.txt, associations.txt,
// groundtruth.txt) and the cameras that record it.
#pragma once

#include <mrpt/img/TCamera.h>
#include <mrpt/poses/CPose3D.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace avm::io
{
/** One line of rgb.txt / depth.txt: `timestamp filename`. */
struct TumListEntry
{
	double timestamp = 0;
	std::string file;  //!< relative to the dataset folder
};

/** Reads rgb.txt or depth.txt. Throws naming file and line on a malformed line
 *  or timestamps that do not increase. */
std::vector<TumListEntry> readTumFileList(const std::filesystem::path& file);

struct RgbdPair
{
	TumListEntry rgb, depth;
};

struct Association
{
	std::vector<RgbdPair> pairs;
	std::vector<std::string> skipped;  //!< one reason per colour frame left out
};

/** Reads associations.txt (`t_rgb rgb t_depth depth`). Throws naming file and
 *  line on a malformed line or pairs out of time order. */
std::vector<RgbdPair> readAssociations(const std::filesystem::path& file);

/** Pairs each colour frame with the depth frame nearest in time, if within
 *  maxDifference seconds; each depth frame is used at most once. */
Association associateNearest(
	const std::vector<TumListEntry>& rgb, const std::vector<TumListEntry>& depth, double maxDifference);

/** A registered RGB-D camera: pinhole intrinsics shared by colour and depth,
 *  and the depth PNG scale. */
struct RgbdCameraModel
{
	mrpt::img::TCamera intrinsics;
	double depthFactor = 5000;  //!< depth PNG value per metre
};

/** Names accepted by cameraPreset(). */
std::vector<std::string> cameraPresetNames();
/** "bonn", "tum-fr1", "tum-fr2", "tum-fr3" (published calibrations, 640x480,
 *  depth factor 5000). Throws listing the names for anything else. */
RgbdCameraModel cameraPreset(const std::string& name);

/** The fixed pose of the camera optical frame in the ground-truth body frame
 *  for a dataset: "bonn" (T_ros * T_m of the Bonn RGB-D Dynamic dataset,
 *  orthonormalised), "none" (identity); anything else is read as a file with a
 *  4x4 matrix. */
mrpt::poses::CPose3D groundTruthBodyToCamera(const std::string& presetOrFile);
}  // namespace avm::io
