// The map itself: construction, the region API, switching and observation
// insertion.
#include "avm/maps/CDualOctoMap.h"

#include <mrpt/maps/CPointsMap.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "RayIntegrator.h"
#include "RegionSpace.h"
#include "ResolutionPolicy.h"
#include "SurfaceSketch.h"
#include "OcTreeKeys.h"
#include "TreeOps.h"

using namespace avm;

CDualOctoMap::CDualOctoMap(
	const TCreationOptions& creation, const TInsertionOptions& insertion, const TLikelihoodOptions& likelihood)
	: insertionOptions(insertion), likelihoodOptions(likelihood), m_creation(creation)
{
	m_creation.validate("creationOpts");
	insertionOptions.validate("insertOpts");
	likelihoodOptions.validate("likelihoodOpts");
	internal_clear();
}

CDualOctoMap::~CDualOctoMap() = default;

CDualOctoMap::CDualOctoMap(const CDualOctoMap& o)
	: mrpt::maps::CMetricMap(o), m_integrator(std::make_unique<detail::RayIntegrator>())
{
	copyFrom(o);
}

CDualOctoMap& CDualOctoMap::operator=(const CDualOctoMap& o)
{
	if (this == &o) return *this;
	mrpt::maps::CMetricMap::operator=(o);
	copyFrom(o);
	return *this;
}

void CDualOctoMap::copyFrom(const CDualOctoMap& o)
{
	insertionOptions = o.insertionOptions;
	likelihoodOptions = o.likelihoodOptions;
	renderingOptions = o.renderingOptions;
	m_creation = o.m_creation;
	m_low = std::make_unique<octomap::OcTree>(*o.m_low);
	m_high = o.m_high ? std::make_unique<octomap::OcTree>(*o.m_high) : nullptr;
	m_policy = std::make_unique<detail::ResolutionPolicy>(*o.m_policy);
	m_sketch = std::make_unique<detail::SurfaceSketch>(*o.m_sketch);
	m_insertions = o.m_insertions;
	m_pointsCacheValid = false;
}

void CDualOctoMap::internal_clear()
{
	m_low = detail::makeTree(m_creation.low);
	m_high.reset();
	m_policy = std::make_unique<detail::ResolutionPolicy>(insertionOptions.switchPolicy, m_creation.low.resolution);
	m_sketch = std::make_unique<detail::SurfaceSketch>(
		static_cast<unsigned>(std::lround(m_creation.low.resolution / m_creation.high.resolution)));
	if (!m_integrator) m_integrator = std::make_unique<detail::RayIntegrator>();
	m_insertions = 0;
	m_pointsCacheValid = false;
}

octomap::OcTree& CDualOctoMap::ensureHighTree()
{
	if (!m_high) m_high = detail::makeTree(m_creation.high);
	return *m_high;
}

void CDualOctoMap::applyRegionChanges()
{
	if (m_policy->hasSwitched()) ensureHighTree();
	const auto change = m_policy->takeSpaceChange();
	for (const auto key : change.entered) detail::refineIntoHighTree(*m_low, ensureHighTree(), key, m_sketch.get());
	if (m_high)
		for (const auto key : change.left) detail::coarsenIntoLowTree(*m_high, *m_low, key, *m_sketch);
	m_pointsCacheValid = false;
}

void CDualOctoMap::addHighResolutionRegion(const mrpt::math::TBoundingBox& worldBox)
{
	m_policy->addFixedRegion(worldBox, m_insertions);
	applyRegionChanges();
}

void CDualOctoMap::placeRegions(const std::vector<TRegionPlacement>& placements)
{
	for (const auto& p : placements)
	{
		if (p.id == 0) throw std::invalid_argument("CDualOctoMap::placeRegions: region id 0 is reserved");
		m_policy->placeRegion(p.id, p.box, insertionOptions.regionLifetime, m_insertions);
	}
	applyRegionChanges();
}

bool CDualOctoMap::endRegion(std::uint32_t id)
{
	if (!m_policy->endRegion(id)) return false;
	applyRegionChanges();
	return true;
}

void CDualOctoMap::switchToHighResolution()
{
	m_policy->switchToHighResolution(m_insertions);
	applyRegionChanges();
}

bool CDualOctoMap::hasSwitched() const { return m_policy->hasSwitched(); }

const std::vector<THighResolutionRegion>& CDualOctoMap::highResolutionRegions() const { return m_policy->regions(); }

std::optional<std::size_t> CDualOctoMap::switchInsertionIndex() const { return m_policy->switchIndex(); }

void CDualOctoMap::setExpectedFrameCount(std::size_t frames) { insertionOptions.expectedFrameCount = frames; }

std::size_t CDualOctoMap::insertionCount() const { return m_insertions; }

const octomap::OcTree* CDualOctoMap::tree(Resolution which) const
{
	return which == Resolution::Low ? m_low.get() : m_high.get();
}

