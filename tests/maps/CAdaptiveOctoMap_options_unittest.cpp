// The .ini face of avm::CAdaptiveOctoMap: creation from a map definition as
// MRPT apps do it, the options' save/load round trip, and rejection of bad
// values with the key's name. Also: observations it cannot use.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/maps/TMetricMapInitializer.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/serialization/CArchive.h>

#include <filesystem>

#include "avm/io/IniOptions.h"
#include "avm/plugin/CAdaptiveOctoMap.h"

using avm::CAdaptiveOctoMap;

namespace
{
const char* kIni = R"ini(
[map]
adaptiveOctoMap_count = 1

[map_adaptiveOctoMap_00_creationOpts]
low_resolution = 0.4
low_probHit = 0.75
low_maxrange = 4.5
high_resolution = 0.1
high_probMiss = 0.35
high_clampingThresMin = 0.15
high_occupancyThres = 0.55

[map_adaptiveOctoMap_00_insertOpts]
switch_policy = paper
switch_at_fraction = 0.25
expected_frame_count = 300
region_margin = 0.2
track_min_sightings = 5

[map_adaptiveOctoMap_00_likelihoodOpts]
decimation = 4
)ini";

CAdaptiveOctoMap::Ptr mapFromIni(const std::string& ini)
{
	mrpt::config::CConfigFileMemory cfg(ini);
	mrpt::maps::TSetOfMetricMapInitializers inits;
	inits.loadFromConfigFile(cfg, "map");
	mrpt::maps::CMultiMetricMap multi;
	multi.setListOfMaps(inits);
	return multi.mapByClass<CAdaptiveOctoMap>();
}

/** The message of the std::invalid_argument thrown while loading `ini`. */
std::string loadError(const std::string& ini)
{
	try
	{
		mapFromIni(ini);
	}
	catch (const std::exception& e)
	{
		return e.what();
	}
	return "(no error)";
}

std::string iniWith(const std::string& creation, const std::string& insertion = "")
{
	return "[map]\nadaptiveOctoMap_count=1\n[map_adaptiveOctoMap_00_creationOpts]\n" + creation +
		   "\n[map_adaptiveOctoMap_00_insertOpts]\n" + insertion + "\n";
}
}  // namespace

TEST(CAdaptiveOctoMapOptions, MapDefinitionFromIniCreatesTheMapWithItsValues)
{
	const auto map = mapFromIni(kIni);
	ASSERT_TRUE(map) << "adaptiveOctoMap_count=1 did not create an avm::CAdaptiveOctoMap";
	const auto& c = map->creationOptions();
	EXPECT_DOUBLE_EQ(c.low.resolution, 0.4);
	EXPECT_DOUBLE_EQ(c.low.probHit, 0.75);
	EXPECT_DOUBLE_EQ(c.low.maxRange, 4.5);
	EXPECT_DOUBLE_EQ(c.low.probMiss, 0.4);  // default kept
	EXPECT_DOUBLE_EQ(c.high.resolution, 0.1);
	EXPECT_DOUBLE_EQ(c.high.probMiss, 0.35);
	EXPECT_DOUBLE_EQ(c.high.clampingThresMin, 0.15);
	EXPECT_DOUBLE_EQ(c.high.occupancyThres, 0.55);
	EXPECT_EQ(map->insertionOptions.switchPolicy, avm::SwitchPolicy::Paper);
	EXPECT_DOUBLE_EQ(map->insertionOptions.switchAtFraction, 0.25);
	EXPECT_EQ(map->insertionOptions.expectedFrameCount, 300u);
	EXPECT_DOUBLE_EQ(map->personOptions.regionMargin, 0.2);
	EXPECT_EQ(map->personOptions.tracking.minSightings, 5u);
	EXPECT_EQ(map->likelihoodOptions.decimation, 4u);
	EXPECT_TRUE(map->isEmpty());
	// A copy (CMultiMetricMap copies by serialization, checkpoints too) keeps them.
	mrpt::io::CMemoryStream buf;
	auto arch = mrpt::serialization::archiveFrom(buf);
	arch << *map;
	buf.Seek(0);
	const auto copy = std::dynamic_pointer_cast<CAdaptiveOctoMap>(arch.ReadObject());
	ASSERT_TRUE(copy);
	EXPECT_EQ(copy->personOptions.tracking.minSightings, 5u);
	EXPECT_DOUBLE_EQ(copy->personOptions.regionMargin, 0.2);
}

