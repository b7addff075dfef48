// The adaptive map's vocabulary: the two trees (low and high resolution), how
// space switches between them, the options of one tree and the answers of a
// query. Below both the public CDualOctoMap.h and the map's internals
// (ResolutionPolicy, TreeOps), so neither includes the other for a name.
#pragma once

#include <mrpt/math/TBoundingBox.h>
#include <mrpt/math/TPoint3D.h>

#include <cstdint>
#include <string>
#include <vector>

#include "avm/io/IniKeyOptions.h"

namespace avm
{
/** Which of the two trees. */
enum class Resolution : std::uint8_t
{
	Low,
	High
};

/** How the map decides what goes into the high-resolution tree. */
enum class SwitchPolicy
{
	/** Algorithm 1 as published: the low tree until the switch, then every
	 *  cloud goes to the high tree, filtered by Algorithm 2. */
	Paper,
	/** Space inside the active regions (boxes around people) is mapped in
	 *  the high tree, the rest in the low tree, split along every ray. */
	Region
};
std::string toString(SwitchPolicy p);
/** Parses "paper" / "region"; throws std::invalid_argument otherwise. */
SwitchPolicy switchPolicyFromString(const std::string& s);

/** How long a high-resolution region lives (region policy). */
enum class RegionLifetime
{
	/** A placement moves the region; the layer above ends it (the plugin,
	 *  whose regions follow persons: once its space has been in view for
	 *  `region_end_after_s` with no sighting of that person; out of view it
	 *  stays). */
	Follow,
	/** Every placement joins the region: every place it has been stays high
	 *  resolution. */
	Persist
};
std::string toString(RegionLifetime l);
/** Parses "follow" / "persist"; throws std::invalid_argument otherwise. */
RegionLifetime regionLifetimeFromString(const std::string& s);

enum class OccupancyState : std::uint8_t
{
	Unknown,
	Free,
	Occupied
};

/** The high-resolution space of one region (the layer above gives each
 *  person one; or one box given through the API): boxes in the world frame,
 *  aligned to the low voxel grid. */
struct THighResolutionRegion
{
	std::uint32_t regionId = 0;                   //!< 0: given with addHighResolutionRegion(), never ends
	std::vector<mrpt::math::TBoundingBox> boxes;  //!< follow: one; persist: all it has covered
};

/** Where a region goes (CDualOctoMap::placeRegions). */
struct TRegionPlacement
{
	std::uint32_t id = 0;          //!< > 0 (0 is the id of addHighResolutionRegion()'s regions)
	mrpt::math::TBoundingBox box;  //!< world frame, used as given, then grown to the low voxel grid
};

/** One visible leaf of either tree (see forEachVisibleLeaf). */
struct TLeafVoxel
{
	mrpt::math::TPoint3D center;
	double size = 0;  //!< edge [m]; larger than the resolution for pruned leaves
	double probability = 0.5;
	bool occupied = false;
};

/** The parameters of one octree. All keys carry the tree's prefix ("low_" or
 *  "high_") in the `_creationOpts` section (CDualOctoMap::TTreeOptions). */
struct TTreeOptions : public io::CIniKeyOptions<TTreeOptions>
{
	explicit TTreeOptions(std::string keyPrefix, double resolution);

	std::string keyPrefix;             //!< "low_" or "high_" (not loaded)
	double resolution;                 //!< [m] voxel edge
	double probHit = 0.7;              //!< hit probability of the sensor model
	double probMiss = 0.4;             //!< miss probability of the sensor model
	double clampingThresMin = 0.1192;  //!< lower clamping probability
	double clampingThresMax = 0.971;   //!< upper clamping probability
	double occupancyThres = 0.5;       //!< probability above which a voxel is occupied
	/** [m] rays longer than this are cut there: free space up to it, no
	 *  occupied endpoint (as octomap's insertPointCloud maxrange). */
	double maxRange = 5.0;

	/** Every key (with keyPrefix): name, member, unit, description, check. */
	io::IniKeys<TTreeOptions> iniKeys() const;
};
}  // namespace avm
