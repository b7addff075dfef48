#include "avm/persons/PersonLayer.h"

namespace avm::persons
{
PersonLayer::PersonLayer(const TrackerOptions& tracking) : m_tracker(tracking) {}

std::vector<PersonObservation> PersonLayer::observe(const mrpt::obs::CObservation3DRangeScan& obs,
	const mrpt::poses::CPose3D& sensorPoseInWorld, const std::vector<PixelSet>& persons, std::size_t frameIndex,
	const SightingOptions& sighting, double regionMargin)
{
	std::vector<PersonObservation> out(persons.size());
	std::vector<PersonSighting> sightings;
	std::vector<std::size_t> ofSighting;
	for (std::size_t i = 0; i < persons.size(); i++)
	{
		auto est = estimateSighting(obs, sensorPoseInWorld, persons[i], sighting);
		out[i].skipReason = est.skipReason;
		if (!est.sighting) continue;
		out[i].sighting = est.sighting;
		sightings.push_back(*est.sighting);
		ofSighting.push_back(i);
	}
	const auto ids = m_tracker.update(sightings, frameIndex, mrpt::Clock::toDouble(obs.timestamp));
	const mrpt::math::TPoint3D margin(regionMargin, regionMargin, regionMargin);
	for (std::size_t s = 0; s < sightings.size(); s++)
	{
		auto& o = out[ofSighting[s]];
		o.personId = ids[s];
		auto box = sightings[s].box;
		box.min -= margin;
		box.max += margin;
		o.regionBox = box;
	}
	return out;
}
}  // namespace avm::persons
