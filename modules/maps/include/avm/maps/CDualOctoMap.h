// avm::CDualOctoMap — the dual octree: a low-resolution OctoMap for the scene and
// a high-resolution one for regions of space (Choi & Shin 2025, Algorithm 1
// resolution switching and Algorithm 2 overlap filtering), as an MRPT metric
// map. It knows regions, not people: the layer above adds, moves and ends them
// (placeRegions, endRegion) and inserts points; avm::CAdaptiveOctoMap
// (modules/plugin) is that layer for persons and the registered MRPT map.
//
// Where things live: src/ResolutionPolicy.cpp decides which space goes to
// which tree (Algorithm 1 and the regions; when a region ends is the layer
// above's call),
// src/RegionSpace.cpp refines space that enters a region and coarsens space
// that leaves one, src/EndpointProjector.cpp turns a scan into endpoint
// records and src/RayIntegrator.cpp those into per-tree free/occupied key
// sets (the hot path, and Algorithm 2),
// src/BatchUpdate.cpp applies them to a tree in one sweep,
// src/CDualOctoMap_{options,query,likelihood,io,render}.cpp the rest
// (doc/map.md has the full map of files).
#pragma once

#include <mrpt/maps/CMetricMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/math/TBoundingBox.h>
#include <mrpt/math/TPoint3D.h>
#include <mrpt/obs/CObservation3DRangeScan.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "avm/io/IniKeyOptions.h"
#include "avm/maps/MapTypes.h"
#include "avm/maps/VisibleLeaves.h"

namespace octomap
{
class OcTree;
}

namespace avm
{
namespace detail
{
class ResolutionPolicy;
class RayIntegrator;
class SurfaceSketch;
struct ScanTargets;
}  // namespace detail

/** The answer to CDualOctoMap::query(). */
struct TOccupancyQuery
{
	OccupancyState state = OccupancyState::Unknown;
	/** Occupancy probability (0.5 when unknown). */
	double probability = 0.5;
	/** The tree responsible for this point (the one that answered, or the one
	 *  that would map it when it is unknown). */
	Resolution tree = Resolution::Low;
	/** Voxel edge of that tree [m]. */
	double resolution = 0;
};

class CDualOctoMap : public mrpt::maps::CMetricMap
{
   public:
	/** The parameters of one octree (avm/maps/MapTypes.h). */
	using TTreeOptions = avm::TTreeOptions;

	/** Section `<prefix>_creationOpts`: the two trees. */
	struct TCreationOptions : public io::CIniKeyOptions<TCreationOptions>
	{
		TTreeOptions low{"low_", 0.20};
		TTreeOptions high{"high_", 0.05};

		/** Both trees' keys, and the checks that high.resolution is finer than
		 *  low.resolution and divides it exactly (so no high voxel straddles a
		 *  low one). */
		io::IniKeys<TCreationOptions> iniKeys() const;
	};

	/** Section `<prefix>_insertOpts`: switching policy and the forced switch. */
	struct TInsertionOptions : public io::CIniKeyOptions<TInsertionOptions>
	{
		SwitchPolicy switchPolicy = SwitchPolicy::Region;
		RegionLifetime regionLifetime = RegionLifetime::Follow;
		/** paper policy: switch at this insertion index (-1 = off); ini key
		 *  `switch_at_insertion` (formerly `switch_at_frame`: an insertion is
		 *  a frame in avm-map, but not every frame is inserted). */
		std::int64_t switchAtInsertion = -1;
		/** paper policy: switch at this fraction of the run (-1 = off); needs
		 *  expectedFrameCount or setExpectedFrameCount(). */
		double switchAtFraction = -1;
		/** Frames in the run, for switchAtFraction (0 = unknown). */
		std::uint64_t expectedFrameCount = 0;
		/** Threads for unprojecting and keying a depth image (bands of rows);
		 *  ray casting and tree updates stay on the inserting thread. */
		std::uint32_t insertionThreads = 1;

		static io::IniKeys<TInsertionOptions> iniKeys();
	};

	/** Section `<prefix>_likelihoodOpts`. */
	struct TLikelihoodOptions : public io::CIniKeyOptions<TLikelihoodOptions>
	{
		/** Use one pixel in `decimation` along rows and columns. */
		std::uint32_t decimation = 8;

		static io::IniKeys<TLikelihoodOptions> iniKeys();
	};

	/** Section `<prefix>_renderOpts`: what getVisualizationInto() draws. */
	struct TRenderingOptions : public io::CIniKeyOptions<TRenderingOptions>
	{
		bool showFreeSpace = false;
		bool showRegions = true;

		static io::IniKeys<TRenderingOptions> iniKeys();
	};

	/** Size figures of one tree, for the paper's comparison. Leaf counts are
	 *  over the leaves of the (pruned) tree, as octomap's leaf iterator sees
	 *  them: a pruned leaf counts once whatever its size; only leaves that the
	 *  map shows (see forEachLeaf) are counted. */
	struct TTreeStats
	{
		double resolution = 0;
		std::size_t occupiedLeaves = 0, freeLeaves = 0;
		std::size_t memoryBytes = 0;  //!< octomap's memoryUsage() (low tree: plus its surface sketch)
		std::size_t binaryBytes = 0;  //!< size of the .bt file
	};

