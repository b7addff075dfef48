// The converted Bonn rawlog against the source PNGs and the ground truth.
#include <gtest/gtest.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/T3DPointsProjectionParams.h>

#include <algorithm>
#include <opencv2/imgcodecs.hpp>

#include "TestData.h"
#include "avm/io/RawlogFrameReader.h"
#include "avm/io/Trajectory.h"
#include "avm/io/TumDataset.h"

using namespace avm;
using mrpt::maps::CSimplePointsMap;
using mrpt::poses::CPose3D;

namespace
{
std::vector<io::RgbdFrame> readFrames(const std::vector<std::size_t>& wanted)
{
	io::RawlogFrameReader reader(test::bonnRawlog());
	std::vector<io::RgbdFrame> out;
	while (auto f = reader.next())
		if (std::find(wanted.begin(), wanted.end(), f->index) != wanted.end()) out.push_back(*f);
	return out;
}

/** World points of the static background (depth 0.3-4 m), every `step` pixels,
 *  projected by hand with the pinhole model and the optical-frame pose. */
CSimplePointsMap worldCloud(const mrpt::obs::CObservation3DRangeScan& obs, const CPose3D& cameraPose, int step)
{
	const cv::Mat depth = io::depthInMetres(obs);
	const auto& K = obs.cameraParams;
	CSimplePointsMap cloud;
	for (int v = 0; v < depth.rows; v += step)
		for (int u = 0; u < depth.cols; u += step)
		{
			const double d = depth.at<float>(v, u);
			if (d < 0.3 || d > 4.0) continue;
			const auto p = cameraPose.composePoint({(u - K.cx()) * d / K.fx(), (v - K.cy()) * d / K.fy(), d});
			cloud.insertPoint(p.x, p.y, p.z);
		}
	return cloud;
}

double medianNearestNeighbour(const CSimplePointsMap& query, const CSimplePointsMap& reference)
{
	std::vector<double> d;
	d.reserve(query.size());
	for (std::size_t i = 0; i < query.size(); ++i)
	{
		float x, y, z, nx, ny, nz, dsq;
		query.getPoint(i, x, y, z);
		reference.kdTreeClosestPoint3D(x, y, z, nx, ny, nz, dsq);
		d.push_back(std::sqrt(dsq));
	}
	std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
	return d[d.size() / 2];
}
}  // namespace

TEST(TumToRawlog, DepthIsExactlyThePngValueOver5000)
{
	const auto frames = readFrames({0, 150});
	const auto pairs = io::readAssociations(test::bonnDatasetDir() / "associations.txt");
	ASSERT_EQ(frames.size(), 2u);
	for (const auto& f : frames)
	{
		const cv::Mat png =
			cv::imread((test::bonnDatasetDir() / pairs[f.index].depth.file).string(), cv::IMREAD_ANYDEPTH);
		ASSERT_EQ(png.type(), CV_16UC1);
		const cv::Mat metres = io::depthInMetres(*f.observation);
		ASSERT_EQ(metres.size(), png.size());
		double worst = 0;
		for (int v = 0; v < png.rows; ++v)
			for (int u = 0; u < png.cols; ++u)
				worst = std::max(worst, std::abs(metres.at<float>(v, u) - png.at<uint16_t>(v, u) / 5000.0));
		EXPECT_LT(worst, 1e-6) << "frame " << f.index;
		EXPECT_DOUBLE_EQ(mrpt::Clock::toDouble(f.observation->timestamp), pairs[f.index].depth.timestamp);
	}
}

TEST(TumToRawlog, SensorPoseTurnsOpticalAxesIntoMrptSensorAxes)
{
	// Columns: the sensor's X (forward), Y (left), Z (up) in optical coordinates.
	const auto R = io::opticalToSensorPose().getRotationMatrix();
	const double expected[3][3] = {{0, -1, 0}, {0, 0, -1}, {1, 0, 0}};
	for (int r = 0; r < 3; ++r)
		for (int c = 0; c < 3; ++c) EXPECT_NEAR(R(r, c), expected[r][c], 1e-12) << r << "," << c;
}

TEST(TumToRawlog, MrptUnprojectionAgreesWithThePinholeModelInTheOpticalFrame)
{
	// MRPT places the points with robot pose (+) sensorPose; with the optical
	// pose as robot pose it must land them where the pinhole model does.
	auto frames = readFrames({0});
	ASSERT_EQ(frames.size(), 1u);
	auto& obs = *frames[0].observation;
	const CPose3D pose = *frames[0].groundTruth;
	CSimplePointsMap mrptCloud;
	mrpt::obs::T3DPointsProjectionParams pp;
	pp.takeIntoAccountSensorPoseOnRobot = true;
	pp.robotPoseInTheWorld = pose;
	obs.unprojectInto(mrptCloud, pp);
	const auto manual = worldCloud(obs, pose, 1);
	ASSERT_GT(mrptCloud.size(), 100000u);
	// Compare only where both keep points (the manual cloud cuts at 4 m).
	CSimplePointsMap nearMrpt;
	for (std::size_t i = 0; i < mrptCloud.size(); i += 7)
	{
		float x, y, z;
		mrptCloud.getPoint(i, x, y, z);
		const auto local = pose.inverseComposePoint({x, y, z});
		if (local.z > 0.35 && local.z < 3.95) nearMrpt.insertPoint(x, y, z);
	}
	EXPECT_LT(medianNearestNeighbour(nearMrpt, manual), 1e-3);
}

TEST(TumToRawlog, GroundTruthCameraPosesAlignCloudsOneSecondApart)
{
	// Frames 0 and 30 (no people yet): with the Bonn body-to-camera transform
	// the static background overlaps; with the raw mocap body poses it does not.
	const auto frames = readFrames({0, 30});
	ASSERT_EQ(frames.size(), 2u);
	const double withTransform = medianNearestNeighbour(worldCloud(*frames[1].observation, *frames[1].groundTruth, 4),
		worldCloud(*frames[0].observation, *frames[0].groundTruth, 2));
	EXPECT_LT(withTransform, 0.04);

	const auto body = io::readTumTrajectory(test::bonnDatasetDir() / "groundtruth.txt");
	const auto b0 = io::interpolatePose(body, frames[0].timestamp());
	const auto b1 = io::interpolatePose(body, frames[1].timestamp());
	ASSERT_TRUE(b0 && b1);
	const double withoutTransform =
		medianNearestNeighbour(worldCloud(*frames[1].observation, *b1, 4), worldCloud(*frames[0].observation, *b0, 2));
	EXPECT_GT(withoutTransform, 0.06);
	std::cout << "median NN distance: " << withTransform << " m with the Bonn transform, " << withoutTransform
			  << " m without\n";
}
