// The person layer of one frame: each person's pixels become a sighting, the
// sightings join person tracks, and each person seen asks for a region: its own
// box grown by the region margin. No octree here: the caller moves the map's
// regions (keyed by person id) to these boxes through the map's region API.
#pragma once

#include <mrpt/math/TBoundingBox.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "avm/io/IniKeyOptions.h"
#include "avm/persons/PersonLabels.h"
#include "avm/persons/PersonSighting.h"
#include "avm/persons/PersonTracker.h"

namespace avm::persons
{
/** The person layer's keys, read from the map's `_insertOpts` section (where
 *  stock MRPT apps' ini files have always had them). */
struct TPersonLayerOptions : public io::CIniKeyOptions<TPersonLayerOptions>
{
	/** [m] grown on each side of a person's box to make its region. */
	double regionMargin = 0.20;
	/** Label name of the pixels that are persons (labelled rawlogs). */
	std::string personLabel = kPersonLabel;
	SightingOptions sighting;
	TrackerOptions tracking;

	static io::IniKeys<TPersonLayerOptions> iniKeys();
};

/** What the person layer made of one person's pixels. */
struct PersonObservation
{
	std::optional<PersonSighting> sighting;
	std::uint32_t personId = 0;  //!< the track (0 when there is no sighting)
	/** The region box the person asks for (world, margin included, before the
	 *  map aligns it to its grid); nothing when there is no sighting. */
	std::optional<mrpt::math::TBoundingBox> regionBox;
	std::string skipReason;  //!< why there is no sighting
};

class PersonLayer
{
   public:
	explicit PersonLayer(const TrackerOptions& tracking = {});

	/** The persons whose pixels are `persons` in `obs`, its depth sensor at
	 *  `sensorPoseInWorld`, seen at frame `frameIndex`: one answer per person,
	 *  in their order. `regionMargin` [m] is grown on each side of a sighting's
	 *  box to make its region box. */
	std::vector<PersonObservation> observe(const mrpt::obs::CObservation3DRangeScan& obs,
		const mrpt::poses::CPose3D& sensorPoseInWorld, const std::vector<PixelSet>& persons, std::size_t frameIndex,
		const SightingOptions& sighting, double regionMargin);

	/** Every person seen so far, in order of id. */
	const std::vector<PersonTrack>& tracks() const { return m_tracker.tracks(); }

	void serializeTo(mrpt::serialization::CArchive& out) const { m_tracker.serializeTo(out); }
	void serializeFrom(mrpt::serialization::CArchive& in) { m_tracker.serializeFrom(in); }

   private:
	PersonTracker m_tracker;
};
}  // namespace avm::persons
