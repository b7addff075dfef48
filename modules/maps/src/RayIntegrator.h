// Scan -> endpoint records (EndpointProjector) -> per-tree free/occupied key
// sets -> octree updates: the insertion hot path. Every ray is cast once, from
// the records, and the part of a ray inside a high-resolution region updates
// the high tree while the rest updates the low tree.
#pragma once

#include <mrpt/math/TPoint3D.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>
#include <octomap/OcTree.h>

#include <utility>
#include <vector>

#include "BatchUpdate.h"
#include "EndpointProjector.h"
#include "KeySet.h"

namespace avm::detail
{
class RayIntegrator
{
   public:
	/** Unprojects the depth image itself (no points3D needed). The rays of
	 *  the pixels whose points lie in one of `freeOnlyBoxes` (world frame,
	 *  bounds included) carve free space as any other, but their endpoints
	 *  are not marked occupied. */
	void integrateDepthImage(const mrpt::obs::CObservation3DRangeScan& obs, const mrpt::poses::CPose3D& sensorPose,
		const ScanTargets& targets, const std::vector<mrpt::math::TBoundingBox>& freeOnlyBoxes = {});
	/** Points in the world frame, rays from `origin`. */
	void integrateWorldPoints(const float* xs, const float* ys, const float* zs, std::size_t n,
		const mrpt::math::TPoint3D& origin, const ScanTargets& targets);
	/** Points in the sensor frame, placed by `sensorPose`. */
	void integrateSensorPoints(const float* xs, const float* ys, const float* zs, std::size_t n,
		const mrpt::poses::CPose3D& sensorPose, const ScanTargets& targets);

	/** Threads for the depth-image pass (row bands); the rays and updates
	 *  stay on the calling thread. */
	void setThreads(unsigned threads) { m_projector.setThreads(threads); }

   private:
	enum class Endpoint
	{
		None,
		Outside,
		Inside
	};
	void begin(const mrpt::math::TPoint3D& origin, const ScanTargets& targets);
	void finish();
	/** Clears the sketch's bits of the high voxels that this depth image sees
	 *  through. */
	void forgetSketchSeenThrough(const mrpt::obs::CObservation3DRangeScan& obs, const mrpt::poses::CPose3D& sensorPose,
		const io::DepthCamera& camera);
	/** Which part of a ray a cast maps: the part outside the regions (in
	 *  the `outside` tree) or the parts inside them (in the high tree). */
	enum class RayPart
	{
		OutsideRegions,
		InsideRegions
	};
	void castRay(const mrpt::math::TPoint3D& end, std::uint64_t endKey, Endpoint endpoint, RayPart part);
	void castSegment(bool inside, double a, double b, bool extendStart, bool extendEnd, double length);
	/** Frees the keys of `freeKeys` that are no endpoint of the scan (of
	 *  `occupiedKeys` or `freeOnlyEnds`, which joins it), then marks the
	 *  scan's occupied keys occupied; each only where it is `tree`'s space. */
	void applyUpdates(octomap::OcTree& tree, const KeyGrid& grid, const BoxKeySet& freeKeys, BoxKeySet& occupiedKeys,
		const KeySet& freeOnlyEnds, bool keepInsideRegions);

	ScanTargets m_targets;
	mrpt::math::TPoint3D m_origin;
	/** end - origin of the ray being cast. */
	mrpt::math::TPoint3D m_rayDir;
	KeyGrid m_outsideGrid, m_insideGrid, m_sketchGrid;
	bool m_hasRegions = false;
	EndpointProjector m_projector;
	EndpointSets m_ends;
	/** The outside grid's voxels of m_ends.inside. */
	KeySet m_insideEndsOutsideGrid;
	/** The scan's free and occupied keys, outside the regions and inside
	 *  them; the occupied sets also take the free-only endpoints
	 *  (applyUpdates), which may lie beyond their boxes: those only keep
	 *  keys out of the free set, whose keys all lie in the box. */
	BoxKeySet m_outsideFree, m_outsideOccupied;
	BoxKeySet m_insideFree, m_insideOccupied;
	BatchUpdate m_batch;
	std::vector<std::pair<double, double>> m_intervals;
	/** The scan's marks for the sketch (SurfaceSketch::markScan). */
	std::vector<std::uint64_t> m_sketchSurface, m_sketchSeen;
};
}  // namespace avm::detail
