// The Bonn frames the map tests insert (depth + ground-truth camera pose),
// read once per test binary, and the reference maps they are compared with.
#pragma once

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/TPixelLabelInfo.h>
#include <mrpt/poses/CPose3D.h>
#include <octomap/OcTree.h>

#include <cstddef>
#include <memory>
#include <vector>

#include "TestData.h"
#include "avm/io/RawlogFrameReader.h"

namespace avm::test
{
struct MapFrame
{
	std::size_t index;
	mrpt::obs::CObservation3DRangeScan::Ptr obs;
	mrpt::poses::CPose3D pose;  //!< ground truth, camera optical frame
};

/** Every `step`-th frame among the first `count` with ground truth. */
inline std::vector<MapFrame> bonnFrames(std::size_t count, std::size_t step)
{
	std::vector<MapFrame> out;
	avm::io::RawlogFrameReader reader(bonnRawlog());
	while (auto f = reader.next())
	{
		if (f->index >= count) break;
		if (f->index % step != 0 || !f->groundTruth) continue;
		out.push_back({f->index, f->observation, *f->groundTruth});
	}
	if (out.empty()) throw std::runtime_error("no frames with ground truth in " + bonnRawlog().string());
	return out;
}

/** Every 5th of the first 150 frames (0.17 s apart), read once: 30 frames,
 *  about 1 m of camera path and the first people entering the view. */
inline const std::vector<MapFrame>& firstBonnFrames()
{
	static const auto frames = bonnFrames(150, 5);
	return frames;
}

/** The frame as octomap takes it: MRPT unprojects the depth image into the
 *  world frame; the rays start at the sensor. */
struct WorldCloud
{
	octomap::Pointcloud points;
	octomap::point3d origin;
};
inline WorldCloud worldCloud(const MapFrame& f)
{
	mrpt::maps::CSimplePointsMap pts;
	mrpt::obs::T3DPointsProjectionParams pp;
	pp.takeIntoAccountSensorPoseOnRobot = true;
	pp.robotPoseInTheWorld = f.pose;
	f.obs->unprojectInto(pts, pp);
	WorldCloud c;
	c.points.reserve(pts.size());
	const auto& xs = pts.getPointsBufferRef_x();
	const auto& ys = pts.getPointsBufferRef_y();
	const auto& zs = pts.getPointsBufferRef_z();
	for (std::size_t i = 0; i < pts.size(); i++) c.points.push_back(xs[i], ys[i], zs[i]);
	const auto o = (f.pose + f.obs->sensorPose).translation();
	c.origin = octomap::point3d(o.x, o.y, o.z);
	return c;
}

/** A single-resolution OctoMap built by octomap itself:
 *  insertPointCloud(discretize = true) integrates the frame's cloud. */
inline void insertWithOctomap(octomap::OcTree& tree, const MapFrame& f, double maxRange)
{
	const auto c = worldCloud(f);
	tree.insertPointCloud(c.points, c.origin, maxRange, false, true);
}
/** The frame with a 60 x 120 pixel patch at the image centre labelled
 *  "person", as a stock MRPT app gives its persons to the map. */
inline mrpt::obs::CObservation3DRangeScan::Ptr withPersonAtCentre(const MapFrame& f)
{
	auto labelled = mrpt::obs::CObservation3DRangeScan::Create(*f.obs);
	auto labels = std::make_shared<mrpt::obs::TPixelLabelInfo<1>>();
	const int rows = labelled->rangeImage.rows(), cols = labelled->rangeImage.cols();
	labels->setSize(rows, cols);
	labels->setLabelName(0, "person");
	for (int r = rows / 2 - 60; r < rows / 2 + 60; r++)
		for (int c = cols / 2 - 30; c < cols / 2 + 30; c++) labels->setLabel(r, c, 0);
	labelled->pixelLabels = labels;
	return labelled;
}
}  // namespace avm::test
