// The plugin map's MRPT serialization: checkpoints, CMultiMetricMap copies and
// maps saved by stock MRPT apps. Version 1 is the stream of the map before the
// person layer moved out of it: the person layer's options, tracks and region
// clocks keep their places between the dual octree's parts.
#include <mrpt/serialization/CArchive.h>

#include <stdexcept>

#include "avm/plugin/CAdaptiveOctoMap.h"

using namespace avm;

IMPLEMENTS_SERIALIZABLE(CAdaptiveOctoMap, CMetricMap, avm)

// Version 1: per-person regions and person tracks. Version 2: the tracks'
// motion (velocity, where and since when the person stays) and the still keys.
// Version 3: each track's last shape. Version 4: each track's band extent.
// Version 5: track_min_sightings (a map of an earlier version reports every
// track, as it did).
uint8_t CAdaptiveOctoMap::serializeGetVersion() const { return 5; }

void CAdaptiveOctoMap::serializeTo(mrpt::serialization::CArchive& out) const
{
	out << genericMapParams;
	writeTreeOptions(out);
	const auto& i = insertionOptions;
	const auto& p = personOptions;
	out.WriteAs<uint8_t>(static_cast<uint8_t>(i.switchPolicy));
	out << p.regionMargin;
	out.WriteAs<uint8_t>(static_cast<uint8_t>(i.regionLifetime));
	out << p.regionEndAfterSeconds << p.personLabel << p.sighting.depthBand << p.sighting.percentile
		<< static_cast<uint64_t>(p.sighting.minPixels) << p.sighting.minDepthFraction << p.tracking.gate
		<< p.tracking.gateGrowth << p.tracking.maxGate << i.switchAtInsertion << i.switchAtFraction
		<< i.expectedFrameCount << i.insertionThreads << p.tracking.stillFraction << p.tracking.stillAfter
		<< static_cast<uint64_t>(p.tracking.minSightings);
	out << likelihoodOptions.decimation << renderingOptions.showFreeSpace << renderingOptions.showRegions;
	writeRegions(out, [this](auto& ar, std::uint32_t id) { m_regionClocks.writeClock(ar, id); });
	m_persons.serializeTo(out);
	writeSketch(out);
	m_regionClocks.writeImageTime(out);
	writeTrees(out);
}

void CAdaptiveOctoMap::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version)
{
	if (version < 1 || version > 5) MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
	in >> genericMapParams;
	readTreeOptions(in);
	auto& i = insertionOptions;
	auto& p = personOptions;
	i.switchPolicy = static_cast<SwitchPolicy>(in.ReadAs<uint8_t>());
	in >> p.regionMargin;
	const auto lifetime = in.ReadAs<uint8_t>();
	if (lifetime > static_cast<uint8_t>(RegionLifetime::Persist))
		throw std::runtime_error("CAdaptiveOctoMap: corrupt region lifetime in the serialized map");
	i.regionLifetime = static_cast<RegionLifetime>(lifetime);
	uint64_t minPixels = 0;
	in >> p.regionEndAfterSeconds >> p.personLabel >> p.sighting.depthBand >> p.sighting.percentile >> minPixels >>
		p.sighting.minDepthFraction >> p.tracking.gate >> p.tracking.gateGrowth >> p.tracking.maxGate >>
		i.switchAtInsertion >> i.switchAtFraction >> i.expectedFrameCount >> i.insertionThreads;
	p.sighting.minPixels = minPixels;
	if (version >= 2) in >> p.tracking.stillFraction >> p.tracking.stillAfter;
	uint64_t minSightings = 1;
	if (version >= 5) in >> minSightings;
	p.tracking.minSightings = minSightings;
	in >> likelihoodOptions.decimation >> renderingOptions.showFreeSpace >> renderingOptions.showRegions;
	creationOptions().validate("serialized creationOpts");
	insertionOptions.validate("serialized insertOpts");
	personOptions.validate("serialized insertOpts");
	m_regionClocks = {};
	readRegions(in, [this](auto& ar, std::uint32_t id) { m_regionClocks.readClock(ar, id); });
	m_persons = persons::PersonLayer(p.tracking);
	m_persons.serializeFrom(in, {version >= 2, version >= 3, version >= 4});
	readSketch(in);
	m_regionClocks.readImageTime(in);
	readTrees(in);
}
