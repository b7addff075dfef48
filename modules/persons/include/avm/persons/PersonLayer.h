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
	/** [m] grown on each side of a person's box to make its region: a person
	 *  walking at 1 m/s moves less than this between two detections 3 frames
	 *  apart. */
	double regionMargin = 0.10;
	/** [s] follow lifetime: a region ends after its space was in view this
	 *  long with no sighting of its person (RegionClocks). */
	double regionEndAfterSeconds = 1.5;
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
	 *  box to make its region box. Each person seen keeps, with their track,
	 *  their shape at `shapeResolution` [m] (their region's resolution)
	 *  within their region box: personShape(). */
	std::vector<PersonObservation> observe(const mrpt::obs::CObservation3DRangeScan& obs,
		const mrpt::poses::CPose3D& sensorPoseInWorld, const std::vector<PixelSet>& persons, std::size_t frameIndex,
		const SightingOptions& sighting, double regionMargin, double shapeResolution);

	/** Where the persons on the move are at the time of `obs`: for each
	 *  moving track seen at most `horizon` [s] before the image, the box of
	 *  all its last sighting's points (PersonTrack::bandExtent) carried on by
	 *  its velocity to the image's time and grown by `margin` [m] on each
	 *  side. The image's pixels whose points lie in such a box are
	 *  the moving persons': their rays see free space up to the person, their
	 *  endpoints are no surface. Between two detections the track carries the
	 *  person forward this way. */
	std::vector<mrpt::math::TBoundingBox> movingPersonBoxes(
		const mrpt::obs::CObservation3DRangeScan& obs, double horizon, double margin) const;

	/** Every person seen so far, in order of id. */
	const std::vector<PersonTrack>& tracks() const { return m_tracker.tracks(); }

	void serializeTo(mrpt::serialization::CArchive& out) const { m_tracker.serializeTo(out); }
	/** `parts`: see PersonTracker::serializeFrom. */
	void serializeFrom(mrpt::serialization::CArchive& in, const TrackStreamParts& parts = {})
	{
		m_tracker.serializeFrom(in, parts);
	}

   private:
	PersonTracker m_tracker;
};
}  // namespace avm::persons
