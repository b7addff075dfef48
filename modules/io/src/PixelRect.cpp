#include "avm/io/PixelRect.h"

#include <algorithm>
#include <cmath>

namespace avm::io
{
PixelRect pixelRectOf(
	const mrpt::math::TBoundingBox& box, const mrpt::poses::CPose3D& sensorPose, const DepthCamera& camera)
{
	const PixelRect whole{0, camera.width - 1, 0, camera.height - 1};
	double u0 = camera.width, u1 = -1, v0 = camera.height, v1 = -1;
	for (int corner = 0; corner < 8; corner++)
	{
		const mrpt::math::TPoint3D w(
			corner & 1 ? box.max.x : box.min.x, corner & 2 ? box.max.y : box.min.y, corner & 4 ? box.max.z : box.min.z);
		const auto s = sensorPose.inverseComposePoint(w);
		if (!(s.x > 1e-3)) return whole;
		const auto p = camera.pixelOf(s);
		u0 = std::min(u0, p.x), u1 = std::max(u1, p.x), v0 = std::min(v0, p.y), v1 = std::max(v1, p.y);
	}
	// Clamped in doubles first: a corner just in front of the camera
	// projects far beyond what an int holds.
	const auto clamp = [](double x, int hi) { return static_cast<int>(std::clamp(x, -1.0, double(hi))); };
	return {std::max(clamp(std::floor(u0) - 1, camera.width), 0),
		std::min(clamp(std::ceil(u1) + 1, camera.width), camera.width - 1),
		std::max(clamp(std::floor(v0) - 1, camera.height), 0),
		std::min(clamp(std::ceil(v1) + 1, camera.height), camera.height - 1)};
}
}  // namespace avm::io
