// One RGB-D frame as it moves through avm: the MRPT observation (registered
// depth + colour, intrinsics, sensorPose) and, when the rawlog carries it, the
// ground-truth pose of the camera.
//
// Frames: the "robot" pose of every avm observation is the camera's OPTICAL
// frame in the world (z forward, x right, y down), the convention of TUM
// trajectories. The observation's `sensorPose` is opticalToSensorPose(), the
// rotation to MRPT's depth-sensor axes (X forward, Y left, Z up), so MRPT code
// that composes robot pose (+) sensorPose places points correctly.
#pragma once

#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <opencv2/core.hpp>

#include <cstddef>
#include <optional>

namespace avm::io
{
struct RgbdFrame
{
	/** Position among the RGB-D observations of the rawlog (0-based; frames
	 *  that could not be read keep their index, so indices match the source). */
	std::size_t index = 0;
	mrpt::obs::CObservation3DRangeScan::Ptr observation;
	/** Ground-truth pose of the camera optical frame in the world. */
	std::optional<mrpt::poses::CPose3D> groundTruth;

	/** UNIX time in seconds. */
	double timestamp() const;
};

/** The pose of MRPT's depth-sensor frame (X forward, Y left, Z up) in the
 *  camera optical frame (z forward, x right, y down). */
mrpt::poses::CPose3D opticalToSensorPose();

/** Depth in metres as CV_32F, 0 where there is no measurement. */
cv::Mat depthInMetres(const mrpt::obs::CObservation3DRangeScan& obs);

/** The colour image (BGR, CV_8UC3) registered with the depth, loading it from
 *  external storage if needed. Shares the observation's pixels. Throws if the
 *  observation has none. */
cv::Mat colourImage(const mrpt::obs::CObservation3DRangeScan& obs);

/** True when every element of the pose is finite. */
bool isFinite(const mrpt::poses::CPose3D& pose);
}  // namespace avm::io
