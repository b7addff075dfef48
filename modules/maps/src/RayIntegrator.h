// Scan -> per-tree free/occupied key sets -> octree updates: the insertion hot
// path. Endpoints are discretized and deduplicated per voxel before any ray
// is cast (as octomap's insertPointCloud with discretize=true), every ray is
// cast once, and the part of a ray inside a high-resolution region updates the
// high tree while the rest updates the low tree.
#pragma once

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/math/TPoint3D.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>
#include <octomap/OcTree.h>

#include <vector>

#include "BatchUpdate.h"
#include "avm/io/PixelRect.h"
#include "KeySet.h"
#include "ResolutionPolicy.h"
#include "SurfaceSketch.h"

namespace avm::detail
{
/** Where one scan goes. */
struct ScanTargets
{
	/** Space outside every region: the low tree, or the high tree once the
	 *  paper policy has switched. */
	octomap::OcTree* outside = nullptr;
	double outsideMaxRange = 0;
	/** Algorithm 2: an endpoint voxel is dropped when this tree has a node at
	 *  its centre (paper policy after the switch: the low tree). */
	const octomap::OcTree* overlapFilter = nullptr;
	/** Space inside `regions` (region policy): the high tree. */
	octomap::OcTree* inside = nullptr;
	double insideMaxRange = 0;
	const RegionBoxes* regions = nullptr;
	/** Region policy: takes the high voxels of the endpoints that land in
	 *  low-tree space (within its range), at `sketchResolution`. */
	SurfaceSketch* sketch = nullptr;
	double sketchResolution = 0;
};

/** One scan's endpoint voxels: where the two front-ends, a cloud's points
 *  (addPoint) and a depth image's rows (scanRows), meet before any ray is
 *  cast. */
struct EndpointSets
{
	/** Endpoint voxels outside the regions (outside grid) and inside them
	 *  (inside grid); for rays that cross a region without ending in one,
	 *  the inside voxel where they leave it (point clouds: the inside voxel
	 *  of the endpoint). */
	KeySet outside, inside, crossing;
	/** Endpoint voxels of free-only pixels: outside regions and inside them. */
	KeySet freeOnlyOutside, freeOnlyInside;
	/** High voxels of the endpoints in low-tree space, for the sketch. */
	KeySet sketch;

	void clear()
	{
		for (auto* s : {&outside, &inside, &crossing, &freeOnlyOutside, &freeOnlyInside, &sketch}) s->clear();
	}
	/** Adds the keys of `other`, set by set. */
	void merge(const EndpointSets& other)
	{
		for (const auto k : other.outside.keys()) outside.insert(k);
		for (const auto k : other.inside.keys()) inside.insert(k);
		for (const auto k : other.crossing.keys()) crossing.insert(k);
		for (const auto k : other.sketch.keys()) sketch.insert(k);
		for (const auto k : other.freeOnlyOutside.keys()) freeOnlyOutside.insert(k);
		for (const auto k : other.freeOnlyInside.keys()) freeOnlyInside.insert(k);
	}
};

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
	void setThreads(unsigned threads) { m_threads = threads < 1 ? 1 : threads; }

   private:
	enum class Endpoint
	{
		None,
		Outside,
		Inside
	};
	struct Grid
	{
		double resolution = 0, inverse = 0;
		void set(double res)
		{
			resolution = res;
			inverse = 1.0 / res;
		}
	};

	/** Per-frame constants of the depth-image pass. */
	struct RowSetup
	{
		const mrpt::math::CMatrix_u16* image = nullptr;
		int cols = 0;
		double cy = 0, fy = 0;
		mrpt::math::CMatrixDouble33 R;
		float unitsF = 0;
		const float* colFactor = nullptr;
		const float* rangeToDepth = nullptr;  //!< per pixel, range images only
		const std::vector<Region>* regions = nullptr;
		/** The free-only test's unprojection, in doubles. */
		const double* colFactorDouble = nullptr;
		bool rangeIsDepth = true;
		const std::vector<mrpt::math::TBoundingBox>* freeOnlyBoxes = nullptr;
	};
	/** One band of rows' endpoint sets and scratch rows. */
	struct PixelBand
	{
		/** The scan's sets (first band) or `own`, merged after the join. */
		EndpointSets* ends = nullptr;
		EndpointSets own;
		std::vector<int> keys;
		std::vector<float> near;
		std::vector<std::uint8_t> flags;
		/** The free-only test's candidates (pixels with depth in a box's
		 *  rectangle), its answer, and the row's points in doubles. */
		std::vector<std::uint8_t> candidate, freeOnly;
		std::vector<double> points;
	};
	void scanRows(const RowSetup& rs, int v0, int v1, PixelBand& band) const;
	/** Sets band.freeOnly over the columns [from, to) of row v that it
	 *  returns (empty: none): the pixels whose points lie in a free-only box. */
	std::pair<int, int> markFreeOnlyPixels(const RowSetup& rs, int v, PixelBand& band) const;
	/** scanRows over all rows, in one band per thread. */
	void scanBands(const RowSetup& rs, int rows);

	void begin(const mrpt::math::TPoint3D& origin, const ScanTargets& targets);
	/** A point of a cloud: its endpoint voxel in the set it belongs to. */
	void addPoint(double x, double y, double z);
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
	bool insideAnyRegion(double x, double y, double z) const;
	template <typename Set>
	void applyUpdates(
		octomap::OcTree& tree, const Grid& grid, const Set& freeKeys, const Set& occupiedKeys, bool keepInsideRegions);

	ScanTargets m_targets;
	mrpt::math::TPoint3D m_origin;
	/** end - origin of the ray being cast. */
	mrpt::math::TPoint3D m_rayDir;
	Grid m_outsideGrid, m_insideGrid, m_sketchGrid;
	bool m_hasRegions = false;
	EndpointSets m_ends;
	/** The outside grid's voxels of m_ends.inside. */
	KeySet m_insideEndsOutsideGrid;
	KeySet m_outsideFree, m_outsideOccupied;
	BoxKeySet m_insideFree, m_insideOccupied;
	std::uint64_t m_lastOutsideKey = 0, m_lastInsideKey = 0, m_lastCrossingKey = 0;
	BatchUpdate m_batch;
	std::vector<std::pair<double, double>> m_intervals;
	std::vector<float> m_columnFactor;
	std::vector<double> m_columnFactorDouble;
	std::vector<float> m_rangeToDepth;
	unsigned m_threads = 1;
	std::vector<PixelBand> m_bands;
	std::vector<io::PixelRect> m_regionRects;
	/** The free-only boxes in view and their rectangles in the image. */
	std::vector<mrpt::math::TBoundingBox> m_freeOnlyBoxes;
	std::vector<io::PixelRect> m_freeOnlyRects;
};
}  // namespace avm::detail