detail::ScanTargets CDualOctoMap::prepareInsertion()
{
	m_policy->beforeIntegration(m_insertions, insertionOptions.switchAtInsertion, insertionOptions.switchAtFraction,
		insertionOptions.expectedFrameCount);
	applyRegionChanges();
	detail::ScanTargets t;
	if (m_policy->policy() == SwitchPolicy::Paper && m_policy->hasSwitched())
	{
		// Algorithm 1 after the switch: all to the high tree, through Algorithm 2.
		t.outside = &ensureHighTree();
		t.outsideMaxRange = m_creation.high.maxRange;
		t.overlapFilter = m_low.get();
		return t;
	}
	t.outside = m_low.get();
	t.outsideMaxRange = m_creation.low.maxRange;
	if (m_policy->policy() == SwitchPolicy::Region && m_sketch->usable())
	{
		t.sketch = m_sketch.get();
		t.sketchResolution = m_creation.high.resolution;
	}
	if (m_policy->policy() == SwitchPolicy::Region && m_policy->hasSwitched())
	{
		t.inside = &ensureHighTree();
		t.insideMaxRange = m_creation.high.maxRange;
		t.regions = &m_policy->boxes();
	}
	return t;
}

void CDualOctoMap::finishInsertion()
{
	// The sketch matters for occupied low voxels and for free ones that still
	// hold a surface not seen through: forget the others now and then.
	constexpr std::size_t kSketchPruneEvery = 30;  // insertions
	if (m_insertions % kSketchPruneEvery == kSketchPruneEvery - 1)
		m_sketch->prune(
			[&](std::uint64_t lowKey, std::uint64_t bits)
			{
				const auto* node = m_low->search(detail::unpackKey(lowKey));
				return node && (bits != 0 || m_low->isNodeOccupied(node));
			});
	++m_insertions;
	m_pointsCacheValid = false;
}

bool CDualOctoMap::insertsAsDepthImage(const mrpt::obs::CObservation3DRangeScan& scan)
{
	if (scan.hasRangeImage && scan.rangeImage_isExternallyStored()) scan.load();
	return scan.hasRangeImage && scan.rangeImage.rows() != 0 && scan.cameraParams.fx() > 0;
}

bool CDualOctoMap::internal_insertObservation(
	const mrpt::obs::CObservation& obs, const std::optional<const mrpt::poses::CPose3D>& robotPose)
{
	const mrpt::poses::CPose3D robot = robotPose ? *robotPose : mrpt::poses::CPose3D();
	for (int i = 0; i < 6; i++)
		if (!std::isfinite(robot[i]))
			throw std::invalid_argument(
				"CAdaptiveOctoMap::insertObservation: non-finite robot pose " + robot.asString());

	if (const auto* scan = dynamic_cast<const mrpt::obs::CObservation3DRangeScan*>(&obs))
	{
		if (!insertsAsDepthImage(*scan)) return false;
		const mrpt::poses::CPose3D sensorPose = robot + scan->sensorPose;
		const auto freeOnly = beforeDepthImage(*scan, robot);
		m_integrator->setThreads(insertionOptions.insertionThreads);
		m_integrator->integrateDepthImage(*scan, sensorPose, prepareInsertion(), freeOnly);
		finishInsertion();
		return true;
	}
	if (const auto* cloud = dynamic_cast<const mrpt::obs::CObservationPointCloud*>(&obs))
	{
		if (!cloud->pointcloud || cloud->pointcloud->empty()) return false;
		const auto& pc = *cloud->pointcloud;
		m_integrator->integrateSensorPoints(pc.getPointsBufferRef_x().data(), pc.getPointsBufferRef_y().data(),
			pc.getPointsBufferRef_z().data(), pc.size(), robot + cloud->sensorPose, prepareInsertion());
		finishInsertion();
		return true;
	}
	return false;
}

bool CDualOctoMap::insertPointCloud(const mrpt::maps::CPointsMap& worldPoints, const mrpt::math::TPoint3D& sensorOrigin)
{
	if (worldPoints.empty()) return false;
	if (!std::isfinite(sensorOrigin.x) || !std::isfinite(sensorOrigin.y) || !std::isfinite(sensorOrigin.z))
		throw std::invalid_argument("CAdaptiveOctoMap::insertPointCloud: non-finite sensor origin");
	m_integrator->integrateWorldPoints(worldPoints.getPointsBufferRef_x().data(),
		worldPoints.getPointsBufferRef_y().data(), worldPoints.getPointsBufferRef_z().data(), worldPoints.size(),
		sensorOrigin, prepareInsertion());
	finishInsertion();
	return true;
}

bool CDualOctoMap::isEmpty() const { return m_low->size() == 0 && (!m_high || m_high->size() == 0); }
