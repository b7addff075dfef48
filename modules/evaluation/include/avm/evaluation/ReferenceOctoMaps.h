// The yardstick of the adaptive map: two plain single-resolution OctoMaps (one
// at the high, one at the low resolution) built by octomap itself,
// insertPointCloud(discretize = true), from the same frames and poses in the
// same run. Against them the adaptive map's size, detail and speed are
// measured: memory and .bt bytes against the single high-resolution map of
// all pixels, occupied voxels inside the person regions against it and against
// a third map, the single high-resolution one that treats the pixels the
// adaptive map took as free-only (moving persons) the same way (IoU), outside
// them against the single low-resolution map.
#pragma once

#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/math/TBoundingBox.h>
#include <mrpt/poses/CPose3D.h>

#include <algorithm>
#include <cstddef>
#include <memory>
#include <vector>

namespace octomap
{
class OcTree;
}

namespace avm
{
class CAdaptiveOctoMap;
}

namespace avm::evaluation
{
struct TReferenceComparison
{
	struct Tree
	{
		double resolution = 0;
		std::size_t occupiedLeaves = 0, memoryBytes = 0, binaryBytes = 0;
		double meanInsertMs = 0;  //!< octomap's insertion CPU time per frame (its thread)
	};
	Tree high, low;                                                //!< the single-resolution maps
	std::size_t adaptiveMemoryBytes = 0, adaptiveBinaryBytes = 0;  //!< both trees
	/** Occupied finest voxels inside the active regions: the adaptive map's
	 *  high tree against the single high-resolution map of all pixels. */
	std::size_t insideAdaptive = 0, insideReference = 0;
	double insideIoU = 0;  //!< 1 when neither has any
	/** The same against the single high-resolution map whose free-only pixels
	 *  (those the adaptive map took as free-only) carve free space but are no
	 *  endpoints: the fair measure of the detail kept where persons move. */
	std::size_t insideFreeOnlyReference = 0;
	double insideFreeOnlyIoU = 0;
	/** Occupied low voxels outside all regions: the adaptive map's low tree
	 *  against the single low-resolution map. */
	std::size_t outsideAdaptive = 0, outsideReference = 0;
	double outsideIoU = 0;

	/** `bytes` as a share of the single high-resolution map's memory, and of
	 *  its .bt file: the measure of what a map (the adaptive one, the single
	 *  low-resolution one) saves. */
	double memoryShare(std::size_t bytes) const { return double(bytes) / double(high.memoryBytes); }
	double binaryShare(std::size_t bytes) const { return double(bytes) / double(high.binaryBytes); }
	/** How many times octomap's high-resolution insertion a frame takes a map
	 *  stage of `mapCpuMs` [ms] a frame. */
	double speedup(double mapCpuMs) const { return high.meanInsertMs / std::max(mapCpuMs, 1e-9); }
};

class ReferenceOctoMaps
{
   public:
	/** Resolutions and ranges as the adaptive map's trees. */
	ReferenceOctoMaps(double highResolution, double lowResolution, double highMaxRange, double lowMaxRange);
	~ReferenceOctoMaps();
	ReferenceOctoMaps(const ReferenceOctoMaps&) = delete;
	ReferenceOctoMaps& operator=(const ReferenceOctoMaps&) = delete;

	/** The scan's depth image, unprojected as MRPT does, into the maps (rays
	 *  from the sensor at robotPose + obs.sensorPose). `freeOnlyBoxes` are the
	 *  ones the adaptive map used for this image
	 *  (CAdaptiveOctoMap::lastFreeOnlyBoxes()): in the free-only map a point
	 *  in one of them (bounds included) carves free space up to its voxel and
	 *  marks nothing occupied; the all-pixels maps take every point. */
	void insert(const mrpt::obs::CObservation3DRangeScan& obs, const mrpt::poses::CPose3D& robotPose,
		const std::vector<mrpt::math::TBoundingBox>& freeOnlyBoxes);
	/** Empty maps and timings, as constructed: for a map made again. */
	void clear();

	TReferenceComparison compare(const CAdaptiveOctoMap& adaptive) const;

   private:
	std::unique_ptr<octomap::OcTree> m_high, m_low, m_highFreeOnly;
	double m_highMaxRange, m_lowMaxRange;
	double m_highMs = 0, m_lowMs = 0;
	std::size_t m_frames = 0;
};
}  // namespace avm::evaluation
