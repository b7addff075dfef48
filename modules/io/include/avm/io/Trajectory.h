// Timestamped 6-DoF poses and the TUM trajectory format
// (`timestamp tx ty tz qx qy qz qw`, quaternion real part last).
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace avm::io
{
struct TimedPose
{
	double timestamp = 0;  //!< UNIX time [s]
	mrpt::poses::CPose3D pose;
};
using Trajectory = std::vector<TimedPose>;

/** The indices of `poses` in time order. Stable: poses of one instant (two
 *  sessions that saw the same frames) keep their order. A run's poses are in
 *  time order already; those of sessions mapped in another order than they
 *  were recorded are not. */
std::vector<std::size_t> timeOrder(const Trajectory& poses);
/** `poses` in time order (timeOrder). */
Trajectory inTimeOrder(const Trajectory& poses);

/** Reads a TUM trajectory. Comments (#) and blank lines are skipped. Throws
 *  std::runtime_error naming the file and line on a malformed line, a
 *  non-finite value, a quaternion far from unit norm, or a timestamp before
 *  the one above it (equal ones are two estimates of one instant). */
Trajectory readTumTrajectory(const std::filesystem::path& file);

/** Writes a TUM trajectory atomically, with a header comment line. */
void writeTumTrajectory(const std::filesystem::path& file, const Trajectory& poses, const std::string& header = {});

/** One TUM line (no newline) for the pose. */
std::string toTumLine(const TimedPose& p);

/** Pose at time t: linear in translation, slerp in rotation, between the two
 *  samples around t. Nothing when t is outside the trajectory or the two
 *  samples are more than maxGap seconds apart. */
std::optional<mrpt::poses::CPose3D> interpolatePose(const Trajectory& poses, double t, double maxGap = 0.5);

/** A rigid transform from a 4x4 matrix (row-major). The rotation block is
 *  orthonormalised (nearest rotation, by SVD): calibration matrices such as
 *  Bonn's carry a scale. Throws when the block is degenerate or reflects. */
mrpt::poses::CPose3D rigidTransformFromMatrix(const double (&m)[16]);

/** Reads a 4x4 row-major matrix (16 numbers, any white space) from a file. */
mrpt::poses::CPose3D readRigidTransformFile(const std::filesystem::path& file);
}  // namespace avm::io
