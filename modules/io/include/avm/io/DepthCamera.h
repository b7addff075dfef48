// The pinhole model of a CObservation3DRangeScan's depth image, in MRPT's
// depth-sensor frame (X forward, Y left, Z up): pixel (u, v) with depth d is
// d * (1, (cx - u) / fx, (cy - v) / fy). Range images (range_is_depth false)
// hold the distance along the ray instead of X.
#pragma once

#include <mrpt/math/TPoint3D.h>
#include <mrpt/obs/CObservation3DRangeScan.h>

#include <cmath>
#include <optional>

namespace avm::io
{
struct DepthCamera
{
	double fx = 0, fy = 0, cx = 0, cy = 0;
	int width = 0, height = 0;
	bool rangeIsDepth = true;

	static DepthCamera of(const mrpt::obs::CObservation3DRangeScan& obs)
	{
		const auto& K = obs.cameraParams;
		return {K.fx(), K.fy(), K.cx(), K.cy(), static_cast<int>(obs.rangeImage.cols()),
			static_cast<int>(obs.rangeImage.rows()), obs.range_is_depth};
	}

	/** The sensor-frame point of pixel (u, v) whose image value is `metres`
	 *  (a depth, or a range for range images). */
	mrpt::math::TPoint3D unproject(double u, double v, double metres) const
	{
		mrpt::math::TPoint3D p(metres, (cx - u) * metres / fx, (cy - v) * metres / fy);
		if (!rangeIsDepth) p *= metres / p.norm();
		return p;
	}

	/** The pixel (u, v), anywhere on the image plane, of a sensor-frame point
	 *  in front of the camera (p.x > 0). */
	mrpt::math::TPoint2D pixelOf(const mrpt::math::TPoint3D& p) const
	{
		return {cx - fx * p.y / p.x, cy - fy * p.z / p.x};
	}

	/** The pixel (u, v) where a sensor-frame point projects, if it is in front
	 *  of the camera and inside the image. */
	std::optional<mrpt::math::TPoint2D> project(const mrpt::math::TPoint3D& p) const
	{
		if (!(p.x > 1e-6)) return std::nullopt;
		const auto px = pixelOf(p);
		if (!(px.x >= 0 && px.y >= 0 && px.x < width && px.y < height)) return std::nullopt;
		return px;
	}
};
}  // namespace avm::io
