// The pixels of a depth image whose rays can reach a box in the world: what
// the map's row passes scan near a region and near a free-only box.
#pragma once

#include <mrpt/math/TBoundingBox.h>
#include <mrpt/poses/CPose3D.h>

#include "avm/io/DepthCamera.h"

namespace avm::io
{
/** Pixels [u0, u1] x [v0, v1], inclusive, inside the image; empty (u0 > u1
 *  or v0 > v1) when the box is off the image. */
struct PixelRect
{
	int u0, u1, v0, v1;
	bool empty() const { return u0 > u1 || v0 > v1; }
};

/** The box's eight corners projected, grown by a pixel; the whole image when
 *  a corner is behind the camera (or not finite). */
PixelRect pixelRectOf(
	const mrpt::math::TBoundingBox& box, const mrpt::poses::CPose3D& sensorPose, const DepthCamera& camera);
}  // namespace avm::io
