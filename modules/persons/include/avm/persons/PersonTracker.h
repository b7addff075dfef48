// Sightings across frames become persons with stable ids: what a rescue team
// reads first (who was seen, where, when), and what the map keys its
// high-resolution regions by.
//
// Association is in the world frame, nearest first: a sighting joins the
// track whose last position is closest, if that is within the track's gate;
// each track takes at most one sighting a frame, so two people side by side
// stay two tracks. The gate widens with the time since the track was last
// seen (a person walks on while unseen) up to `maxGate`, and tracks never
// expire: a person out of view for a while and seen again near the same place
// keeps the id. Pairs are taken in the order (distance, track id, sighting
// index), so the same sightings always give the same ids.
//
// A track is a person once confirmed: seen `minSightings` times, as trackers
// confirm theirs (SORT's min_hits). A detector's false box, or a person's
// fragment split off for a frame or two, makes a track seen once or twice;
// such a track still places a region (a person's space is mapped in detail
// from their first sighting) but is not reported as a person.
//
// A track is still once its person has stayed within `stillFraction` of their
// own size (the mean edge of their box) of one place for `stillAfter` seconds:
// a victim lying still or a worker at a desk, mapped like any surface. Any
// other track is moving, and its pixels are no surface (PersonLayer).
#pragma once

#include <mrpt/math/TBoundingBox.h>
#include <mrpt/math/TPoint3D.h>
#include <mrpt/serialization/CArchive.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "avm/persons/PersonSighting.h"

namespace avm::persons
{
/** Loaded by the map from its `_insertOpts` (track_gate, track_gate_growth,
 *  track_max_gate, person_still_fraction, person_still_after_s,
 *  track_min_sightings). */
struct TrackerOptions
{
	double gate = 0.6;        //!< [m] gate of a track seen in the same instant
	double gateGrowth = 1.0;  //!< [m/s] gate widening per second unseen (walking pace)
	double maxGate = 1.5;     //!< [m] widest gate
	/** [share of the box's mean edge] farthest a still person may move from
	 *  where they settled: scale-free, so near and far persons, standing or
	 *  lying, are judged alike. */
	double stillFraction = 0.25;
	double stillAfter = 2.0;  //!< [s] a person settled this long is still
	/** Sightings that confirm a track as a person. 3, SORT's min_hits: on the
	 *  Bonn crowd sequence every track seen less often was seen once or
	 *  twice, every other at least 5 times. */
	std::size_t minSightings = 3;
};

struct PersonTrack
{
	std::uint32_t id = 0;  //!< 1, 2, ... in order of first sighting
	std::size_t firstFrame = 0, lastFrame = 0;
	double firstTime = 0, lastTime = 0;  //!< [s] UNIX time
	mrpt::math::TPoint3D position;       //!< last world position
	mrpt::math::TBoundingBox box;        //!< last world box (no margin)
	/** Last world box of all the person's points (PersonSighting::bandExtent). */
	mrpt::math::TBoundingBox bandExtent;
	std::size_t sightings = 0;
	/** [m/s] between the last two sightings (zero after the first). */
	mrpt::math::TPoint3D velocity{0, 0, 0};
	/** Where and since when [s] the person has stayed (within stillFraction). */
	mrpt::math::TPoint3D settledAt;
	double settledSince = 0;
	bool still = false;  //!< settled for stillAfter, as of the last sighting
	/** World frame: the person's last shape, their sighting's shape
	 *  (PersonSighting::shape), replaced at each sighting. */
	std::vector<mrpt::math::TPoint3Df> shape;
};

/** What a stream of tracks holds besides the tracks' sightings: the plugin
 *  map's stream has the motion from its version 2 on, the shapes from 3 on,
 *  the band extents from 4 on. */
struct TrackStreamParts
{
	bool motion = true;      //!< velocity and settling state
	bool shape = true;       //!< PersonTrack::shape
	bool bandExtent = true;  //!< PersonTrack::bandExtent
};

/** The tracks of `tracks` confirmed as persons (seen at least `minSightings`
 *  times), in their order: what is reported as persons. */
std::vector<PersonTrack> confirmedTracks(const std::vector<PersonTrack>& tracks, std::size_t minSightings);

/** The mean edge [m] of a box: the size a still person's motion is judged by. */
double meanEdge(const mrpt::math::TBoundingBox& box);

class PersonTracker
{
   public:
	explicit PersonTracker(const TrackerOptions& options = {});

	/** Associates the sightings of one frame; returns their track ids in the
	 *  sightings' order (new tracks for the unmatched ones). */
	std::vector<std::uint32_t> update(const std::vector<PersonSighting>& sightings, std::size_t frame, double time);

	/** Every track so far, in order of id. */
	const std::vector<PersonTrack>& tracks() const { return m_tracks; }

	/** Writes every part; reads the `parts` the stream holds (a track read
	 *  without motion is settled where last seen; without a shape, has none;
	 *  without a band extent, takes its box). */
	void serializeTo(mrpt::serialization::CArchive& out) const;
	void serializeFrom(mrpt::serialization::CArchive& in, const TrackStreamParts& parts = {});

   private:
	TrackerOptions m_options;
	std::vector<PersonTrack> m_tracks;
};
}  // namespace avm::persons