TEST(CAdaptiveOctoMapOptions, SaveThenLoadGivesTheSameOptionsAndKeySet)
{
	const auto map = mapFromIni(kIni);
	ASSERT_TRUE(map);
	mrpt::config::CConfigFileMemory saved;
	map->creationOptions().saveToConfigFile(saved, "c");
	map->insertionOptions.saveToConfigFile(saved, "i");
	map->personOptions.saveToConfigFile(saved, "i");
	map->likelihoodOptions.saveToConfigFile(saved, "l");

	CAdaptiveOctoMap::TCreationOptions c;
	CAdaptiveOctoMap::TInsertionOptions i;
	avm::persons::TPersonLayerOptions p;
	CAdaptiveOctoMap::TLikelihoodOptions l;
	c.loadFromConfigFile(saved, "c");
	i.loadFromConfigFile(saved, "i");
	p.loadFromConfigFile(saved, "i");
	l.loadFromConfigFile(saved, "l");
	for (const auto* t : {&c.low, &c.high})
	{
		const auto& ref = t == &c.low ? map->creationOptions().low : map->creationOptions().high;
		EXPECT_EQ(t->resolution, ref.resolution);
		EXPECT_EQ(t->probHit, ref.probHit);
		EXPECT_EQ(t->probMiss, ref.probMiss);
		EXPECT_EQ(t->clampingThresMin, ref.clampingThresMin);
		EXPECT_EQ(t->clampingThresMax, ref.clampingThresMax);
		EXPECT_EQ(t->occupancyThres, ref.occupancyThres);
		EXPECT_EQ(t->maxRange, ref.maxRange);
	}
	EXPECT_EQ(i.switchPolicy, map->insertionOptions.switchPolicy);
	EXPECT_EQ(i.switchAtFraction, map->insertionOptions.switchAtFraction);
	EXPECT_EQ(i.expectedFrameCount, map->insertionOptions.expectedFrameCount);
	EXPECT_EQ(p.regionMargin, map->personOptions.regionMargin);
	EXPECT_EQ(p.personLabel, map->personOptions.personLabel);
	EXPECT_EQ(p.tracking.minSightings, map->personOptions.tracking.minSightings);
	EXPECT_EQ(l.decimation, map->likelihoodOptions.decimation);

	// The key set a user's ini is checked against: 7 per tree in creationOpts.
	std::vector<std::string> keys;
	saved.getAllKeys("c", keys);
	EXPECT_EQ(keys.size(), 14u);
	saved.getAllKeys("i", keys);
	EXPECT_EQ(keys.size(), 19u);  // with person_still_fraction, person_still_after_s, track_min_sightings
}

