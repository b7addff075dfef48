// The pinhole model of a CObservation3DRangeScan's depth image, in MRPT's
// depth-sensor frame (X forward, Y left, Z up): pixel (u, v) with depth d is
// d * (1, (cx - u) / fx, (cy - v) / fy). Range images (range_is_depth false)
// hold the distance along the ray instead of X. The same camera in its optical
// frame (OpenCV's: x right, y down, z forward), as visual odometry uses it:
// pixel (u, v) with depth d is d * ((u - cx) / fx, (v - cy) / fy, 1).
#pragma once

#include <mrpt/math/TPoint3D.h>
#include <Eigen/Core>
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

	/** The optical-frame point of pixel (u, v) at depth `depth`. */
	Eigen::Vector3d opticalPointOf(double u, double v, double depth) const
	{
		return {(u - cx) * depth / fx, (v - cy) * depth / fy, depth};
	}

	/** The pixel of optical-frame point `p` (p[2] > 0), for a double or a
	 *  Ceres Jet (a cost functor projects with the same arithmetic). */
	template <class T>
	void opticalPixelOf(const T* p, T* pixel) const
	{
		pixel[0] = T(fx) * p[0] / p[2] + T(cx);
		pixel[1] = T(fy) * p[1] / p[2] + T(cy);
	}
	Eigen::Vector2d opticalPixelOf(const Eigen::Vector3d& p) const
	{
		Eigen::Vector2d pixel;
		opticalPixelOf(p.data(), pixel.data());
		return pixel;
	}
};
}  // namespace avm::io
