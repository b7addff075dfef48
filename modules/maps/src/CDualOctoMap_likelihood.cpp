// Observation likelihood and matching ratio, so that localization and SLAM
// apps can weigh poses against this map. As MRPT's COctoMap: the sum of
// log occupancy probabilities of the observed points that land in known
// voxels (unknown space neither rewards nor penalizes a pose).
#include <mrpt/maps/CPointsMap.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationPointCloud.h>

#include <cmath>

#include "avm/io/DepthCamera.h"
#include "avm/maps/CDualOctoMap.h"

using namespace avm;

namespace
{
double logOccupancy(const TOccupancyQuery& q)
{
	return q.state == OccupancyState::Unknown ? 0.0 : std::log(q.probability);
}
}  // namespace

bool CDualOctoMap::internal_canComputeObservationLikelihood(const mrpt::obs::CObservation& obs) const
{
	if (const auto* scan = dynamic_cast<const mrpt::obs::CObservation3DRangeScan*>(&obs)) return scan->hasRangeImage;
	if (const auto* cloud = dynamic_cast<const mrpt::obs::CObservationPointCloud*>(&obs))
		return cloud->pointcloud && !cloud->pointcloud->empty();
	return false;
}

double CDualOctoMap::internal_computeObservationLikelihood(
	const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const
{
	const std::size_t step = likelihoodOptions.decimation;
	double logLik = 0;
	if (const auto* scan = dynamic_cast<const mrpt::obs::CObservation3DRangeScan*>(&obs))
	{
		if (!scan->hasRangeImage) return 0;
		if (scan->rangeImage_isExternallyStored()) scan->load();
		const mrpt::poses::CPose3D sensorPose = takenFrom + scan->sensorPose;
		const auto camera = io::DepthCamera::of(*scan);
		const auto& img = scan->rangeImage;
		for (int v = 0; v < img.rows(); v += static_cast<int>(step))
			for (int u = 0; u < img.cols(); u += static_cast<int>(step))
			{
				if (img(v, u) == 0) continue;
				const auto p = camera.unproject(u, v, img(v, u) * scan->rangeUnits);
				logLik += logOccupancy(query(sensorPose.composePoint(p)));
			}
		return logLik;
	}
	if (const auto* cloud = dynamic_cast<const mrpt::obs::CObservationPointCloud*>(&obs))
	{
		if (!cloud->pointcloud) return 0;
		const mrpt::poses::CPose3D sensorPose = takenFrom + cloud->sensorPose;
		const auto& pc = *cloud->pointcloud;
		for (std::size_t i = 0; i < pc.size(); i += step)
		{
			mrpt::math::TPoint3D p;
			pc.getPoint(i, p);
			logLik += logOccupancy(query(sensorPose.composePoint(p)));
		}
	}
	return logLik;
}

float CDualOctoMap::compute3DMatchingRatio(const mrpt::maps::CMetricMap* otherMap,
	const mrpt::poses::CPose3D& otherMapPose, [[maybe_unused]] const mrpt::maps::TMatchingRatioParams& params) const
{
	// Matching is by voxel membership: a point matches when it falls in an
	// occupied voxel, so the distance thresholds of `params` do not apply.
	const auto* points = otherMap ? otherMap->getAsSimplePointsMap() : nullptr;
	if (!points || points->empty()) return 0;
	std::size_t matched = 0;
	for (std::size_t i = 0; i < points->size(); i++)
	{
		mrpt::math::TPoint3D p;
		points->getPoint(i, p);
		if (query(otherMapPose.composePoint(p)).state == OccupancyState::Occupied) matched++;
	}
	return static_cast<float>(matched) / static_cast<float>(points->size());
}