TEST(CAdaptiveOctoMapOptions, RejectsBadValuesNamingTheKey)
{
	auto expectKeyInError = [](const std::string& ini, const std::string& key)
	{
		const auto msg = loadError(ini);
		EXPECT_NE(msg.find(key), std::string::npos) << "error for " << key << " was: " << msg;
	};
	// High not finer than low.
	expectKeyInError(iniWith("low_resolution=0.2\nhigh_resolution=0.2"), "high_resolution");
	expectKeyInError(iniWith("low_resolution=0.2\nhigh_resolution=0.4"), "high_resolution");
	// High that does not tile low.
	expectKeyInError(iniWith("low_resolution=0.2\nhigh_resolution=0.03"), "high_resolution");
	// Too fine for a depth-16 tree, not positive, not a number.
	expectKeyInError(iniWith("low_resolution=0.002\nhigh_resolution=0.001"), "low_resolution");
	expectKeyInError(iniWith("low_resolution=-0.2"), "low_resolution");
	expectKeyInError(iniWith("low_resolution=abc"), "low_resolution");
	expectKeyInError(iniWith("high_probHit=1.5"), "high_probHit");
	expectKeyInError(iniWith("low_probMiss=0.7"), "low_probMiss");
	expectKeyInError(iniWith("low_clampingThresMin=0.98"), "low_clampingThresMax");
	expectKeyInError(iniWith("high_maxrange=0"), "high_maxrange");
	expectKeyInError(iniWith("", "switch_policy=fast"), "switch_policy");
	expectKeyInError(iniWith("", "region_margin=-1"), "region_margin");
	expectKeyInError(iniWith("", "insertion_threads=0"), "insertion_threads");
	expectKeyInError(iniWith("", "region_lifetime=forever"), "region_lifetime");
	expectKeyInError(iniWith("", "region_end_after_s=0"), "region_end_after_s");
	expectKeyInError(iniWith("", "person_depth_band=-0.5"), "person_depth_band");
	expectKeyInError(iniWith("", "person_percentile=0.5"), "person_percentile");
	expectKeyInError(iniWith("", "min_person_pixels=0"), "min_person_pixels");
	expectKeyInError(iniWith("", "min_person_depth_fraction=1.5"), "min_person_depth_fraction");
	expectKeyInError(iniWith("", "track_gate=0"), "track_gate");
	expectKeyInError(iniWith("", "track_gate=1\ntrack_max_gate=0.5"), "track_max_gate");
	expectKeyInError(iniWith("", "person_still_fraction=-0.1"), "person_still_fraction");
	expectKeyInError(iniWith("", "person_still_after_s=-1"), "person_still_after_s");
	expectKeyInError(iniWith("", "switch_policy=paper\nswitch_at_fraction=1.5"), "switch_at_fraction");
	expectKeyInError(iniWith("", "switch_policy=region\nswitch_at_insertion=10"), "switch_at_insertion");
	expectKeyInError(iniWith("", "switch_policy=paper\nswitch_at_insertion=2.5"), "switch_at_insertion");
	// The section is named too (MRPT re-wraps the message when the map is
	// created through it; loading the options directly keeps it verbatim).
	const auto msg = loadError(iniWith("high_probHit=1.5"));
	EXPECT_NE(msg.find("map_adaptiveOctoMap_00_creationOpts"), std::string::npos) << msg;
	mrpt::config::CConfigFileMemory cfg("[tree]\nlow_probMiss=0.9\n");
	CAdaptiveOctoMap::TCreationOptions c;
	try
	{
		c.loadFromConfigFile(cfg, "tree");
		ADD_FAILURE() << "low_probMiss=0.9 accepted";
	}
	catch (const std::invalid_argument& e)
	{
		EXPECT_EQ(std::string(e.what()), "[tree] low_probMiss = 0.9: must be in (0, 0.5)");
	}
}

TEST(CAdaptiveOctoMapOptions, ObservationsItCannotUseReturnFalse)
{
	CAdaptiveOctoMap map;
	mrpt::obs::CObservation2DRangeScan laser;
	laser.resizeScan(10);
	EXPECT_FALSE(map.insertObservation(laser));

	mrpt::obs::CObservation3DRangeScan noDepth;
	noDepth.hasRangeImage = false;
	EXPECT_FALSE(map.insertObservation(noDepth));

	mrpt::obs::CObservationPointCloud emptyCloud;
	emptyCloud.pointcloud = mrpt::maps::CSimplePointsMap::Create();
	EXPECT_FALSE(map.insertObservation(emptyCloud));

	EXPECT_TRUE(map.isEmpty());
	EXPECT_EQ(map.insertionCount(), 0u);
}

TEST(CAdaptiveOctoMapOptions, RegionPolicyRefusesAGlobalSwitchAndBadBoxes)
{
	CAdaptiveOctoMap map;
	EXPECT_THROW(map.switchToHighResolution(), std::logic_error);
	EXPECT_THROW(map.addHighResolutionRegion(mrpt::math::TBoundingBox({0, 0, 0}, {0, 1, 1})), std::invalid_argument);
	EXPECT_FALSE(map.hasSwitched());
}

TEST(CAdaptiveOctoMapOptions, RegionsNeverMergeAndAlignToTheLowGrid)
{
	CAdaptiveOctoMap map;  // low 0.20 m
	map.addHighResolutionRegion(mrpt::math::TBoundingBox({0.05, 0.05, 0.05}, {1.0, 1.0, 1.0}));
	map.addHighResolutionRegion(mrpt::math::TBoundingBox({3.0, 3.0, 3.0}, {3.5, 3.5, 3.5}));
	ASSERT_EQ(map.highResolutionRegions().size(), 2u);
	const auto r0 = map.highResolutionRegions()[0].boxes.at(0);
	EXPECT_NEAR(r0.min.x, 0.0, 1e-9);
	EXPECT_NEAR(r0.max.x, 1.0, 1e-9);
	// A third box overlapping both stays a region of its own: the space
	// between the first two is not pulled in.
	map.addHighResolutionRegion(mrpt::math::TBoundingBox({0.9, 0.9, 0.9}, {1.1, 1.1, 1.1}));
	ASSERT_EQ(map.highResolutionRegions().size(), 3u);
	EXPECT_EQ(map.query({2.0, 2.0, 2.0}).tree, avm::Resolution::Low);
	EXPECT_EQ(map.query({1.05, 1.05, 1.05}).tree, avm::Resolution::High);
	EXPECT_EQ(map.query({3.55, 3.55, 3.55}).tree, avm::Resolution::High) << "grown to the low grid";
	EXPECT_TRUE(map.hasSwitched());
	EXPECT_EQ(map.switchInsertionIndex(), std::optional<std::size_t>(0));
}

