#include "avm/persons/PersonLayer.h"

#include <algorithm>

#include "avm/io/IniKeys.h"

namespace avm::persons
{
PersonLayer::PersonLayer(const TrackerOptions& tracking) : m_tracker(tracking) {}

std::vector<PersonObservation> PersonLayer::observe(const mrpt::obs::CObservation3DRangeScan& obs,
	const mrpt::poses::CPose3D& sensorPoseInWorld, const std::vector<PixelSet>& persons, std::size_t frameIndex,
	const SightingOptions& sighting, double regionMargin, double shapeResolution)
{
	std::vector<PersonObservation> out(persons.size());
	std::vector<PersonSighting> sightings;
	std::vector<std::size_t> ofSighting;
	const mrpt::math::TPoint3D margin(regionMargin, regionMargin, regionMargin);
	for (std::size_t i = 0; i < persons.size(); i++)
	{
		// A shape is kept only at a positive resolution (personShape).
		auto est = estimateSighting(
			obs, sensorPoseInWorld, persons[i], sighting, shapeResolution > 0 ? BandPoints::Keep : BandPoints::Drop);
		out[i].skipReason = est.skipReason;
		if (!est.sighting) continue;
		const mrpt::math::TBoundingBox region(est.sighting->box.min - margin, est.sighting->box.max + margin);
		out[i].regionBox = region;
		auto& s = sightings.emplace_back(std::move(*est.sighting));
		s.shape = personShape(est.bandPoints, shapeResolution, region);
		ofSighting.push_back(i);
	}
	const auto ids = m_tracker.update(sightings, frameIndex, mrpt::Clock::toDouble(obs.timestamp));
	for (std::size_t s = 0; s < sightings.size(); s++)
	{
		auto& o = out[ofSighting[s]];
		o.personId = ids[s];
		o.sighting = std::move(sightings[s]);
	}
	return out;
}

std::vector<mrpt::math::TBoundingBox> PersonLayer::movingPersonBoxes(
	const mrpt::obs::CObservation3DRangeScan& obs, double horizon, double margin) const
{
	std::vector<mrpt::math::TBoundingBox> boxes;
	const double time = mrpt::Clock::toDouble(obs.timestamp);
	const mrpt::math::TPoint3D grow(margin, margin, margin);
	for (const auto& t : tracks())
	{
		const double since = time - t.lastTime;
		if (t.still || since > horizon) continue;
		const auto moved = t.velocity * std::max(0.0, since);
		// All the person's pixels, not the percentile box: a pixel of theirs
		// outside the box would become a wall.
		boxes.emplace_back(t.bandExtent.min + moved - grow, t.bandExtent.max + moved + grow);
	}
	return boxes;
}

io::IniKeys<TPersonLayerOptions> TPersonLayerOptions::iniKeys()
{
	using O = TPersonLayerOptions;
	using S = SightingOptions;
	using T = TrackerOptions;
	io::IniKeys<O> keys;
	keys.number("region_margin", &O::regionMargin, "m", "grown on each side of a person's box to make its region",
			{[](double v) { return v >= 0; }, "must be >= 0 metres"})
		.number("region_end_after_s", &O::regionEndAfterSeconds, "s",
			"follow: in-view time with no sighting after which a region ends, its detail folded into the low tree",
			{[](double v) { return v > 0; }, "must be > 0 seconds"})
		.text("person_label", &O::personLabel,
			"pixelLabels name of persons: \"person\" may hold many (one per 4-connected blob), \"person/<k>\" one each",
			{[](const std::string& v) { return !v.empty(); }, "must not be empty"})
		.number("person_depth_band", &O::sighting, &S::depthBand, "m",
			"half-width of the person's depth band around its robust depth; pixels outside are background",
			{[](double v) { return v > 0; }, "must be > 0 metres"})
		.number("person_percentile", &O::sighting, &S::percentile, "",
			"a person's box spans the [p, 1-p] percentiles of its points on each axis, p in [0, 0.5)",
			{[](double v) { return v >= 0 && v < 0.5; }, "must be in [0, 0.5)"})
		.number<std::int64_t>("min_person_pixels", &O::sighting, &S::minPixels, "pixels",
			"depth pixels in the band needed for a sighting", {[](std::int64_t v) { return v >= 1; }, "must be >= 1"})
		.number("min_person_depth_fraction", &O::sighting, &S::minDepthFraction, "0..1",
			"share of a person's pixels that must have depth",
			{[](double v) { return v >= 0 && v <= 1; }, "must be in [0, 1]"})
		.number("track_gate", &O::tracking, &T::gate, "m",
			"farthest a sighting may be from a track seen at the same instant to join it",
			{[](double v) { return v > 0; }, "must be > 0 metres"})
		.number("track_gate_growth", &O::tracking, &T::gateGrowth, "m/s",
			"the gate widens by this per second the track was unseen",
			{[](double v) { return v >= 0; }, "must be >= 0 m/s"})
		.number("track_max_gate", &O::tracking, &T::maxGate, "m",
			"widest gate: a person back near where last seen keeps the id")
		.number("person_still_fraction", &O::tracking, &T::stillFraction, "share of the box's mean edge",
			"a person who stays within this share of their own size of one place for person_still_after_s is still "
			"and mapped like any surface; else moving, and their pixels carve free space but are no surface",
			{[](double v) { return v >= 0; }, "must be >= 0"})
		.number("person_still_after_s", &O::tracking, &T::stillAfter, "s",
			"how long a person must stay in one place to be still",
			{[](double v) { return v >= 0; }, "must be >= 0 seconds"})
		.number<std::int64_t>("track_min_sightings", &O::tracking, &T::minSightings, "sightings",
			"a track is reported as a person (persons.csv, person_shapes.ply, the scene, the live view) once seen "
			"this often; any track has its region from its first sighting",
			{[](std::int64_t v) { return v >= 1; }, "must be >= 1"})
		.check(
			"track_max_gate", [](const O& o) { return o.tracking.maxGate >= o.tracking.gate; },
			"must be >= track_gate");
	return keys;
}
}  // namespace avm::persons

template struct avm::io::CIniKeyOptions<avm::persons::TPersonLayerOptions>;
