// One pinhole model in two frames (io::DepthCamera): MRPT's depth-sensor frame
// (X forward, Y left, Z up) for the map, the optical frame (x right, y down,
// z forward) for visual odometry; both must be the same camera.
#include <gtest/gtest.h>

#include "avm/io/DepthCamera.h"

using namespace avm;

namespace
{
io::DepthCamera camera() { return {525.0, 520.0, 319.5, 239.5, 640, 480, true}; }
}  // namespace

TEST(DepthCamera, OpticalAndSensorFramesAreTheSameCamera)
{
	const auto K = camera();
	for (const auto& [u, v, d] : {std::tuple{10.0, 20.0, 1.5}, {319.5, 239.5, 3.0}, {600.25, 470.75, 0.4}})
	{
		const Eigen::Vector3d optical = K.opticalPointOf(u, v, d);
		const auto sensor = K.unproject(u, v, d);
		// Sensor X, Y, Z are optical z, -x, -y.
		EXPECT_NEAR(sensor.x, optical.z(), 1e-12);
		EXPECT_NEAR(sensor.y, -optical.x(), 1e-12);
		EXPECT_NEAR(sensor.z, -optical.y(), 1e-12);
		const Eigen::Vector2d pixel = K.opticalPixelOf(optical);
		EXPECT_NEAR(pixel.x(), u, 1e-9);
		EXPECT_NEAR(pixel.y(), v, 1e-9);
		const auto sensorPixel = K.pixelOf(sensor);
		EXPECT_NEAR(sensorPixel.x, u, 1e-9);
		EXPECT_NEAR(sensorPixel.y, v, 1e-9);
	}
}

TEST(DepthCamera, ARangeImageValueIsTheDistanceAlongTheRay)
{
	auto K = camera();
	K.rangeIsDepth = false;
	const auto p = K.unproject(10.0, 20.0, 2.0);
	EXPECT_NEAR(p.norm(), 2.0, 1e-12);
	EXPECT_NEAR(K.pixelOf(p).x, 10.0, 1e-9);
	EXPECT_NEAR(K.pixelOf(p).y, 20.0, 1e-9);
}