// The forced switch's key was named for frames but counts insertions: its old
// name switch_at_frame is still read, with a warning, and is no unknown key.
TEST(CAdaptiveOctoMapOptions, TheOldNameOfSwitchAtInsertionIsStillRead)
{
	CAdaptiveOctoMap::TInsertionOptions o;
	mrpt::config::CConfigFileMemory old("[s]\nswitch_policy = paper\nswitch_at_frame = 7\n");
	testing::internal::CaptureStderr();
	o.loadFromConfigFile(old, "s");
	const std::string warning = testing::internal::GetCapturedStderr();
	EXPECT_EQ(o.switchAtInsertion, 7);
	EXPECT_NE(warning.find("[s] switch_at_frame is now called switch_at_insertion"), std::string::npos) << warning;
	EXPECT_TRUE(avm::io::unknownKeys(old, "s", o).empty());
	mrpt::config::CConfigFileMemory typo("[s]\nswitch_at_frames = 7\n");
	EXPECT_EQ(avm::io::unknownKeys(typo, "s", o), std::vector<std::string>{"switch_at_frames"});
}

// The stock-app examples in ini/ create the map with the values they document.
TEST(CAdaptiveOctoMapOptions, ExampleIniFilesCreateTheMap)
{
	const std::filesystem::path dir = std::filesystem::path(AVM_SOURCE_DIR) / "ini";
	for (const auto& [file, section] :
		std::vector<std::pair<std::string, std::string>>{{"map-observations2map.ini", "MappingApplication"},
			{"map-icp-slam.ini", "MappingApplication"}, {"map-RawLogViewer.ini", "map"}})
	{
		mrpt::config::CConfigFile cfg((dir / file).string());
		mrpt::maps::TSetOfMetricMapInitializers inits;
		inits.loadFromConfigFile(cfg, section);
		mrpt::maps::CMultiMetricMap multi;
		multi.setListOfMaps(inits);
		const auto map = multi.mapByClass<CAdaptiveOctoMap>();
		ASSERT_TRUE(map) << file;
		EXPECT_DOUBLE_EQ(map->creationOptions().low.resolution, 0.20) << file;
		EXPECT_DOUBLE_EQ(map->creationOptions().high.resolution, 0.05) << file;
		EXPECT_EQ(map->insertionOptions.switchPolicy, avm::SwitchPolicy::Region) << file;
	}
}

// ini/map-observations2map.ini documents every key of the map for stock MRPT
// apps, each at its built-in default (the values avm-map's ini/default.ini has).
TEST(CAdaptiveOctoMapOptions, TheObservations2mapExampleHasEveryKeyAtItsDefault)
{
	const mrpt::config::CConfigFile ini(
		(std::filesystem::path(AVM_SOURCE_DIR) / "ini/map-observations2map.ini").string());
	const std::string prefix = "MappingApplication_adaptiveOctoMap_00_";
	const auto expectEveryKeyAtItsDefault = [&](const auto& defaults, const std::string& section)
	{
		auto loaded = defaults;
		loaded.loadFromConfigFile(ini, prefix + section);
		mrpt::config::CConfigFileMemory builtIn, fromFile;
		defaults.saveToConfigFile(builtIn, "s");
		loaded.saveToConfigFile(fromFile, "s");
		std::vector<std::string> keys;
		builtIn.getAllKeys("s", keys);
		for (const auto& key : keys)
		{
			EXPECT_TRUE(ini.keyExists(prefix + section, key)) << section << " " << key << " is not documented";
			EXPECT_EQ(fromFile.read_string("s", key, ""), builtIn.read_string("s", key, ""))
				<< section << " " << key << " is not at its default";
		}
	};
	const CAdaptiveOctoMap map;
	expectEveryKeyAtItsDefault(map.creationOptions(), "creationOpts");
	expectEveryKeyAtItsDefault(map.insertionOptions, "insertOpts");
	expectEveryKeyAtItsDefault(map.personOptions, "insertOpts");
	expectEveryKeyAtItsDefault(map.likelihoodOptions, "likelihoodOpts");
	expectEveryKeyAtItsDefault(map.renderingOptions, "renderOpts");
}
