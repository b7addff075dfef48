#include "avm/evaluation/ReferenceOctoMaps.h"

#include <mrpt/maps/CSimplePointsMap.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <set>

#include "avm/io/ThreadCpuTime.h"
#include "avm/plugin/CAdaptiveOctoMap.h"
#include "avm/maps/OcTreeFile.h"
#include "avm/maps/OccupiedKeys.h"
#include "PlainTreeStats.h"

namespace avm::evaluation
{
namespace
{
bool inRegions(const CAdaptiveOctoMap& map, double x, double y, double z)
{
	for (const auto& r : map.highResolutionRegions())
		for (const auto& b : r.boxes)
			if (x >= b.min.x && x < b.max.x && y >= b.min.y && y < b.max.y && z >= b.min.z && z < b.max.z) return true;
	return false;
}

/** Finest-level keys of the occupied voxels of `tree` whose centre is inside
 *  the regions (or outside, when `inside` is false). */
std::set<FinestKey> occupiedKeys(const octomap::OcTree& tree, const CAdaptiveOctoMap& map, bool inside)
{
	return occupiedFinestKeys(tree, [&](double x, double y, double z) { return inRegions(map, x, y, z) == inside; });
}

/** insertPointCloud(discretize = true) of `surface` and `freeOnly`, where the
 *  free-only points' rays update their free cells as octomap's computeUpdate
 *  makes them and their endpoint voxels are not marked occupied (a voxel both
 *  free on some ray and an endpoint is occupied, as in computeUpdate). */
void insertFreeOnly(octomap::OcTree& tree, const octomap::Pointcloud& surface, const octomap::Pointcloud& freeOnly,
	const octomap::point3d& origin, double maxRange)
{
	octomap::KeySet freeCells, occupiedCells, passingFree, passingEnds;
	tree.computeDiscreteUpdate(surface, origin, freeCells, occupiedCells, maxRange);
	tree.computeDiscreteUpdate(freeOnly, origin, passingFree, passingEnds, maxRange);
	for (const auto& k : passingFree)
		if (!occupiedCells.count(k)) freeCells.insert(k);
	for (const auto& k : freeCells) tree.updateNode(k, false);
	for (const auto& k : occupiedCells) tree.updateNode(k, true);
}

TReferenceComparison::Tree sizesOf(const octomap::OcTree& t, double totalMs, std::size_t frames)
{
	const auto plain = plainTreeStats(t);
	TReferenceComparison::Tree s;
	s.resolution = plain.resolution;
	s.occupiedLeaves = plain.occupiedLeaves;
	s.memoryBytes = plain.memoryBytes;
	s.binaryBytes = plain.binaryBytes;
	s.meanInsertMs = frames ? totalMs / double(frames) : 0;
	return s;
}
}  // namespace

ReferenceOctoMaps::ReferenceOctoMaps(double highRes, double lowRes, double highMaxRange, double lowMaxRange)
	: m_high(std::make_unique<octomap::OcTree>(highRes)),
	  m_low(std::make_unique<octomap::OcTree>(lowRes)),
	  m_highFreeOnly(std::make_unique<octomap::OcTree>(highRes)),
	  m_highMaxRange(highMaxRange),
	  m_lowMaxRange(lowMaxRange)
{
}

ReferenceOctoMaps::~ReferenceOctoMaps() = default;

void ReferenceOctoMaps::clear()
{
	m_high = std::make_unique<octomap::OcTree>(m_high->getResolution());
	m_low = std::make_unique<octomap::OcTree>(m_low->getResolution());
	m_highFreeOnly = std::make_unique<octomap::OcTree>(m_high->getResolution());
	m_highMs = m_lowMs = 0;
	m_frames = 0;
}

void ReferenceOctoMaps::insert(const mrpt::obs::CObservation3DRangeScan& obs, const mrpt::poses::CPose3D& robotPose,
	const std::vector<mrpt::math::TBoundingBox>& freeOnlyBoxes)
{
	mrpt::maps::CSimplePointsMap pts;
	mrpt::obs::T3DPointsProjectionParams pp;
	pp.takeIntoAccountSensorPoseOnRobot = true;
	pp.robotPoseInTheWorld = robotPose;
	const_cast<mrpt::obs::CObservation3DRangeScan&>(obs).unprojectInto(pts, pp);  // MRPT's is not const
	octomap::Pointcloud cloud, surface, freeOnly;
	cloud.reserve(pts.size());
	const auto& xs = pts.getPointsBufferRef_x();
	const auto& ys = pts.getPointsBufferRef_y();
	const auto& zs = pts.getPointsBufferRef_z();
	for (std::size_t i = 0; i < pts.size(); i++)
	{
		cloud.push_back(xs[i], ys[i], zs[i]);
		const mrpt::math::TPoint3D p(xs[i], ys[i], zs[i]);
		const bool passing = std::any_of(
			freeOnlyBoxes.begin(), freeOnlyBoxes.end(), [&](const auto& box) { return box.containsPoint(p); });
		(passing ? freeOnly : surface).push_back(xs[i], ys[i], zs[i]);
	}
	const auto o = (robotPose + obs.sensorPose).translation();
	const octomap::point3d origin(static_cast<float>(o.x), static_cast<float>(o.y), static_cast<float>(o.z));
	double t0 = io::threadCpuMs();
	m_high->insertPointCloud(cloud, origin, m_highMaxRange, false, true);
	m_highMs += io::threadCpuMs() - t0;
	t0 = io::threadCpuMs();
	m_low->insertPointCloud(cloud, origin, m_lowMaxRange, false, true);
	m_lowMs += io::threadCpuMs() - t0;
	insertFreeOnly(*m_highFreeOnly, surface, freeOnly, origin, m_highMaxRange);
	++m_frames;
}

TReferenceComparison ReferenceOctoMaps::compare(const CAdaptiveOctoMap& map) const
{
	TReferenceComparison c;
	c.high = sizesOf(*m_high, m_highMs, m_frames);
	c.low = sizesOf(*m_low, m_lowMs, m_frames);
	for (const auto& s : {map.lowResolutionStats(), map.highResolutionStats()})
	{
		c.adaptiveMemoryBytes += s.memoryBytes;
		c.adaptiveBinaryBytes += s.binaryBytes;
	}
	std::set<FinestKey> mineInside;
	if (const auto* high = map.tree(Resolution::High)) mineInside = occupiedKeys(*high, map, true);
	const auto refInside = occupiedKeys(*m_high, map, true);
	const auto freeOnlyInside = occupiedKeys(*m_highFreeOnly, map, true);
	const auto mineOutside = occupiedKeys(*map.tree(Resolution::Low), map, false);
	const auto refOutside = occupiedKeys(*m_low, map, false);
	c.insideAdaptive = mineInside.size();
	c.insideReference = refInside.size();
	c.insideIoU = intersectionOverUnion(mineInside, refInside);
	c.insideFreeOnlyReference = freeOnlyInside.size();
	c.insideFreeOnlyIoU = intersectionOverUnion(mineInside, freeOnlyInside);
	c.outsideAdaptive = mineOutside.size();
	c.outsideReference = refOutside.size();
	c.outsideIoU = intersectionOverUnion(mineOutside, refOutside);
	return c;
}
}  // namespace avm::evaluation
