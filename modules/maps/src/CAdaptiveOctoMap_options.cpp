// The .ini face of the map: load, save (the same key set) and validation of
// every option, with errors that name "[section] key".
#include <mrpt/config/CConfigFileBase.h>

#include <charconv>
#include <cmath>
#include <stdexcept>

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
	throw std::invalid_argument("[" + section + "] " + key + " = " + value + ": " + problem);
}

void requireInOpenRange(const std::string& section, const std::string& key, double v, double lo, double hi)
{
	if (!(v > lo && v < hi))
		reject(section, key, str(v), "must be in (" + str(lo) + ", " + str(hi) + ")");
}

/** An integer key that must not be negative (MRPT reads it as a signed int,
 *  so a negative value is caught here rather than wrapping around). */
std::int64_t readNonNegative(
	const mrpt::config::CConfigFileBase& c, const std::string& section, const std::string& key, std::int64_t def)
{
	const std::string text = c.read_string(section, key, str(def));
	std::size_t used = 0;
	long long v = 0;
	try
	{
		v = std::stoll(text, &used);
	}
	catch (const std::exception&)
	{
		reject(section, key, text, "not an integer");
	}
	if (used != text.size()) reject(section, key, text, "not an integer");
	if (v < 0) reject(section, key, text, "must be >= 0");
	return v;
}

double readNumber(const mrpt::config::CConfigFileBase& c, const std::string& section, const std::string& key, double def)
{
	const std::string text = c.read_string(section, key, str(def));
	std::size_t used = 0;
	double v = 0;
	try
	{
		v = std::stod(text, &used);
	}
	catch (const std::exception&)
	{
		reject(section, key, text, "not a number");
	}
	if (used != text.size()) reject(section, key, text, "not a number");
	return v;
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
	const std::string policy = c.read_string(section, "switch_policy", toString(switchPolicy));
	try
	{
		switchPolicy = switchPolicyFromString(policy);
	}
	catch (const std::invalid_argument&)
	{
		reject(section, "switch_policy", policy, "expected paper or region");
	}
	regionMargin = readNumber(c, section, "region_margin", regionMargin);
	regionExpiryFrames = static_cast<std::uint32_t>(readNonNegative(c, section, "region_expiry_frames", regionExpiryFrames));
	personLabel = c.read_string(section, "person_label", personLabel);
	minLabelPixels = static_cast<std::uint32_t>(readNonNegative(c, section, "min_label_pixels", minLabelPixels));
	labelDepthBand = readNumber(c, section, "label_depth_band", labelDepthBand);
	labelPercentile = readNumber(c, section, "label_percentile", labelPercentile);
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
	c.write(section, "region_expiry_frames", str(regionExpiryFrames));
	c.write(section, "person_label", personLabel);
	c.write(section, "min_label_pixels", str(minLabelPixels));
	c.write(section, "label_depth_band", str(labelDepthBand));
	c.write(section, "label_percentile", str(labelPercentile));
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
	if (!(std::isfinite(labelDepthBand) && labelDepthBand > 0))
		reject(section, "label_depth_band", str(labelDepthBand), "must be > 0 metres");
	if (!(labelPercentile >= 0 && labelPercentile < 0.5))
		reject(section, "label_percentile", str(labelPercentile), "must be in [0, 0.5)");
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