	struct TRayHit
	{
		mrpt::math::TPoint3D point;  //!< centre of the occupied voxel hit
		Resolution tree = Resolution::Low;
		double resolution = 0;
	};

	~CDualOctoMap() override;

	/** The tree parameters; fixed for the map's life (clear() keeps them). */
	const TCreationOptions& creationOptions() const { return m_creation; }
	TInsertionOptions insertionOptions;
	TLikelihoodOptions likelihoodOptions;
	TRenderingOptions renderingOptions;

	/** @name Switching (Algorithm 1)
	 * @{ */
	/** Region policy: from now on, the box (world frame, used as given, then
	 *  grown to the low tree's voxel grid) is mapped in the high tree, for the
	 *  map's life; what the low tree knew there moves into the high tree.
	 *  Paper policy: the call switches like switchToHighResolution().
	 *  Throws std::invalid_argument on an empty or non-finite box. */
	void addHighResolutionRegion(const mrpt::math::TBoundingBox& worldBox);
	/** Region policy: each region moves to its placement's box (world frame,
	 *  grown to the low tree's voxel grid) or, for a new id, is made there.
	 *  Persist lifetime: the box joins the region. Paper policy: switches.
	 *  Placed together, so space one region leaves and another enters in the
	 *  same call stays in the high tree. */
	void placeRegions(const std::vector<TRegionPlacement>& placements);
	/** Ends the region now (its detail folded into the low tree): the layer
	 *  above decides when, e.g. its follow lifetime is over or its person has
	 *  been attended to. False if there is no region of that id. */
	bool endRegion(std::uint32_t id);
	/** Paper policy: every later insertion goes to the high tree (filtered by
	 *  Algorithm 2). Region policy: std::logic_error (a region is needed). */
	void switchToHighResolution();
	/** Whether the high tree takes data: paper policy, since the switch;
	 *  region policy, while a region exists. */
	bool hasSwitched() const;
	/** The active regions (region policy), in order of creation. */
	const std::vector<THighResolutionRegion>& highResolutionRegions() const;
	/** Index (0-based, among successful insertions) of the first insertion
	 *  that used the high tree. */
	std::optional<std::size_t> switchInsertionIndex() const;
	/** Frames in the run, for `switch_at_fraction`. */
	void setExpectedFrameCount(std::size_t frames);
	/** Inserts points already in the world frame, rays cast from
	 *  `sensorOrigin` (a points map with a sensor origin). False if empty. */
	bool insertPointCloud(const mrpt::maps::CPointsMap& worldPoints, const mrpt::math::TPoint3D& sensorOrigin);
	/** Successful insertions so far. */
	std::size_t insertionCount() const;
	/** @} */

	/** @name Queries over both trees
	 * @{ */
	TOccupancyQuery query(const mrpt::math::TPoint3D& p) const;
	/** First occupied voxel along the ray (direction need not be unit), up to
	 *  maxRange [m]; unknown space is passed through. Marches in steps of half
	 *  the finest resolution. */
	std::optional<TRayHit> castRay(
		const mrpt::math::TPoint3D& origin, const mrpt::math::TPoint3D& direction, double maxRange) const;
	/** Box of all known (free or occupied) visible voxels; nothing when empty. */
	std::optional<mrpt::math::TBoundingBox> knownSpaceBoundingBox() const;
	/** Whether the camera of `scan`, at `sensorPose` (world), looks at the box:
	 *  its centre projects into the image within the low tree's max range
	 *  (occlusion is not considered). */
	bool inCameraView(const mrpt::math::TBoundingBox& box, const mrpt::obs::CObservation3DRangeScan& scan,
		const mrpt::poses::CPose3D& sensorPose) const;
	/** Calls `visit` for every leaf of `tree` that the map shows: in region
	 *  policy all leaves (the low tree holds no region space); in paper policy
	 *  the high tree's leaves where the low tree has no node (Algorithm 2). */
	void forEachLeaf(Resolution tree, const std::function<void(const TLeafVoxel&)>& visit) const;
	TTreeStats lowResolutionStats() const;
	/** All zeros except the resolution while the high tree does not exist. */
	TTreeStats highResolutionStats() const;
	/** Bytes of this map serialized by MRPT. */
	std::size_t serializedBytes() const;
	/** @} */

	/** Read-only access to a tree (nullptr: the high tree is not created yet). */
	const octomap::OcTree* tree(Resolution which) const;

