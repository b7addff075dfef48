// The map itself: construction from an .ini map definition, plugin
// registration, triggers and observation insertion.
#include "avm/maps/CAdaptiveOctoMap.h"

#include <mrpt/core/initializer.h>
#include <mrpt/maps/CPointsMap.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/rtti/CObject.h>
#include <octomap/OcTree.h>

#include <cmath>
#include <stdexcept>

#include "RayIntegrator.h"
#include "ResolutionPolicy.h"
#include "TreeOps.h"

using namespace avm;

MAP_DEFINITION_REGISTER("avm::CAdaptiveOctoMap,adaptiveOctoMap", avm::CAdaptiveOctoMap)

// A plugin loaded by dlopen must register its class itself, or MRPT cannot
// deserialize it (CMultiMetricMap copies maps by serializing them).
MRPT_INITIALIZER(avm_register_CAdaptiveOctoMap)
{
	mrpt::rtti::registerClass(CLASS_ID(avm::CAdaptiveOctoMap));
}

CAdaptiveOctoMap::TMapDefinition::TMapDefinition() = default;

void CAdaptiveOctoMap::TMapDefinition::loadFromConfigFile_map_specific(
	const mrpt::config::CConfigFileBase& source, const std::string& prefix)
{
	// MRPT 2.5.8's TSetOfMetricMapInitializers::loadFromConfigFile leaks the
	// definition when this throws (found by fuzzing), so a bad value is kept
	// and thrown when the map is created, with the same message.
	try
	{
		creationOpts.loadFromConfigFile(source, prefix + "_creationOpts");
		insertionOpts.loadFromConfigFile(source, prefix + "_insertOpts");
		likelihoodOpts.loadFromConfigFile(source, prefix + "_likelihoodOpts");
		renderOpts.loadFromConfigFile(source, prefix + "_renderOpts");
		loadError.clear();
	}
	catch (const std::exception& e)
	{
		loadError = e.what();
	}
}

void CAdaptiveOctoMap::TMapDefinition::dumpToTextStream_map_specific(std::ostream& out) const
{
	creationOpts.dumpToTextStream(out);
	insertionOpts.dumpToTextStream(out);
	likelihoodOpts.dumpToTextStream(out);
	renderOpts.dumpToTextStream(out);
}

mrpt::maps::CMetricMap* CAdaptiveOctoMap::internal_CreateFromMapDefinition(
	const mrpt::maps::TMetricMapInitializer& def)
{
	const auto& d = dynamic_cast<const TMapDefinition&>(def);
	if (!d.loadError.empty()) throw std::invalid_argument(d.loadError);
	auto* map = new CAdaptiveOctoMap(d.creationOpts, d.insertionOpts, d.likelihoodOpts);
	map->renderingOptions = d.renderOpts;
	return map;
}

CAdaptiveOctoMap::CAdaptiveOctoMap() : CAdaptiveOctoMap(TCreationOptions(), TInsertionOptions(), TLikelihoodOptions()) {}

CAdaptiveOctoMap::CAdaptiveOctoMap(
	const TCreationOptions& creation, const TInsertionOptions& insertion, const TLikelihoodOptions& likelihood)
	: insertionOptions(insertion), likelihoodOptions(likelihood), m_creation(creation)
{
	m_creation.validate("creationOpts");
	insertionOptions.validate("insertOpts");
	likelihoodOptions.validate("likelihoodOpts");
	internal_clear();
}

CAdaptiveOctoMap::~CAdaptiveOctoMap() = default;

CAdaptiveOctoMap::CAdaptiveOctoMap(const CAdaptiveOctoMap& o)
	: mrpt::maps::CMetricMap(o),
	  insertionOptions(o.insertionOptions),
	  likelihoodOptions(o.likelihoodOptions),
	  renderingOptions(o.renderingOptions),
	  m_creation(o.m_creation),
	  m_low(std::make_unique<octomap::OcTree>(*o.m_low)),
	  m_high(o.m_high ? std::make_unique<octomap::OcTree>(*o.m_high) : nullptr),
	  m_policy(std::make_unique<detail::ResolutionPolicy>(*o.m_policy)),
	  m_integrator(std::make_unique<detail::RayIntegrator>()),
	  m_insertions(o.m_insertions)
{
}

CAdaptiveOctoMap& CAdaptiveOctoMap::operator=(const CAdaptiveOctoMap& o)
{
	if (this == &o) return *this;
	CAdaptiveOctoMap copy(o);
	mrpt::maps::CMetricMap::operator=(o);
	insertionOptions = copy.insertionOptions;
	likelihoodOptions = copy.likelihoodOptions;
	renderingOptions = copy.renderingOptions;
	m_creation = copy.m_creation;
	m_low = std::move(copy.m_low);
	m_high = std::move(copy.m_high);
	m_policy = std::move(copy.m_policy);
	m_insertions = copy.m_insertions;
	m_pointsCacheValid = false;
	return *this;
}

