// The surface sketch forgetting what a depth image saw through: a high voxel
// whose pixel sees a surface beyond it.
#include "RayIntegrator.h"

#include "avm/io/DepthCamera.h"
#include "avm/io/PoseTransform.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace avm::detail
{
namespace
{
/** std::lround of a pixel coordinate (>= 0, inside the image), without its
 *  call into libm: the fraction above the truncation is exact. */
int roundNonNegative(double x)
{
	const int whole = static_cast<int>(x);
	return whole + (x - whole >= 0.5 ? 1 : 0);
}
}  // namespace

void RayIntegrator::forgetSketchSeenThrough(const mrpt::obs::CObservation3DRangeScan& obs,
	const mrpt::poses::CPose3D& sensorPose, const io::DepthCamera& camera)
{
	// A single high-resolution map frees the voxels its rays cross, so a person who walked
	// through leaves nothing there once the wall behind is seen again. The low
	// tree's rays are too coarse to say which high voxels they crossed; the
	// depth image says it for the few the sketch holds: a voxel whose pixel
	// sees a surface more than a voxel beyond it has been seen through. The
	// endpoints of this image are marked after (finish()), so a surface seen
	// again stays.
	const double highEdge = m_sketchGrid.resolution;
	const double lowHalfDiagonal = 0.5 * std::sqrt(3.0) * highEdge * m_targets.sketch->ratio();
	const double maxRange = m_targets.outsideMaxRange;
	const auto& img = obs.rangeImage;
	const auto units = obs.rangeUnits;
	// The image's four side planes, through the sensor, normals inwards: a low
	// voxel wholly outside one of them has no high voxel that projects into
	// the image, and most of the sketch lies there.
	const double W = camera.width, H = camera.height;
	std::array<mrpt::math::TPoint3D, 4> sides{mrpt::math::TPoint3D(camera.cx, -camera.fx, 0),
		mrpt::math::TPoint3D(W - camera.cx, camera.fx, 0), mrpt::math::TPoint3D(camera.cy, 0, -camera.fy),
		mrpt::math::TPoint3D(H - camera.cy, 0, camera.fy)};
	for (auto& n : sides) n *= 1.0 / n.norm();
	const double outsideBy = lowHalfDiagonal + 1e-6;
	const auto outsideTheImage = [&](const mrpt::math::TPoint3D& c)
	{
		return std::any_of(
			sides.begin(), sides.end(), [&](const auto& n) { return n.x * c.x + n.y * c.y + n.z * c.z < -outsideBy; });
	};
	// A high voxel's centre is its low voxel's plus a fixed offset per bit:
	// the offsets turned into the sensor frame once per image.
	const unsigned ratio = m_targets.sketch->ratio();
	const io::PoseTransform sensor(sensorPose);
	std::vector<mrpt::math::TPoint3D> offsets(ratio * ratio * ratio);
	for (unsigned bit = 0; bit < offsets.size(); ++bit)
	{
		const auto o = m_targets.sketch->offsetOfBit(bit);
		mrpt::math::TPoint3D w;
		for (int i = 0; i < 3; ++i) w[i] = (o[i] + 0.5) * highEdge - 0.5 * highEdge * ratio;
		offsets[bit] = sensor.inverseRotate(w);
	}
	// Only a low voxel whose centre is within reach of the sensor can lose
	// bits (the test below): the range holds every such voxel, a low voxel
	// more on each side for the rounding of its bounds.
	const double lowEdge = highEdge * ratio;
	const auto inReach = KeyRange::around(mrpt::math::TPoint3D(sensorPose.x(), sensorPose.y(), sensorPose.z()),
		maxRange + lowHalfDiagonal + lowEdge, 1.0 / lowEdge);
	m_targets.sketch->updateBitsWithin(inReach,
		[&](std::uint64_t lowKey, std::uint64_t bits)
		{
			if (bits == 0) return bits;
			const auto lowCentre = sensor.inverseCompose(centreOf(lowKey, lowEdge));
			if (lowCentre.x <= -lowHalfDiagonal || lowCentre.norm() > maxRange + lowHalfDiagonal) return bits;
			if (outsideTheImage(lowCentre)) return bits;
			// Where each bit's pixel is first, then the pixels: the sketch's
			// voxels scatter over the image, so most reads miss the cache,
			// and read together they wait for memory once, not once a bit.
			struct Probe
			{
				const std::uint16_t* pixel;
				double along;
				unsigned bit;
			};
			std::array<Probe, 64> probes;
			std::size_t n = 0;
			for (std::uint64_t rest = bits; rest != 0; rest &= rest - 1)
			{
				const auto bit = static_cast<unsigned>(__builtin_ctzll(rest));
				const auto p = lowCentre + offsets[bit];
				const double distance = p.norm();
				if (distance > maxRange) continue;
				const auto pixel = camera.project(p);
				if (!pixel) continue;
				const int u = roundNonNegative(pixel->x), v = roundNonNegative(pixel->y);
				if (u >= camera.width || v >= camera.height) continue;
				const std::uint16_t* raw = &img(v, u);
				__builtin_prefetch(raw);
				probes[n++] = {raw, camera.rangeIsDepth ? p.x : distance, bit};
			}
			for (std::size_t i = 0; i < n; ++i)
			{
				const std::uint16_t raw = *probes[i].pixel;
				if (raw == 0) continue;
				const double measured = raw * units;
				if (measured > probes[i].along + highEdge) bits &= ~(std::uint64_t(1) << probes[i].bit);
			}
			return bits;
		});
}

}  // namespace avm::detail