	/** @name CMetricMap
	 * @{ */
	bool isEmpty() const override;
	/** Writes prefix_low.bt, prefix_high.bt (empty tree if not created) and
	 *  prefix.3Dscene, each atomically. */
	void saveMetricMapRepresentationToFile(const std::string& prefix) const override;
	void getVisualizationInto(mrpt::opengl::CSetOfObjects& outObj) const override;
	/** Centres of the occupied visible voxels of both trees. */
	const mrpt::maps::CSimplePointsMap* getAsSimplePointsMap() const override;
	/** Fraction of the other map's points (moved by otherMapPose) that fall in
	 *  occupied voxels of this map. */
	float compute3DMatchingRatio(const mrpt::maps::CMetricMap* otherMap, const mrpt::poses::CPose3D& otherMapPose,
		const mrpt::maps::TMatchingRatioParams& params) const override;
	std::string asString() const override;
	/** @} */

   protected:
	/** Throws std::invalid_argument (naming the key) on invalid options. */
	CDualOctoMap(
		const TCreationOptions& creation, const TInsertionOptions& insertion, const TLikelihoodOptions& likelihood);
	CDualOctoMap(const CDualOctoMap& other);
	CDualOctoMap& operator=(const CDualOctoMap& other);

	/** Boxes in the world frame: a depth pixel whose point lies in one of
	 *  them (bounds included) is free-only. */
	using FreeOnlyBoxes = std::vector<mrpt::math::TBoundingBox>;
	/** Whether insertObservation maps `scan` as a depth image (it has one,
	 *  with a camera), loading an externally stored one: the images
	 *  beforeDepthImage is called with. */
	static bool insertsAsDepthImage(const mrpt::obs::CObservation3DRangeScan& scan);
	/** Called with each depth image about to be inserted (after its checks,
	 *  before rays are cast): where the layer above reads it, e.g. places the
	 *  regions the image shows and ends those it is done with. Returns the image's
	 *  free-only boxes: the rays of the pixels whose points lie in them carve
	 *  free space as any other, but their endpoints are not marked occupied
	 *  (something there is passing through); the map does not ask what they
	 *  are. */
	virtual FreeOnlyBoxes beforeDepthImage(
		const mrpt::obs::CObservation3DRangeScan& /*scan*/, const mrpt::poses::CPose3D& /*robotPose*/)
	{
		return {};
	}
	/** The label getVisualizationInto() draws above region `regionId` (not 0). */
	virtual std::string regionLabel(std::uint32_t regionId) const { return "region " + std::to_string(regionId); }

	/** @name The map's parts of a serialized stream
	 *  CAdaptiveOctoMap's stream (version 1) holds the person layer's options
	 *  and tracks between them, so the map writes and reads itself in parts.
	 * @{ */
	/** Both trees' creation options. */
	void writeTreeOptions(mrpt::serialization::CArchive& out) const;
	void readTreeOptions(mrpt::serialization::CArchive& in);
	/** What the layer above keeps with each region in the stream, after its
	 *  id (the plugin: the region's follow-lifetime clock); written and read
	 *  the same way. */
	using RegionRecord = std::function<void(mrpt::serialization::CArchive&, std::uint32_t regionId)>;
	/** The insertion count, the switch and the regions (read after
	 *  insertionOptions.switchPolicy). */
	void writeRegions(mrpt::serialization::CArchive& out, const RegionRecord& record) const;
	void readRegions(mrpt::serialization::CArchive& in, const RegionRecord& record);
	/** The surface sketch. */
	void writeSketch(mrpt::serialization::CArchive& out) const;
	void readSketch(mrpt::serialization::CArchive& in);
	/** Both trees. */
	void writeTrees(mrpt::serialization::CArchive& out) const;
	void readTrees(mrpt::serialization::CArchive& in);
	/** @} */

	void internal_clear() override;
	bool internal_insertObservation(
		const mrpt::obs::CObservation& obs, const std::optional<const mrpt::poses::CPose3D>& robotPose) override;
	double internal_computeObservationLikelihood(
		const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const override;
	bool internal_canComputeObservationLikelihood(const mrpt::obs::CObservation& obs) const override;

   private:
	octomap::OcTree& ensureHighTree();
	/** Forced switch, expiry and region changes for the coming insertion;
	 *  returns where its scan goes. */
	detail::ScanTargets prepareInsertion();
	void finishInsertion();
	/** Applies the region changes the policy reports to the trees. */
	void applyRegionChanges();
	TTreeStats statsOf(Resolution which) const;
	/** The options and a deep copy of the trees, regions and sketch. */
	void copyFrom(const CDualOctoMap& other);

	TCreationOptions m_creation;
	std::unique_ptr<octomap::OcTree> m_low, m_high;
	std::unique_ptr<detail::ResolutionPolicy> m_policy;
	/** Where in each low voxel the surface was (region policy). */
	std::unique_ptr<detail::SurfaceSketch> m_sketch;
	/** Scratch buffers of the insertion hot path; not part of the map state. */
	std::unique_ptr<detail::RayIntegrator> m_integrator;
	std::size_t m_insertions = 0;
	mutable mrpt::maps::CSimplePointsMap m_pointsCache;
	mutable bool m_pointsCacheValid = false;
};
}  // namespace avm
