// avm::viewer::MapSnapshot — everything the live view draws, as plain values:
// a copy of what the map shows at one moment (occupied voxels of both trees,
// free voxels when asked, the regions, the person tracks), plus what the
// pipeline knows besides the map (trajectory, camera, colour image with the
// person boxes, the figures of the status line). Taking one reads the map and
// copies; drawing it (MapView) never touches the map, so the map can go on
// being inserted into while a snapshot is drawn.
#pragma once

#include <mrpt/img/CImage.h>
#include <mrpt/img/TColor.h>
#include <mrpt/img/TCamera.h>
#include <mrpt/img/TPixelCoord.h>
#include <mrpt/math/TBoundingBox.h>
#include <mrpt/math/TPoint3D.h>
#include <mrpt/poses/CPose3D.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "avm/persons/PersonColour.h"

namespace octomap
{
class OcTree;
}

namespace avm
{
class CAdaptiveOctoMap;
}

namespace avm::viewer
{
/** One leaf of a tree: its centre and edge. */
struct SnapshotVoxel
{
	mrpt::math::TPoint3Df centre;
	float size = 0;  //!< [m] edge; larger than the resolution for pruned leaves
};

struct SnapshotRegion
{
	std::uint32_t personId = 0;                   //!< 0: a region given through the map's API
	std::vector<mrpt::math::TBoundingBox> boxes;  //!< world frame
};

struct SnapshotPerson
{
	std::uint32_t id = 0;
	mrpt::math::TPoint3D position;  //!< last world position
	std::size_t lastFrame = 0;
	/** Last shape: voxel centres at the high resolution (PersonTrack::shape). */
	std::vector<mrpt::math::TPoint3Df> shape;
	/** The shape's colour: the map's person colour, or a finished run's
	 *  person_shapes.ply's. */
	mrpt::img::TColor shapeColour = persons::kPersonColour;
};

/** A person box in the colour image. */
struct ImageBox
{
	double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  //!< [px]
	std::uint32_t personId = 0;             //!< 0: not (yet) taken for a person
	double score = 0;
};

/** The figures of the status line; what is not known stays empty. */
struct RunStatus
{
	std::optional<std::size_t> frame;  //!< index of the frame last inserted
	std::size_t frames = 0;            //!< frames in the run (0 = unknown)
	double fps = 0;                    //!< frames per second so far (0 = unknown)
	/** Stage and its time for the last frame or its mean [ms], in the order shown. */
	std::vector<std::pair<std::string, double>> stageMs;
	std::optional<std::size_t> switchFrame;  //!< first frame mapped in the high tree
	/** The map's switchInsertionIndex(), shown while the frame is not known:
	 *  not every frame is inserted. */
	std::optional<std::size_t> switchInsertion;
	std::string note;  //!< anything else, shown at the end
};

struct MapSnapshot
{
	/** @name From the map (snapshotOf)
	 * @{ */
	double lowResolution = 0, highResolution = 0;  //!< [m]
	std::vector<SnapshotVoxel> lowOccupied, highOccupied;
	/** Free leaves; empty unless asked for (they outnumber the occupied ones). */
	std::vector<SnapshotVoxel> lowFree, highFree;
	bool hasFreeSpace = false;  //!< the free leaves were taken
	std::vector<SnapshotRegion> regions;
	std::vector<SnapshotPerson> persons;
	std::size_t mapMemoryBytes = 0;  //!< octomap's memoryUsage() of both trees
	/** @} */

	/** @name From the pipeline (or a finished run's files)
	 * @{ */
	std::vector<mrpt::poses::CPose3D> trajectory;  //!< camera optical frame in the world
	std::optional<mrpt::poses::CPose3D> camera;    //!< the current camera, drawn as a frustum
	std::optional<mrpt::img::TCamera> intrinsics;  //!< of the colour camera, for the frustum
	mrpt::img::CImage image;                       //!< the current colour image (empty: no image window)
	std::vector<ImageBox> imageBoxes;
	std::vector<mrpt::img::TPixelCoordf> features;        //!< odometry features used
	std::vector<mrpt::img::TPixelCoordf> maskedFeatures;  //!< odometry features dropped by a person mask
	RunStatus status;
	/** @} */
};

/** What snapshotOf() copies. */
struct SnapshotOptions
{
	bool freeSpace = false;  //!< also the free leaves
};

/** The map as it shows itself now: CAdaptiveOctoMap::forEachLeaf() of both
 *  trees (so paper policy's overlap filter applies), highResolutionRegions(),
 *  confirmedPersons(), the trees' memoryUsage(), and switchInsertionIndex() (an
 *  insertion, not a frame: the caller that knows the frame sets switchFrame). The caller must keep the map from being modified meanwhile. */
MapSnapshot snapshotOf(const CAdaptiveOctoMap& map, const SnapshotOptions& options = {});

/** The same from two octrees as written to map_low.bt / map_high.bt (high may
 *  be null): a high leaf shows where the low tree has no node, the map's own
 *  rule (Algorithm 2; in region policy the low tree holds no region space). */
MapSnapshot snapshotOfTrees(
	const octomap::OcTree& low, const octomap::OcTree* high, const SnapshotOptions& options = {});

/** A finished avm-map run in `outDir`: map_low.bt (required), map_high.bt,
 *  trajectory.txt, persons.csv with the persons' last shapes of
 *  person_shapes.ply, and the regions and switch frame of stats.json,
 *  each when present. Throws std::runtime_error naming the file on a missing
 *  map_low.bt or on any file it cannot read. */
MapSnapshot snapshotOfRun(const std::filesystem::path& outDir, const SnapshotOptions& options = {});

/** The status line: frame, fps, stage times, switch frame, persons, memory. */
std::string statusLine(const MapSnapshot& s);
/** The same in two parts: frame, fps and stage times; the rest. */
std::array<std::string, 2> statusLines(const MapSnapshot& s);
}  // namespace avm::viewer
