// Any observation -> its endpoint records (EndpointSets): a cloud point by
// point (addPoint), a depth image row by row through the row kernels
// (addDepthImage). The two front-ends meet in the records, before any ray is
// cast (RayIntegrator). Endpoints are discretized and deduplicated per voxel
// there, as octomap's insertPointCloud with discretize=true.
//
// Each front-end classifies its endpoints against the regions with its own
// function: classifyPoint (a cloud, a point at a time, in doubles) and
// classifyRow (a depth row, in floats, vectorized). Both put an endpoint in a
// region when it lies in a box (the row along its ray in floats, so a point
// within rounding of a face may fall the other way), but they record a ray
// that crosses a region and ends beyond it differently. A cloud records its
// point's inside voxel, so the crossing ray keeps the point's direction; a
// depth row records the voxel where the ray leaves the farthest region it
// crosses, so that the thousands of pixels behind a region share a few
// crossing rays, at the price of directions rounded to that voxel's centre.
// The row's record is the faster, not the more exact one, so clouds keep
// theirs.
#pragma once

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/math/TBoundingBox.h>
#include <mrpt/math/TPoint3D.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

#include "avm/io/DepthCamera.h"
#include "avm/io/PixelRect.h"
#include "KeySet.h"
#include "ResolutionPolicy.h"
#include "RowKernels.h"
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
	/** High voxels of the endpoints in low-tree space, for the sketch: only
	 *  those in the box given to clear(). */
	BoxKeySet sketch;

	/** Empties the sets; the sketch then takes the keys in `sketchBox`. */
	void clear(const KeyRange& sketchBox)
	{
		for (auto* s : {&outside, &inside, &crossing, &freeOnlyOutside, &freeOnlyInside}) s->clear();
		sketch.reset(sketchBox.first(), sketchBox.last());
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

/** A key grid: its voxel edge and that edge's inverse. */
struct KeyGrid
{
	double resolution = 0, inverse = 0;
	void set(double res)
	{
		resolution = res;
		inverse = 1.0 / res;
	}
};

/** Parameter interval [t0, t1] within [0, 1] where o + t d lies in the box
 *  (slab method); false if none. */
inline bool clipToBox(const mrpt::math::TPoint3D& o, const mrpt::math::TPoint3D& d, const mrpt::math::TBoundingBox& b,
	double& t0, double& t1)
{
	t0 = 0;
	t1 = 1;
	for (int i = 0; i < 3; i++)
	{
		if (std::abs(d[i]) < 1e-12)
		{
			if (o[i] < b.min[i] || o[i] >= b.max[i]) return false;
			continue;
		}
		const double inv = 1.0 / d[i];
		double ta = (b.min[i] - o[i]) * inv, tb = (b.max[i] - o[i]) * inv;
		if (ta > tb) std::swap(ta, tb);
		t0 = std::max(t0, ta);
		t1 = std::min(t1, tb);
		if (t0 >= t1) return false;
	}
	return true;
}

class EndpointProjector
{
   public:
	/** Starts a scan from `origin` at `targets`' grids and regions; its
	 *  records go to `ends`, cleared here. */
	void begin(const mrpt::math::TPoint3D& origin, const ScanTargets& targets, EndpointSets& ends);
	/** The points of a cloud in the world frame. */
	void addWorldPoints(const float* xs, const float* ys, const float* zs, std::size_t n);
	/** The points of a cloud in the sensor frame, placed by `sensorPose`. */
	void addSensorPoints(
		const float* xs, const float* ys, const float* zs, std::size_t n, const mrpt::poses::CPose3D& sensorPose);
	/** Every pixel of a depth image seen from `sensorPose`, unprojected
	 *  from the image itself (no points3D needed). The pixels whose points
	 *  lie in one of `freeOnlyBoxes` (world frame, bounds included) are
	 *  recorded free-only: their rays carve free space, their endpoints are
	 *  not marked occupied. */
	void addDepthImage(const mrpt::obs::CObservation3DRangeScan& obs, const mrpt::poses::CPose3D& sensorPose,
		const io::DepthCamera& camera, const std::vector<mrpt::math::TBoundingBox>& freeOnlyBoxes);

	/** Threads for the depth image (row bands). */
	void setThreads(unsigned threads) { m_threads = threads < 1 ? 1 : threads; }

   private:
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
	/** The depth row's classification (row kernels classifyAgainstBox and
	 *  insideRowKeys) over the columns [from, to) of row v that the regions'
	 *  rectangles cover: a pixel's inside key is its point's when that lies in
	 *  a region, else that of the voxel where its ray leaves the farthest
	 *  region it crosses, else none; a point in a region is no outside
	 *  endpoint (its outsideX becomes -1). */
	void classifyRow(const RowSetup& rs, const rows::RowRays& rays, int v, int from, int to, PixelBand& band,
		rows::RowKeys inside, int* outsideX) const;
	/** Sets band.freeOnly over the columns [from, to) of row v that it
	 *  returns (empty: none): the pixels whose points lie in a free-only box. */
	std::pair<int, int> markFreeOnlyPixels(const RowSetup& rs, int v, PixelBand& band) const;
	/** scanRows over all rows, in one band per thread. */
	void scanBands(const RowSetup& rs, int rows);

	/** A point of a cloud (world frame): its endpoint voxel in the set it
	 *  belongs to. */
	void addPoint(double x, double y, double z);
	enum class PointPlace
	{
		Outside,
		InRegion,
		BeyondRegion
	};
	/** The cloud's classification: the point lies in a region
	 *  (Region::contains, half-open as the voxels), beyond one that its ray
	 *  crosses (clipToBox), or neither. */
	PointPlace classifyPoint(const mrpt::math::TPoint3D& p) const;

	const RegionBoxes* m_regions = nullptr;
	bool m_hasRegions = false, m_hasSketch = false;
	mrpt::math::TPoint3D m_origin;
	KeyGrid m_outsideGrid, m_insideGrid, m_sketchGrid;
	/** The sketch's keys that can matter: RayIntegrator::finish() marks a
	 *  sketch key only within the low tree's max range of the origin (the
	 *  high voxel's centre or its low voxel's), so the keys within that
	 *  range, half a low voxel's diagonal and a low voxel. */
	KeyRange m_sketchBox{};
	EndpointSets* m_ends = nullptr;
	std::uint64_t m_lastOutsideKey = 0, m_lastInsideKey = 0, m_lastCrossingKey = 0;
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
