// The follow lifetime of the persons' regions: a region ends once its space has
// been in view for region_end_after_s with no sighting of its person; a person
// out of view keeps it. The map knows regions, not why they end: the person
// layer keeps each region's clock and says which regions end; the map answers
// whether a box is in the camera's view and ends them.
#pragma once

#include <mrpt/math/TBoundingBox.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <vector>

namespace avm::persons
{
/** A person's region as the clocks see it: its id and its latest box. */
struct RegionInView
{
	std::uint32_t personId = 0;
	mrpt::math::TBoundingBox box;
};

class RegionClocks
{
   public:
	/** The person was seen at `time` [s] and their region placed: their clock
	 *  restarts. `newRegion`: the region is made now, so its clock starts
	 *  afresh (whatever a region of theirs that ended had counted). */
	void seen(std::uint32_t personId, double time, bool newRegion);

	/** A depth image taken at `time` [s]: the camera looked since the previous
	 *  image (a gap over a second, a paused recording, counts as a second).
	 *  When `follow`, that time counts, for each of `regions` whose box
	 *  `inView` holds, as far as it came after the person's last sighting;
	 *  returns the persons whose regions have now been in view `endAfter` [s]
	 *  with no sighting, in the order of `regions`. */
	std::vector<std::uint32_t> age(double time, bool follow, const std::vector<RegionInView>& regions, double endAfter,
		const std::function<bool(const mrpt::math::TBoundingBox&)>& inView);

	/** [s] in view with no sighting so far (0 for a person with no clock). */
	double unseenInViewSeconds(std::uint32_t personId) const;

	/** @name The stream
	 *  One region's clock, written with the map's record of that region, and
	 *  the last image's time, between the map's surface sketch and its trees
	 *  (where the map's stream has always had them).
	 * @{ */
	void writeClock(mrpt::serialization::CArchive& out, std::uint32_t personId) const;
	void readClock(mrpt::serialization::CArchive& in, std::uint32_t personId);
	void writeImageTime(mrpt::serialization::CArchive& out) const;
	void readImageTime(mrpt::serialization::CArchive& in);
	/** @} */

   private:
	struct Clock
	{
		double unseenInViewSeconds = 0;
		double lastSeenTime = 0;  //!< [s] UNIX time of the person's last sighting
	};
	std::map<std::uint32_t, Clock> m_clocks;
	/** [s] the time of the last depth image. */
	std::optional<double> m_lastImageTime;
};
}  // namespace avm::persons
