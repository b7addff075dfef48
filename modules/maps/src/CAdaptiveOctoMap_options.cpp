// The .ini face of the map: load, save (the same key set) and validation of
// every option, with errors that name "[section] key".
#include <mrpt/config/CConfigFileBase.h>

#include <charconv>
#include <cmath>
#include <stdexcept>

#include "avm/io/ErrorMessage.h"
#include "avm/io/IniOptions.h"
#include "avm/maps/CAdaptiveOctoMap.h"

namespace avm
{
namespace
{
/** Shortest text that reads back to the same value (saved keys round-trip
 *  exactly, messages show what the user typed). */
template <typename T>
std::string str(const T& v)
{
	char buf[64];
	const auto r = std::to_chars(buf, buf + sizeof(buf), v);
	return std::string(buf, r.ptr);
}

[[noreturn]] void reject(const std::string& section, const std::string& key, const std::string& value,
	const std::string& problem)
{
	throw io::iniValueError(section, key, value, problem);
}

void requireInOpenRange(const std::string& section, const std::string& key, double v, double lo, double hi)
{
	if (!(v > lo && v < hi))
		reject(section, key, str(v), "must be in (" + str(lo) + ", " + str(hi) + ")");
}

/** An integer key that must not be negative. */
std::int64_t readNonNegative(
	const mrpt::config::CConfigFileBase& c, const std::string& section, const std::string& key, std::int64_t def)
{
	const auto v = io::readIniValue<std::int64_t>(c, section, key, def);
	if (v < 0) reject(section, key, str(v), "must be >= 0");
	return v;
}

double readNumber(const mrpt::config::CConfigFileBase& c, const std::string& section, const std::string& key, double def)
{
	return io::readIniValue<double>(c, section, key, def);
}

/** A key naming one of an enum's values, parsed by `parse` (which throws
 *  std::invalid_argument on anything else). */
template <typename Enum, typename Parse>
Enum readChoice(const mrpt::config::CConfigFileBase& c, const std::string& section, const std::string& key, Enum def,
	Parse parse, const std::string& expected)
{
	const std::string text = c.read_string(section, key, toString(def));
	try
	{
		return parse(text);
	}
	catch (const std::invalid_argument&)
	{
		reject(section, key, text, expected);
	}
}

// A tree of depth 16 spans +-resolution * 2^15 around the origin; below this
// half extent an indoor run would leave the tree.
constexpr double kMinTreeHalfExtent = 100.0;  // [m]
constexpr double kTreeHalfCells = 32768.0;
}  // namespace

std::string toString(SwitchPolicy p) { return p == SwitchPolicy::Paper ? "paper" : "region"; }

SwitchPolicy switchPolicyFromString(const std::string& s)
{
	if (s == "paper") return SwitchPolicy::Paper;
	if (s == "region") return SwitchPolicy::Region;
	throw std::invalid_argument("unknown switch policy '" + s + "' (expected paper or region)");
}

std::string toString(RegionLifetime l) { return l == RegionLifetime::Persist ? "persist" : "follow"; }

RegionLifetime regionLifetimeFromString(const std::string& s)
{
	if (s == "follow") return RegionLifetime::Follow;
	if (s == "persist") return RegionLifetime::Persist;
	throw std::invalid_argument("unknown region lifetime '" + s + "' (expected follow or persist)");
}

// ---------------------------------------------------------------- TTreeOptions
CAdaptiveOctoMap::TTreeOptions::TTreeOptions(std::string prefix, double res)
	: keyPrefix(std::move(prefix)), resolution(res)
{
}

void CAdaptiveOctoMap::TTreeOptions::loadFromConfigFile(
	const mrpt::config::CConfigFileBase& c, const std::string& section)
{
	resolution = readNumber(c, section, keyPrefix + "resolution", resolution);
	probHit = readNumber(c, section, keyPrefix + "probHit", probHit);
	probMiss = readNumber(c, section, keyPrefix + "probMiss", probMiss);
	clampingThresMin = readNumber(c, section, keyPrefix + "clampingThresMin", clampingThresMin);
	clampingThresMax = readNumber(c, section, keyPrefix + "clampingThresMax", clampingThresMax);
	occupancyThres = readNumber(c, section, keyPrefix + "occupancyThres", occupancyThres);
	maxRange = readNumber(c, section, keyPrefix + "maxrange", maxRange);
	validate(section);
}

void CAdaptiveOctoMap::TTreeOptions::saveToConfigFile(
	mrpt::config::CConfigFileBase& c, const std::string& section) const
{
	c.write(section, keyPrefix + "resolution", str(resolution));
	c.write(section, keyPrefix + "probHit", str(probHit));
	c.write(section, keyPrefix + "probMiss", str(probMiss));
	c.write(section, keyPrefix + "clampingThresMin", str(clampingThresMin));
	c.write(section, keyPrefix + "clampingThresMax", str(clampingThresMax));
	c.write(section, keyPrefix + "occupancyThres", str(occupancyThres));
	c.write(section, keyPrefix + "maxrange", str(maxRange));
}

void CAdaptiveOctoMap::TTreeOptions::validate(const std::string& section) const
{
	const auto& p = keyPrefix;
	if (!(std::isfinite(resolution) && resolution > 0))
		reject(section, p + "resolution", str(resolution), "must be a positive length in metres");
	if (resolution * kTreeHalfCells < kMinTreeHalfExtent)
		reject(section, p + "resolution", str(resolution),
			"too fine for an octree of depth 16: it would span only +-" + str(resolution * kTreeHalfCells) +
				" m (at least +-" + str(kMinTreeHalfExtent) + " m needed, i.e. resolution >= " +
				str(kMinTreeHalfExtent / kTreeHalfCells) + " m)");
	if (resolution > 100)
		reject(section, p + "resolution", str(resolution), "larger than 100 m is not a voxel map");
	requireInOpenRange(section, p + "probHit", probHit, 0.5, 1.0);
	requireInOpenRange(section, p + "probMiss", probMiss, 0.0, 0.5);
	requireInOpenRange(section, p + "clampingThresMin", clampingThresMin, 0.0, 1.0);
	requireInOpenRange(section, p + "clampingThresMax", clampingThresMax, 0.0, 1.0);
	if (!(clampingThresMin < clampingThresMax))
		reject(section, p + "clampingThresMax", str(clampingThresMax),
			"must be above " + p + "clampingThresMin (" + str(clampingThresMin) + ")");
	requireInOpenRange(section, p + "occupancyThres", occupancyThres, 0.0, 1.0);
	if (!(std::isfinite(maxRange) && maxRange > 0))
		reject(section, p + "maxrange", str(maxRange), "must be a positive range in metres");
}

// ------------------------------------------------------------ TCreationOptions
void CAdaptiveOctoMap::TCreationOptions::loadFromConfigFile(
	const mrpt::config::CConfigFileBase& c, const std::string& section)
{
	low.loadFromConfigFile(c, section);
	high.loadFromConfigFile(c, section);
	validate(section);
}

void CAdaptiveOctoMap::TCreationOptions::saveToConfigFile(
	mrpt::config::CConfigFileBase& c, const std::string& section) const
{
	low.saveToConfigFile(c, section);
	high.saveToConfigFile(c, section);
}

void CAdaptiveOctoMap::TCreationOptions::validate(const std::string& section) const
{
	low.validate(section);
	high.validate(section);
	if (!(high.resolution < low.resolution))
		reject(section, high.keyPrefix + "resolution", str(high.resolution),
			"must be finer than " + low.keyPrefix + "resolution (" + str(low.resolution) + ")");
	const double ratio = low.resolution / high.resolution;
	if (std::abs(ratio - std::round(ratio)) > 1e-6)
		reject(section, high.keyPrefix + "resolution", str(high.resolution),
			"must divide " + low.keyPrefix + "resolution (" + str(low.resolution) +
				") a whole number of times, so that no high voxel straddles two low ones");
}

// ----------------------------------------------------------- TInsertionOptions
void CAdaptiveOctoMap::TInsertionOptions::loadFromConfigFile(
	const mrpt::config::CConfigFileBase& c, const std::string& section)
{
	switchPolicy = readChoice(c, section, "switch_policy", switchPolicy, switchPolicyFromString, "expected paper or region");
	regionMargin = readNumber(c, section, "region_margin", regionMargin);
	regionLifetime = readChoice(
		c, section, "region_lifetime", regionLifetime, regionLifetimeFromString, "expected follow or persist");
	regionEndAfterSeconds = readNumber(c, section, "region_end_after_s", regionEndAfterSeconds);
	personLabel = c.read_string(section, "person_label", personLabel);
	sighting.depthBand = readNumber(c, section, "person_depth_band", sighting.depthBand);
	sighting.percentile = readNumber(c, section, "person_percentile", sighting.percentile);
	sighting.minPixels = static_cast<std::size_t>(
		readNonNegative(c, section, "min_person_pixels", static_cast<std::int64_t>(sighting.minPixels)));
	sighting.minDepthFraction = readNumber(c, section, "min_person_depth_fraction", sighting.minDepthFraction);
	tracking.gate = readNumber(c, section, "track_gate", tracking.gate);
	tracking.gateGrowth = readNumber(c, section, "track_gate_growth", tracking.gateGrowth);
	tracking.maxGate = readNumber(c, section, "track_max_gate", tracking.maxGate);
	const double frame = readNumber(c, section, "switch_at_frame", static_cast<double>(switchAtFrame));
	if (frame != std::floor(frame)) reject(section, "switch_at_frame", str(frame), "must be a whole insertion index");
	switchAtFrame = static_cast<std::int64_t>(frame);
	switchAtFraction = readNumber(c, section, "switch_at_fraction", switchAtFraction);
	expectedFrameCount = static_cast<std::uint64_t>(readNonNegative(c, section, "expected_frame_count",
		static_cast<std::int64_t>(expectedFrameCount)));
	insertionThreads = static_cast<std::uint32_t>(readNonNegative(c, section, "insertion_threads", insertionThreads));
	validate(section);
}

void CAdaptiveOctoMap::TInsertionOptions::saveToConfigFile(
	mrpt::config::CConfigFileBase& c, const std::string& section) const
{
	c.write(section, "switch_policy", toString(switchPolicy));
	c.write(section, "region_margin", str(regionMargin));
	c.write(section, "region_lifetime", toString(regionLifetime));
	c.write(section, "region_end_after_s", str(regionEndAfterSeconds));
	c.write(section, "person_label", personLabel);
	c.write(section, "person_depth_band", str(sighting.depthBand));
	c.write(section, "person_percentile", str(sighting.percentile));
	c.write(section, "min_person_pixels", str(sighting.minPixels));
	c.write(section, "min_person_depth_fraction", str(sighting.minDepthFraction));
	c.write(section, "track_gate", str(tracking.gate));
	c.write(section, "track_gate_growth", str(tracking.gateGrowth));
	c.write(section, "track_max_gate", str(tracking.maxGate));
	c.write(section, "switch_at_frame", str(switchAtFrame));
	c.write(section, "switch_at_fraction", str(switchAtFraction));
	c.write(section, "expected_frame_count", str(expectedFrameCount));
	c.write(section, "insertion_threads", str(insertionThreads));
}

void CAdaptiveOctoMap::TInsertionOptions::validate(const std::string& section) const
{
	if (!(std::isfinite(regionMargin) && regionMargin >= 0))
		reject(section, "region_margin", str(regionMargin), "must be >= 0 metres");
	if (personLabel.empty()) reject(section, "person_label", "", "must not be empty");
	if (insertionThreads < 1 || insertionThreads > 16)
		reject(section, "insertion_threads", str(insertionThreads), "must be in [1, 16]");
	if (!(std::isfinite(regionEndAfterSeconds) && regionEndAfterSeconds > 0))
		reject(section, "region_end_after_s", str(regionEndAfterSeconds), "must be > 0 seconds");
	if (!(std::isfinite(sighting.depthBand) && sighting.depthBand > 0))
		reject(section, "person_depth_band", str(sighting.depthBand), "must be > 0 metres");
	if (!(sighting.percentile >= 0 && sighting.percentile < 0.5))
		reject(section, "person_percentile", str(sighting.percentile), "must be in [0, 0.5)");
	if (sighting.minPixels < 1) reject(section, "min_person_pixels", str(sighting.minPixels), "must be >= 1");
	if (!(sighting.minDepthFraction >= 0 && sighting.minDepthFraction <= 1))
		reject(section, "min_person_depth_fraction", str(sighting.minDepthFraction), "must be in [0, 1]");
	if (!(std::isfinite(tracking.gate) && tracking.gate > 0))
		reject(section, "track_gate", str(tracking.gate), "must be > 0 metres");
	if (!(std::isfinite(tracking.gateGrowth) && tracking.gateGrowth >= 0))
		reject(section, "track_gate_growth", str(tracking.gateGrowth), "must be >= 0 m/s");
	if (!(std::isfinite(tracking.maxGate) && tracking.maxGate >= tracking.gate))
		reject(section, "track_max_gate", str(tracking.maxGate), "must be >= track_gate");
	if (switchAtFrame < -1) reject(section, "switch_at_frame", str(switchAtFrame), "must be -1 (off) or >= 0");
	if (!(switchAtFraction == -1 || (switchAtFraction >= 0 && switchAtFraction <= 1)))
		reject(section, "switch_at_fraction", str(switchAtFraction), "must be -1 (off) or in [0, 1]");
	if (switchPolicy == SwitchPolicy::Region)
	{
		if (switchAtFrame != -1)
			reject(section, "switch_at_frame", str(switchAtFrame), "a forced switch needs switch_policy = paper");
		if (switchAtFraction != -1)
			reject(section, "switch_at_fraction", str(switchAtFraction),
				"a forced switch needs switch_policy = paper");
	}
}

// ---------------------------------------------------------- TLikelihoodOptions
void CAdaptiveOctoMap::TLikelihoodOptions::loadFromConfigFile(
	const mrpt::config::CConfigFileBase& c, const std::string& section)
{
	decimation = static_cast<std::uint32_t>(readNonNegative(c, section, "decimation", decimation));
	validate(section);
}

void CAdaptiveOctoMap::TLikelihoodOptions::saveToConfigFile(
	mrpt::config::CConfigFileBase& c, const std::string& section) const
{
	c.write(section, "decimation", str(decimation));
}

void CAdaptiveOctoMap::TLikelihoodOptions::validate(const std::string& section) const
{
	if (decimation < 1) reject(section, "decimation", str(decimation), "must be >= 1");
}

// ----------------------------------------------------------- TRenderingOptions
void CAdaptiveOctoMap::TRenderingOptions::loadFromConfigFile(
	const mrpt::config::CConfigFileBase& c, const std::string& section)
{
	showFreeSpace = c.read_bool(section, "show_free_space", showFreeSpace);
	showRegions = c.read_bool(section, "show_regions", showRegions);
}

void CAdaptiveOctoMap::TRenderingOptions::saveToConfigFile(
	mrpt::config::CConfigFileBase& c, const std::string& section) const
{
	c.write(section, "show_free_space", showFreeSpace ? "true" : "false");
	c.write(section, "show_regions", showRegions ? "true" : "false");
}
}  // namespace avm
