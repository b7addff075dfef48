// Algorithm 1 (resolution switching) and its region variant: which space the
// high-resolution tree maps, and when that changed. Knows nothing of octrees;
// CAdaptiveOctoMap applies the changes it reports to the trees.
#pragma once

#include <mrpt/math/TBoundingBox.h>
#include <mrpt/math/TPoint3D.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>

#include <cstddef>
#include <optional>
#include <vector>

#include "avm/maps/CAdaptiveOctoMap.h"

namespace avm::detail
{
struct Region
{
	/** World frame, aligned to the low tree's voxel grid. */
	mrpt::math::TBoundingBox box;
	/** Insertion index of the last trigger that created or refreshed it. */
	std::size_t refreshedAt = 0;

	/** Half-open on the max side, as octree voxels are. */
	bool contains(double x, double y, double z) const
	{
		return x >= box.min.x && x < box.max.x && y >= box.min.y && y < box.max.y && z >= box.min.z &&
			   z < box.max.z;
	}
};

class ResolutionPolicy
{
   public:
	ResolutionPolicy(SwitchPolicy policy, double lowResolution);

	SwitchPolicy policy() const { return m_policy; }

	/** Paper policy: switch to the high tree (later triggers change nothing).
	 *  Region policy: std::logic_error. */
	void trigger(std::size_t insertionIndex);
	/** Region policy: the box, grown to the low grid, becomes (or merges into)
	 *  an active region. Paper policy: a trigger. */
	void addRegion(const mrpt::math::TBoundingBox& box, std::size_t insertionIndex);
	/** Called before integrating insertion `index`: the forced switch of the
	 *  paper's ratio experiment and the expiry of regions. */
	void beforeIntegration(
		std::size_t index, const CAdaptiveOctoMap::TInsertionOptions& opts, std::size_t expectedFrames);

	/** Paper: switched. Region: a region exists. */
	bool highActive() const;
	std::optional<std::size_t> switchIndex() const { return m_switchIndex; }
	const std::vector<Region>& regions() const { return m_regions; }
	const Region* regionContaining(const mrpt::math::TPoint3D& p) const;

	/** Regions created or grown since the last call (their low space must be
	 *  emptied), and regions expired (their high space must be emptied). */
	std::vector<mrpt::math::TBoundingBox> takeGrownRegions();
	std::vector<mrpt::math::TBoundingBox> takeExpiredRegions();

	void serializeTo(mrpt::serialization::CArchive& out) const;
	void serializeFrom(mrpt::serialization::CArchive& in);

   private:
	void markSwitched(std::size_t insertionIndex);

	SwitchPolicy m_policy;
	double m_lowResolution;
	std::optional<std::size_t> m_switchIndex;
	std::vector<Region> m_regions;
	std::vector<mrpt::math::TBoundingBox> m_grown, m_expired;
};

/** Boxes (world frame, margin included) around the pixels of `obs` labelled
 *  `opts.personLabel`, one per 4-connected blob of labelled pixels. */
std::vector<mrpt::math::TBoundingBox> regionsFromPixelLabels(
	const mrpt::obs::CObservation3DRangeScan& obs, const mrpt::poses::CPose3D& sensorPoseInWorld,
	const CAdaptiveOctoMap::TInsertionOptions& opts);
}  // namespace avm::detail