void CAdaptiveOctoMap::internal_clear()
{
	m_low = detail::makeTree(m_creation.low);
	m_high.reset();
	m_policy = std::make_unique<detail::ResolutionPolicy>(insertionOptions.switchPolicy, m_creation.low.resolution);
	if (!m_integrator) m_integrator = std::make_unique<detail::RayIntegrator>();
	m_insertions = 0;
	m_pointsCacheValid = false;
}

octomap::OcTree& CAdaptiveOctoMap::ensureHighTree()
{
	if (!m_high) m_high = detail::makeTree(m_creation.high);
	return *m_high;
}

void CAdaptiveOctoMap::applyRegionChanges()
{
	if (m_policy->highActive()) ensureHighTree();
	for (const auto& box : m_policy->takeGrownRegions()) detail::deleteSpace(*m_low, box);
	for (const auto& box : m_policy->takeExpiredRegions())
		if (m_high) detail::deleteSpace(*m_high, box);
	m_pointsCacheValid = false;
}

void CAdaptiveOctoMap::addHighResolutionRegion(const mrpt::math::TBoundingBox& worldBox)
{
	m_policy->addRegion(worldBox, m_insertions);
	applyRegionChanges();
}

void CAdaptiveOctoMap::switchToHighResolution()
{
	m_policy->trigger(m_insertions);
	applyRegionChanges();
}

bool CAdaptiveOctoMap::isHighResolutionActive() const { return m_policy->highActive(); }

std::vector<mrpt::math::TBoundingBox> CAdaptiveOctoMap::highResolutionRegions() const
{
	std::vector<mrpt::math::TBoundingBox> out;
	for (const auto& r : m_policy->regions()) out.push_back(r.box);
	return out;
}

std::optional<std::size_t> CAdaptiveOctoMap::switchInsertionIndex() const { return m_policy->switchIndex(); }

void CAdaptiveOctoMap::setExpectedFrameCount(std::size_t frames) { insertionOptions.expectedFrameCount = frames; }

std::size_t CAdaptiveOctoMap::insertionCount() const { return m_insertions; }

const octomap::OcTree* CAdaptiveOctoMap::tree(Resolution which) const
{
	return which == Resolution::Low ? m_low.get() : m_high.get();
}

detail::ScanTargets CAdaptiveOctoMap::prepareInsertion()
{
	m_policy->beforeIntegration(m_insertions, insertionOptions, insertionOptions.expectedFrameCount);
	applyRegionChanges();
	detail::ScanTargets t;
	if (m_policy->policy() == SwitchPolicy::Paper && m_policy->highActive())
	{
		// Algorithm 1 after the switch: all to the high tree, through Algorithm 2.
		t.outside = &ensureHighTree();
		t.outsideMaxRange = m_creation.high.maxRange;
		t.overlapFilter = m_low.get();
		return t;
	}
	t.outside = m_low.get();
	t.outsideMaxRange = m_creation.low.maxRange;
	if (m_policy->policy() == SwitchPolicy::Region && m_policy->highActive())
	{
		t.inside = &ensureHighTree();
		t.insideMaxRange = m_creation.high.maxRange;
		t.regions = &m_policy->regions();
	}
	return t;
}

void CAdaptiveOctoMap::finishInsertion()
{
	++m_insertions;
	m_pointsCacheValid = false;
}

bool CAdaptiveOctoMap::internal_insertObservation(
	const mrpt::obs::CObservation& obs, const std::optional<const mrpt::poses::CPose3D>& robotPose)
{
	const mrpt::poses::CPose3D robot = robotPose ? *robotPose : mrpt::poses::CPose3D();
	for (int i = 0; i < 6; i++)
		if (!std::isfinite(robot[i]))
			throw std::invalid_argument("CAdaptiveOctoMap::insertObservation: non-finite robot pose " + robot.asString());

	if (const auto* scan = dynamic_cast<const mrpt::obs::CObservation3DRangeScan*>(&obs))
	{
		if (scan->hasRangeImage && scan->rangeImage_isExternallyStored()) scan->load();
		if (!scan->hasRangeImage || scan->rangeImage.rows() == 0 || scan->cameraParams.fx() <= 0) return false;
		const mrpt::poses::CPose3D sensorPose = robot + scan->sensorPose;
		for (const auto& box : detail::regionsFromPixelLabels(*scan, sensorPose, insertionOptions))
			m_policy->addRegion(box, m_insertions);
		m_integrator->setThreads(insertionOptions.insertionThreads);
		m_integrator->integrateDepthImage(*scan, sensorPose, prepareInsertion());
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

bool CAdaptiveOctoMap::insertPointCloud(const mrpt::maps::CPointsMap& worldPoints, const mrpt::math::TPoint3D& sensorOrigin)
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

bool CAdaptiveOctoMap::isEmpty() const
{
	return m_low->size() == 0 && (!m_high || m_high->size() == 0);
}
