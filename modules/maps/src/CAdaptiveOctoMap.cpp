// The map itself: construction from an .ini map definition, plugin
// registration, switching and observation insertion.
#include "avm/maps/CAdaptiveOctoMap.h"

#include <mrpt/core/initializer.h>
#include <mrpt/maps/CPointsMap.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/rtti/CObject.h>
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
#include "avm/io/DepthCamera.h"
#include "avm/io/RgbdFrame.h"

using namespace avm;

MAP_DEFINITION_REGISTER("avm::CAdaptiveOctoMap,adaptiveOctoMap", avm::CAdaptiveOctoMap)

// A plugin loaded by dlopen must register its class itself, or MRPT cannot
// deserialize it (CMultiMetricMap copies maps by serializing them).
MRPT_INITIALIZER(avm_register_CAdaptiveOctoMap) { mrpt::rtti::registerClass(CLASS_ID(avm::CAdaptiveOctoMap)); }

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

mrpt::maps::CMetricMap* CAdaptiveOctoMap::internal_CreateFromMapDefinition(const mrpt::maps::TMetricMapInitializer& def)
{
	const auto& d = dynamic_cast<const TMapDefinition&>(def);
	if (!d.loadError.empty()) throw std::invalid_argument(d.loadError);
	auto* map = new CAdaptiveOctoMap(d.creationOpts, d.insertionOpts, d.likelihoodOpts);
	map->renderingOptions = d.renderOpts;
	return map;
}

CAdaptiveOctoMap::CAdaptiveOctoMap() : CAdaptiveOctoMap(TCreationOptions(), TInsertionOptions(), TLikelihoodOptions())
{
}

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
	  m_sketch(std::make_unique<detail::SurfaceSketch>(*o.m_sketch)),
	  m_persons(o.m_persons),
	  m_lastScanTime(o.m_lastScanTime),
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
	m_sketch = std::move(copy.m_sketch);
	m_persons = copy.m_persons;
	m_lastScanTime = copy.m_lastScanTime;
	m_insertions = copy.m_insertions;
	m_pointsCacheValid = false;
	return *this;
}

void CAdaptiveOctoMap::internal_clear()
{
	m_low = detail::makeTree(m_creation.low);
	m_high.reset();
	m_policy = std::make_unique<detail::ResolutionPolicy>(insertionOptions.switchPolicy, m_creation.low.resolution);
	m_sketch = std::make_unique<detail::SurfaceSketch>(
		static_cast<unsigned>(std::lround(m_creation.low.resolution / m_creation.high.resolution)));
	m_persons = persons::PersonLayer(insertionOptions.tracking);
	m_lastScanTime.reset();
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
	if (m_policy->hasSwitched()) ensureHighTree();
	const auto change = m_policy->takeSpaceChange();
	for (const auto key : change.entered) detail::refineIntoHighTree(*m_low, ensureHighTree(), key, m_sketch.get());
	if (m_high)
		for (const auto key : change.left) detail::coarsenIntoLowTree(*m_high, *m_low, key, *m_sketch);
	m_pointsCacheValid = false;
}

void CAdaptiveOctoMap::addHighResolutionRegion(const mrpt::math::TBoundingBox& worldBox)
{
	m_policy->addFixedRegion(worldBox, m_insertions);
	applyRegionChanges();
}

void CAdaptiveOctoMap::placeRegions(const std::vector<TRegionPlacement>& placements, double time)
{
	for (const auto& p : placements)
	{
		if (p.id == 0) throw std::invalid_argument("CAdaptiveOctoMap::placeRegions: region id 0 is reserved");
		m_policy->personSeen(p.id, p.box, time, insertionOptions.regionLifetime, m_insertions);
	}
	applyRegionChanges();
}

bool CAdaptiveOctoMap::endRegion(std::uint32_t id)
{
	if (!m_policy->endRegion(id)) return false;
	applyRegionChanges();
	return true;
}

