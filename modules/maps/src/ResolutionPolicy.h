// Algorithm 1 (resolution switching) and its per-region variant: which space
// the high-resolution tree maps, and how that changed. Knows nothing of
// octrees; CDualOctoMap applies the changes it reports to the trees.
//
// Region policy: the high-resolution space is the exact union of the low
// voxels covered by the regions' boxes (each box grown to whole low voxels),
// one region per id (the layer above gives each person one), never a box
// around several. Boxes may overlap; what
// they cover is tracked as a set of low voxel keys, so the trees learn
// exactly which low voxels entered the high-resolution space (to be refined)
// and which left it (to be coarsened).
#pragma once

#include <mrpt/math/TBoundingBox.h>
#include <mrpt/math/TPoint3D.h>
#include <mrpt/serialization/CArchive.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "KeySet.h"
#include "avm/maps/MapTypes.h"

namespace avm::detail
{
/** One box of high-resolution space, aligned to the low voxel grid: the unit
 *  the ray integrator tests against. */
struct Region
{
	mrpt::math::TBoundingBox box;

	/** Half-open on the max side, as octree voxels are. */
	bool contains(double x, double y, double z) const
	{
		return x >= box.min.x && x < box.max.x && y >= box.min.y && y < box.max.y && z >= box.min.z && z < box.max.z;
	}
};

/** The high-resolution space as the ray integrator tests it: the boxes for
 *  rays and points, and the low voxels they cover for keys, so that testing a
 *  key is one lookup however many boxes there are. */
struct RegionBoxes
{
	std::vector<Region> boxes;
	/** Packed low keys. */
	BoxKeySet covered;

	bool empty() const { return boxes.empty(); }
	/** Whether the voxel of `packed`, a key of a grid whose voxels divide the
	 *  low ones `ratio` times per axis, lies in the space. The regions are
	 *  whole low voxels, so this is whether its low voxel does. */
	bool covers(std::uint64_t packed, unsigned ratio) const
	{
		return covered.contains(ratio == 1 ? packed : coarserKeyOf(packed, ratio));
	}
};

/** Low voxels that entered and left the high-resolution space (packed keys
 *  of the low tree, see KeySet.h), in increasing key order. */
struct SpaceChange
{
	std::vector<std::uint64_t> entered, left;
};

class ResolutionPolicy
{
   public:
	ResolutionPolicy(SwitchPolicy policy, double lowResolution);

	SwitchPolicy policy() const { return m_policy; }

	/** Paper policy: switch to the high tree (later switches change nothing).
	 *  Region policy: std::logic_error. */
	void switchToHighResolution(std::size_t insertionIndex);
	/** Region policy: a region without an id, which never ends (the API's
	 *  addHighResolutionRegion). Paper policy: a switch. */
	void addFixedRegion(const mrpt::math::TBoundingBox& box, std::size_t insertionIndex);
	/** Region policy: region `regionId` (not 0) is placed at this box (world
	 *  frame). Follow: the region moves to the box. Persist: the box joins the
	 *  region. Paper policy: a switch. */
	void placeRegion(std::uint32_t regionId, const mrpt::math::TBoundingBox& box, RegionLifetime lifetime,
		std::size_t insertionIndex);
	/** Removes the region; false if there is none with that id. */
	bool endRegion(std::uint32_t regionId);
	/** Called before integrating insertion `index`: the forced switch of the
	 *  paper's ratio experiment, at insertion `switchAtInsertion` or at
	 *  `switchAtFraction` of `expectedFrames` (-1: not forced). */
	void beforeIntegration(
		std::size_t index, std::int64_t switchAtInsertion, double switchAtFraction, std::size_t expectedFrames);

	/** Paper: switched. Region: a region exists. */
	bool hasSwitched() const;
	std::optional<std::size_t> switchIndex() const { return m_switchIndex; }
	const std::vector<THighResolutionRegion>& regions() const { return m_regions; }
	/** Every box of every region and the low voxels they cover, for the
	 *  integrator (brings the covered voxels up to date first). */
	const RegionBoxes& boxes();
	bool inHighResolutionSpace(const mrpt::math::TPoint3D& p) const;

	/** What the high-resolution space gained and lost since the last call. */
	SpaceChange takeSpaceChange();

	/** What the map's owner keeps with each region in the stream, after its
	 *  id (CDualOctoMap::RegionRecord); nothing when empty. */
	using RegionRecord = std::function<void(mrpt::serialization::CArchive&, std::uint32_t regionId)>;
	void serializeTo(mrpt::serialization::CArchive& out, const RegionRecord& record = {}) const;
	void serializeFrom(mrpt::serialization::CArchive& in, const RegionRecord& record = {});

   private:
	void markSwitched(std::size_t insertionIndex);
	/** After the regions changed: rebuilds the boxes, and marks the covered
	 *  voxels for a rebuild (once for all the changes of a frame). */
	void regionsChanged();
	/** Rebuilds the covered voxels if the regions changed since. */
	void updateCovered();
	/** The covered voxels, up to date, as sorted packed keys. */
	std::vector<std::uint64_t> coveredInKeyOrder();
	mrpt::math::TBoundingBox alignedToGrid(const mrpt::math::TBoundingBox& b) const;
	void requireValid(const mrpt::math::TBoundingBox& box) const;

	SwitchPolicy m_policy;
	double m_lowResolution;
	std::optional<std::size_t> m_switchIndex;
	std::vector<THighResolutionRegion> m_regions;
	/** m_space.covered is rebuilt lazily: stale while m_coveredStale. */
	RegionBoxes m_space;
	/** The low keys the trees hold as high-resolution space (sorted); they
	 *  hold m_space's while m_treesCaughtUp. */
	std::vector<std::uint64_t> m_coveredApplied;
	bool m_coveredStale = false, m_treesCaughtUp = true;
};
}  // namespace avm::detail
