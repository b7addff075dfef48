// The .ini face of the map: every option declared once (io::IniKeys), which
// gives load, save (the same key set), validation with errors that name
// "[section] key", and the keys' documentation.
#include <mrpt/config/CConfigFileBase.h>

#include <cmath>
#include <stdexcept>

#include "OcTreeKeys.h"
#include "avm/io/EnumNames.h"
#include "avm/io/IniKeys.h"
#include "avm/maps/CDualOctoMap.h"

namespace avm
{
namespace
{
using io::iniText;

io::IniRule<double> inOpenRange(double lo, double hi)
{
	return {[lo, hi](double v) { return v > lo && v < hi; }, "must be in (" + iniText(lo) + ", " + iniText(hi) + ")"};
}

// Below this half extent of the tree (treeHalfExtent) an indoor run
// would leave it.
constexpr double kMinTreeHalfExtent = 100.0;  // [m]
}  // namespace

namespace
{
const io::EnumNames<SwitchPolicy>& switchPolicyNames()
{
	static const io::EnumNames<SwitchPolicy> names(
		"switch policy", {{SwitchPolicy::Paper, "paper"}, {SwitchPolicy::Region, "region"}});
	return names;
}

const io::EnumNames<RegionLifetime>& regionLifetimeNames()
{
	static const io::EnumNames<RegionLifetime> names(
		"region lifetime", {{RegionLifetime::Follow, "follow"}, {RegionLifetime::Persist, "persist"}});
	return names;
}
}  // namespace

std::string toString(SwitchPolicy p) { return switchPolicyNames().name(p); }

SwitchPolicy switchPolicyFromString(const std::string& s) { return switchPolicyNames().parse(s); }

std::string toString(RegionLifetime l) { return regionLifetimeNames().name(l); }

RegionLifetime regionLifetimeFromString(const std::string& s) { return regionLifetimeNames().parse(s); }

// ---------------------------------------------------------------- TTreeOptions
TTreeOptions::TTreeOptions(std::string prefix, double res) : keyPrefix(std::move(prefix)), resolution(res) {}

io::IniKeys<TTreeOptions> TTreeOptions::iniKeys() const
{
	using O = TTreeOptions;
	const std::string p = keyPrefix;
	io::IniKeys<O> keys;
	keys.number(p + "resolution", &O::resolution, "m", "voxel edge",
			{[](double v) { return v > 0; }, "must be a positive length in metres"})
		.check(
			p + "resolution", [](const O& o) { return treeHalfExtent(o.resolution) >= kMinTreeHalfExtent; },
			[](const O& o)
			{
				return "too fine for an octree of depth 16: it would span only +-" +
					   iniText(treeHalfExtent(o.resolution)) + " m (at least +-" + iniText(kMinTreeHalfExtent) +
					   " m needed, i.e. resolution >= " + iniText(kMinTreeHalfExtent / treeHalfExtent(1.0)) + " m)";
			})
		.check(
			p + "resolution", [](const O& o) { return o.resolution <= 100; }, "larger than 100 m is not a voxel map")
		.number(p + "probHit", &O::probHit, "", "hit probability of the sensor model", inOpenRange(0.5, 1.0))
		.number(p + "probMiss", &O::probMiss, "", "miss probability of the sensor model", inOpenRange(0.0, 0.5))
		.number(p + "clampingThresMin", &O::clampingThresMin, "", "lower clamping probability", inOpenRange(0.0, 1.0))
		.number(p + "clampingThresMax", &O::clampingThresMax, "", "upper clamping probability", inOpenRange(0.0, 1.0))
		.check(
			p + "clampingThresMax", [](const O& o) { return o.clampingThresMin < o.clampingThresMax; },
			[p](const O& o) { return "must be above " + p + "clampingThresMin (" + iniText(o.clampingThresMin) + ")"; })
		.number(p + "occupancyThres", &O::occupancyThres, "", "probability above which a voxel is occupied",
			inOpenRange(0.0, 1.0))
		.number(p + "maxrange", &O::maxRange, "m", "rays cut here: free space up to it, no endpoint",
			{[](double v) { return v > 0; }, "must be a positive range in metres"});
	return keys;
}

// ------------------------------------------------------------ TCreationOptions
io::IniKeys<CDualOctoMap::TCreationOptions> CDualOctoMap::TCreationOptions::iniKeys() const
{
	using O = TCreationOptions;
	const std::string highKey = high.keyPrefix + "resolution", lowKey = low.keyPrefix + "resolution";
	io::IniKeys<O> keys;
	keys.include(&O::low, low.iniKeys())
		.include(&O::high, high.iniKeys())
		.check(
			highKey, [](const O& o) { return o.high.resolution < o.low.resolution; },
			[lowKey](const O& o) { return "must be finer than " + lowKey + " (" + iniText(o.low.resolution) + ")"; })
		.check(
			highKey,
			[](const O& o)
			{
				const double ratio = o.low.resolution / o.high.resolution;
				return std::abs(ratio - std::round(ratio)) <= 1e-6;
			},
			[lowKey](const O& o)
			{
				return "must divide " + lowKey + " (" + iniText(o.low.resolution) +
					   ") a whole number of times, so that no high voxel straddles two low ones";
			});
	return keys;
}

// ----------------------------------------------------------- TInsertionOptions
io::IniKeys<CDualOctoMap::TInsertionOptions> CDualOctoMap::TInsertionOptions::iniKeys()
{
	using O = TInsertionOptions;
	const auto forcedSwitchNeedsPaper = [](const O& o) { return o.switchPolicy == SwitchPolicy::Paper; };
	io::IniKeys<O> keys;
	keys.choice(
			"switch_policy", &O::switchPolicy, switchPolicyFromString, [](SwitchPolicy p) { return toString(p); },
			"region (space around people at high resolution) | paper (Algorithm 1 as published)",
			"expected paper or region")
		.choice(
			"region_lifetime", &O::regionLifetime, regionLifetimeFromString,
			[](RegionLifetime l) { return toString(l); },
			"follow (the region moves with its person; ends once its space was in view region_end_after_s with no "
			"sighting of the person; out of view it stays) | persist (every place a person has been stays high "
			"resolution)",
			"expected follow or persist")
		.number("switch_at_insertion", &O::switchAtInsertion, "",
			"paper policy: force the switch at this insertion index (0 = the first observation inserted; in avm-map "
			"the first frame mapped); -1 = off",
			{[](std::int64_t v) { return v >= -1; }, "must be -1 (off) or >= 0"})
		.renamed("switch_at_frame", "switch_at_insertion")
		.check(
			"switch_at_insertion", [=](const O& o) { return o.switchAtInsertion == -1 || forcedSwitchNeedsPaper(o); },
			"a forced switch needs switch_policy = paper")
		.number("switch_at_fraction", &O::switchAtFraction, "",
			"paper policy: force the switch at this fraction of the run; -1 = off",
			{[](double v) { return v == -1 || (v >= 0 && v <= 1); }, "must be -1 (off) or in [0, 1]"})
		.check(
			"switch_at_fraction", [=](const O& o) { return o.switchAtFraction == -1 || forcedSwitchNeedsPaper(o); },
			"a forced switch needs switch_policy = paper")
		.number<std::int64_t>("expected_frame_count", &O::expectedFrameCount, "",
			"frames in the run, for switch_at_fraction; 0 = counted by avm-map",
			{[](std::int64_t v) { return v >= 0; }, "must be >= 0"})
		.number<std::int64_t>("insertion_threads", &O::insertionThreads, "",
			"threads for unprojecting and keying a depth image (row bands), 1..16; rays and tree updates stay on one "
			"thread",
			{[](std::int64_t v) { return v >= 1 && v <= 16; }, "must be in [1, 16]"});
	return keys;
}

// ---------------------------------------------------------- TLikelihoodOptions
io::IniKeys<CDualOctoMap::TLikelihoodOptions> CDualOctoMap::TLikelihoodOptions::iniKeys()
{
	io::IniKeys<TLikelihoodOptions> keys;
	keys.number<std::int64_t>("decimation", &TLikelihoodOptions::decimation, "",
		"use one pixel in N along rows and columns", {[](std::int64_t v) { return v >= 1; }, "must be >= 1"});
	return keys;
}

// ----------------------------------------------------------- TRenderingOptions
io::IniKeys<CDualOctoMap::TRenderingOptions> CDualOctoMap::TRenderingOptions::iniKeys()
{
	io::IniKeys<TRenderingOptions> keys;
	keys.number("show_free_space", &TRenderingOptions::showFreeSpace, "", "draw free voxels too")
		.number("show_regions", &TRenderingOptions::showRegions, "", "draw the high-resolution regions");
	return keys;
}
}  // namespace avm

template struct avm::io::CIniKeyOptions<avm::TTreeOptions>;
template struct avm::io::CIniKeyOptions<avm::CDualOctoMap::TCreationOptions>;
template struct avm::io::CIniKeyOptions<avm::CDualOctoMap::TInsertionOptions>;
template struct avm::io::CIniKeyOptions<avm::CDualOctoMap::TLikelihoodOptions>;
template struct avm::io::CIniKeyOptions<avm::CDualOctoMap::TRenderingOptions>;