std::vector<persons::PersonObservation> CAdaptiveOctoMap::observePersons(const mrpt::obs::CObservation3DRangeScan& obs,
	const mrpt::poses::CPose3D& robotPose, const std::vector<persons::PixelSet>& persons, std::size_t frameIndex)
{
	if (persons.empty()) return {};
	if (!io::isFinite(robotPose))
		throw std::invalid_argument("CAdaptiveOctoMap::observePersons: non-finite robot pose " + robotPose.asString());
	if (obs.hasRangeImage && obs.rangeImage_isExternallyStored()) obs.load();
	auto seen = m_persons.observe(
		obs, robotPose + obs.sensorPose, persons, frameIndex, insertionOptions.sighting, insertionOptions.regionMargin);
	std::vector<TRegionPlacement> placements;
	for (const auto& o : seen)
		if (o.regionBox) placements.push_back({o.personId, *o.regionBox});
	placeRegions(placements, mrpt::Clock::toDouble(obs.timestamp));
	return seen;
}

const std::vector<persons::PersonTrack>& CAdaptiveOctoMap::personTracks() const { return m_persons.tracks(); }

void CAdaptiveOctoMap::ageRegions(const mrpt::obs::CObservation3DRangeScan& obs, const mrpt::poses::CPose3D& sensorPose)
{
	const double now = mrpt::Clock::toDouble(obs.timestamp);
	// A gap in the stream (a paused recording) is not time spent looking.
	constexpr double kMaxStep = 1.0;  // [s]
	const double from = m_lastScanTime ? std::max(*m_lastScanTime, now - kMaxStep) : now;
	m_lastScanTime = now;
	if (insertionOptions.regionLifetime != RegionLifetime::Follow || now <= from) return;
	const auto camera = io::DepthCamera::of(obs);
	const double range = m_creation.low.maxRange;
	// In view: the centre of the person's latest box is in the image and
	// within the sensor's range (occlusion is not considered).
	const auto inView = [&](const mrpt::math::TBoundingBox& box)
	{
		const auto p = sensorPose.inverseComposePoint((box.min + box.max) * 0.5);
		return p.x <= range && camera.project(p).has_value();
	};
	if (!m_policy->age(from, now, insertionOptions.regionEndAfterSeconds, inView).empty()) applyRegionChanges();
}

void CAdaptiveOctoMap::switchToHighResolution()
{
	m_policy->switchToHighResolution(m_insertions);
	applyRegionChanges();
}

bool CAdaptiveOctoMap::hasSwitched() const { return m_policy->hasSwitched(); }

const std::vector<THighResolutionRegion>& CAdaptiveOctoMap::highResolutionRegions() const
{
	return m_policy->regions();
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
	m_policy->beforeIntegration(m_insertions, insertionOptions.switchAtFrame, insertionOptions.switchAtFraction,
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

void CAdaptiveOctoMap::finishInsertion()
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

bool CAdaptiveOctoMap::internal_insertObservation(
	const mrpt::obs::CObservation& obs, const std::optional<const mrpt::poses::CPose3D>& robotPose)
{
	const mrpt::poses::CPose3D robot = robotPose ? *robotPose : mrpt::poses::CPose3D();
	for (int i = 0; i < 6; i++)
		if (!std::isfinite(robot[i]))
			throw std::invalid_argument(
				"CAdaptiveOctoMap::insertObservation: non-finite robot pose " + robot.asString());

	if (const auto* scan = dynamic_cast<const mrpt::obs::CObservation3DRangeScan*>(&obs))
	{
		if (scan->hasRangeImage && scan->rangeImage_isExternallyStored()) scan->load();
		if (!scan->hasRangeImage || scan->rangeImage.rows() == 0 || scan->cameraParams.fx() <= 0) return false;
		const mrpt::poses::CPose3D sensorPose = robot + scan->sensorPose;
		observePersons(*scan, robot,
			persons::personPixelsFromLabels(*scan, insertionOptions.personLabel, insertionOptions.sighting.minPixels),
			m_insertions);
		ageRegions(*scan, sensorPose);
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

bool CAdaptiveOctoMap::insertPointCloud(
	const mrpt::maps::CPointsMap& worldPoints, const mrpt::math::TPoint3D& sensorOrigin)
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

bool CAdaptiveOctoMap::isEmpty() const { return m_low->size() == 0 && (!m_high || m_high->size() == 0); }
