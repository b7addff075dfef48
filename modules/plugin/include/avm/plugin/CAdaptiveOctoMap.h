// avm::CAdaptiveOctoMap — the MRPT plugin map "adaptiveOctoMap": the dual octree
// (avm::CDualOctoMap, modules/maps) joined with the person layer
// (avm::persons::PersonLayer, modules/persons). It reads the person pixel labels
// of each depth image it inserts, turns them into person tracks, moves each
// person's high-resolution region with it and ends the regions whose lifetime
// is over (persons::RegionClocks), so stock MRPT apps that load
// libavm-adaptive-octomap.so map people at high resolution with no avm code of
// their own. It owns the map's MRPT serialization (checkpoints, CMultiMetricMap
// copies) and the `.ini` map definition.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "avm/maps/CDualOctoMap.h"
#include "avm/persons/PersonLabels.h"
#include "avm/persons/PersonLayer.h"
#include "avm/persons/RegionClocks.h"

namespace avm
{
class CAdaptiveOctoMap : public CDualOctoMap
{
	DEFINE_SERIALIZABLE(CAdaptiveOctoMap, avm)

   public:
	/** Default options (region policy, 0.20 m / 0.05 m). */
	CAdaptiveOctoMap();
	/** Throws std::invalid_argument (naming the key) on invalid options. */
	CAdaptiveOctoMap(const TCreationOptions& creation, const TInsertionOptions& insertion,
		const TLikelihoodOptions& likelihood, const persons::TPersonLayerOptions& people = {});
	CAdaptiveOctoMap(const CAdaptiveOctoMap& other);
	CAdaptiveOctoMap& operator=(const CAdaptiveOctoMap& other);

	/** Section `<prefix>_insertOpts` too: person labels, sightings, tracks and
	 *  the margin of their regions. */
	persons::TPersonLayerOptions personOptions;

	/** The person layer on `persons`, the pixels of each person in `obs` (taken
	 *  at `robotPose`, composed with obs.sensorPose as for insertion), seen at
	 *  frame `frameIndex`; then the regions of the persons seen are placed,
	 *  each region's id its person's. Inserting an observation with person
	 *  pixel labels calls this itself, unless prepareRegions() was called. */
	std::vector<persons::PersonObservation> observePersons(const mrpt::obs::CObservation3DRangeScan& obs,
		const mrpt::poses::CPose3D& robotPose, const std::vector<persons::PixelSet>& persons, std::size_t frameIndex);
	/** The region step of depth image `scan`, to be inserted next at
	 *  `robotPose`, for a program whose persons come through observePersons
	 *  (avm-map): the follow regions age and those over end, and the moving
	 *  persons' boxes become the image's free-only boxes. Inserting that image
	 *  then reads no person labels and takes the step no second time; without
	 *  this call the insertion does both itself (stock MRPT apps). */
	void prepareRegions(const mrpt::obs::CObservation3DRangeScan& scan, const mrpt::poses::CPose3D& robotPose);
	/** Every person track so far, confirmed or not: each has had a region. */
	const std::vector<persons::PersonTrack>& personTracks() const { return m_persons.tracks(); }
	/** The tracks confirmed as persons (track_min_sightings): what is
	 *  reported as persons, in the scene (getVisualizationInto) and by
	 *  avm-map. */
	std::vector<persons::PersonTrack> confirmedPersons() const
	{
		return persons::confirmedTracks(personTracks(), personOptions.tracking.minSightings);
	}
	/** The follow lifetime's clock of each person region. */
	const persons::RegionClocks& regionClocks() const { return m_regionClocks; }
	/** The free-only boxes of the last depth image inserted (the moving
	 *  persons' boxes; none under the paper policy): for a reference map that
	 *  treats the same pixels the same way. Not serialized. */
	const std::vector<mrpt::math::TBoundingBox>& lastFreeOnlyBoxes() const { return m_lastFreeOnlyBoxes; }

	/** The dual octree's visualization, and the confirmed persons' last
	 *  shapes as one point cloud in the person colour, named kPersonShapesName. */
	void getVisualizationInto(mrpt::opengl::CSetOfObjects& outObj) const override;
	static constexpr const char* kPersonShapesName = "person_shapes";

	MAP_DEFINITION_START(CAdaptiveOctoMap)
	TCreationOptions creationOpts;
	TInsertionOptions insertionOpts;
	persons::TPersonLayerOptions personOpts;
	TLikelihoodOptions likelihoodOpts;
	TRenderingOptions renderOpts;
	/** Why the options were rejected ("" = valid); thrown when the map is
	 *  created (see loadFromConfigFile_map_specific). */
	std::string loadError;
	MAP_DEFINITION_END(CAdaptiveOctoMap)

   protected:
	void internal_clear() override;
	/** Unless prepareRegions() took the step for this image: the persons
	 *  labelled in it are observed before it is inserted, so the image is
	 *  mapped with their regions in place, then the region step. Region
	 *  policy: the pixels of the persons on the move are free only (a person
	 *  walking through leaves no trail); a still person is mapped like any
	 *  surface. */
	FreeOnlyBoxes beforeDepthImage(
		const mrpt::obs::CObservation3DRangeScan& scan, const mrpt::poses::CPose3D& robotPose) override;
	/** "person N": a region's id is its person's. */
	std::string regionLabel(std::uint32_t regionId) const override { return "person " + std::to_string(regionId); }

   private:
	/** Follow lifetime: the time until `scan` (taken at `robotPose`) counts
	 *  for the person regions its camera looks at; those unseen for
	 *  region_end_after_s in view end. */
	void endRegionsUnseenInView(const mrpt::obs::CObservation3DRangeScan& scan, const mrpt::poses::CPose3D& robotPose);
	/** The regions' end and the free-only boxes of `scan`. */
	void regionStep(const mrpt::obs::CObservation3DRangeScan& scan, const mrpt::poses::CPose3D& robotPose);

	/** Sightings and person tracks; it tells where the persons' regions go. */
	persons::PersonLayer m_persons;
	persons::RegionClocks m_regionClocks;
	FreeOnlyBoxes m_lastFreeOnlyBoxes;
	/** The image prepareRegions() took the step for, until it is inserted. */
	const mrpt::obs::CObservation3DRangeScan* m_regionsPreparedFor = nullptr;
};
}  // namespace avm
