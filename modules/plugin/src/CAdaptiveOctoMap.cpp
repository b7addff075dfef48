// The plugin map: registration in MRPT, construction from an .ini map
// definition, and the person layer driving the dual octree's regions.
#include "avm/plugin/CAdaptiveOctoMap.h"

#include <mrpt/core/initializer.h>
#include <mrpt/opengl/CPointCloud.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/rtti/CObject.h>

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "avm/io/RgbdFrame.h"
#include "avm/persons/PersonColour.h"

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
		personOpts.loadFromConfigFile(source, prefix + "_insertOpts");
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
	personOpts.dumpToTextStream(out);
	likelihoodOpts.dumpToTextStream(out);
	renderOpts.dumpToTextStream(out);
}

mrpt::maps::CMetricMap* CAdaptiveOctoMap::internal_CreateFromMapDefinition(const mrpt::maps::TMetricMapInitializer& def)
{
	const auto& d = dynamic_cast<const TMapDefinition&>(def);
	if (!d.loadError.empty()) throw std::invalid_argument(d.loadError);
	auto* map = new CAdaptiveOctoMap(d.creationOpts, d.insertionOpts, d.likelihoodOpts, d.personOpts);
	map->renderingOptions = d.renderOpts;
	return map;
}

CAdaptiveOctoMap::CAdaptiveOctoMap() : CAdaptiveOctoMap(TCreationOptions(), TInsertionOptions(), TLikelihoodOptions())
{
}

CAdaptiveOctoMap::CAdaptiveOctoMap(const TCreationOptions& creation, const TInsertionOptions& insertion,
	const TLikelihoodOptions& likelihood, const persons::TPersonLayerOptions& people)
	: CDualOctoMap(creation, insertion, likelihood), personOptions(people), m_persons(people.tracking)
{
	personOptions.validate("insertOpts");
}

CAdaptiveOctoMap::CAdaptiveOctoMap(const CAdaptiveOctoMap& o)
	: CDualOctoMap(o),
	  personOptions(o.personOptions),
	  m_persons(o.m_persons),
	  m_regionClocks(o.m_regionClocks),
	  m_lastFreeOnlyBoxes(o.m_lastFreeOnlyBoxes)
{
}

CAdaptiveOctoMap& CAdaptiveOctoMap::operator=(const CAdaptiveOctoMap& o)
{
	if (this == &o) return *this;
	CDualOctoMap::operator=(o);
	personOptions = o.personOptions;
	m_persons = o.m_persons;
	m_regionClocks = o.m_regionClocks;
	m_lastFreeOnlyBoxes = o.m_lastFreeOnlyBoxes;
	return *this;
}

void CAdaptiveOctoMap::internal_clear()
{
	CDualOctoMap::internal_clear();
	m_persons = persons::PersonLayer(personOptions.tracking);
	m_regionClocks = {};
	m_lastFreeOnlyBoxes.clear();
	m_regionsPreparedFor = nullptr;
}

std::vector<persons::PersonObservation> CAdaptiveOctoMap::observePersons(const mrpt::obs::CObservation3DRangeScan& obs,
	const mrpt::poses::CPose3D& robotPose, const std::vector<persons::PixelSet>& persons, std::size_t frameIndex)
{
	if (persons.empty()) return {};
	if (!io::isFinite(robotPose))
		throw std::invalid_argument("CAdaptiveOctoMap::observePersons: non-finite robot pose " + robotPose.asString());
	if (obs.hasRangeImage && obs.rangeImage_isExternallyStored()) obs.load();
	auto seen = m_persons.observe(obs, robotPose + obs.sensorPose, persons, frameIndex, personOptions.sighting,
		personOptions.regionMargin, creationOptions().high.resolution);
	const double time = mrpt::Clock::toDouble(obs.timestamp);
	const auto& regions = highResolutionRegions();
	std::vector<TRegionPlacement> placements;
	for (const auto& o : seen)
	{
		if (!o.regionBox) continue;
		placements.push_back({o.personId, *o.regionBox});
		const bool newRegion = std::none_of(
			regions.begin(), regions.end(), [&](const THighResolutionRegion& r) { return r.regionId == o.personId; });
		m_regionClocks.seen(o.personId, time, newRegion);
	}
	placeRegions(placements);
	return seen;
}

void CAdaptiveOctoMap::endRegionsUnseenInView(
	const mrpt::obs::CObservation3DRangeScan& scan, const mrpt::poses::CPose3D& robotPose)
{
	std::vector<persons::RegionInView> regions;
	for (const auto& r : highResolutionRegions())
		if (r.regionId != 0 && !r.boxes.empty()) regions.push_back({r.regionId, r.boxes.back()});
	const auto sensorPose = robotPose + scan.sensorPose;
	const auto ended = m_regionClocks.age(mrpt::Clock::toDouble(scan.timestamp),
		insertionOptions.regionLifetime == RegionLifetime::Follow, regions, personOptions.regionEndAfterSeconds,
		[&](const mrpt::math::TBoundingBox& box) { return inCameraView(box, scan, sensorPose); });
	for (const auto id : ended) endRegion(id);
}

void CAdaptiveOctoMap::prepareRegions(
	const mrpt::obs::CObservation3DRangeScan& scan, const mrpt::poses::CPose3D& robotPose)
{
	// Only for an image the insertion maps as depth: it calls the hook for no other.
	if (!insertsAsDepthImage(scan)) return;
	regionStep(scan, robotPose);
	m_regionsPreparedFor = &scan;
}

void CAdaptiveOctoMap::regionStep(const mrpt::obs::CObservation3DRangeScan& scan, const mrpt::poses::CPose3D& robotPose)
{
	endRegionsUnseenInView(scan, robotPose);
	// Algorithm 1 maps every point; the region policy knows who moves. A
	// person unseen for as long as a region lasts unseen is no longer
	// followed; the region margin is how far they may stray from their box.
	m_lastFreeOnlyBoxes.clear();
	if (insertionOptions.switchPolicy == SwitchPolicy::Region)
		m_lastFreeOnlyBoxes =
			m_persons.movingPersonBoxes(scan, personOptions.regionEndAfterSeconds, personOptions.regionMargin);
}

CDualOctoMap::FreeOnlyBoxes CAdaptiveOctoMap::beforeDepthImage(
	const mrpt::obs::CObservation3DRangeScan& scan, const mrpt::poses::CPose3D& robotPose)
{
	if (std::exchange(m_regionsPreparedFor, nullptr) != &scan)
	{
		observePersons(scan, robotPose,
			persons::personPixelsFromLabels(scan, personOptions.personLabel, personOptions.sighting.minPixels),
			insertionCount());
		regionStep(scan, robotPose);
	}
	return m_lastFreeOnlyBoxes;
}

void CAdaptiveOctoMap::getVisualizationInto(mrpt::opengl::CSetOfObjects& outObj) const
{
	CDualOctoMap::getVisualizationInto(outObj);
	if (!genericMapParams.enableSaveAs3DObject) return;
	auto shapes = mrpt::opengl::CPointCloud::Create();
	for (const auto& t : confirmedPersons())
		for (const auto& p : t.shape) shapes->insertPoint(p.x, p.y, p.z);
	if (shapes->empty()) return;
	shapes->setName(kPersonShapesName);
	shapes->setColor_u8(persons::kPersonColour);
	shapes->setPointSize(4.0f);
	outObj.insert(shapes);
}
