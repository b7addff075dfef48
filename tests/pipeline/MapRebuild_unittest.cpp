// [pipeline] rebuild_map: the map made again from the rawlog at the final
// poses, so that it follows a trajectory the loop closures corrected (after
// loops: MapRebuildLoops_unittest.cpp).
#include <gtest/gtest.h>
#include <mrpt/containers/yaml.h>

#include "DefaultIni.h"
#include "TestData.h"
#include "avm/pipeline/MappingPipeline.h"

using namespace avm;
namespace fs = std::filesystem;

namespace
{
/** The default configuration without pictures or checkpoints. */
mrpt::config::CConfigFileMemory defaultIniWithoutCheckpoints()
{
	auto ini = test::defaultIni();
	ini.write("pipeline", "picture_size", "0");
	ini.write("pipeline", "checkpoint_interval_s", "0");
	return ini;
}

mrpt::containers::yaml statsOf(const fs::path& out)
{
	return mrpt::containers::yaml::FromFile((out / "stats.json").string());
}
}  // namespace

// The rebuild replays the run's map calls: at the poses the run used, it makes
// the same map, regions and persons, byte for byte.
TEST(PipelineMapRebuild, AtUnchangedPosesTheMapIsTheSameByteForByte)
{
	const auto dir = test::scratchDir("pipeline-map-rebuild-same");
	const auto runWith = [&](const std::string& when)
	{
		auto ini = defaultIniWithoutCheckpoints();
		ini.write("pipeline", "max_frames", "160");
		ini.write("pipeline", "rebuild_map", when);
		pipeline::MappingPipeline p(ini, AVM_SOURCE_DIR);
		const auto out = dir / when;
		const auto summary = p.run(test::bonnRawlog(), out);
		EXPECT_EQ(summary.frames, 160u);
		EXPECT_GT(summary.persons, 0u);
		EXPECT_EQ(summary.mapRebuild.has_value(), when == "always");
		if (summary.mapRebuild)
		{
			EXPECT_EQ(summary.mapRebuild->frames, 160u);
		}
		return out;
	};
	const auto incremental = runWith("never"), rebuilt = runWith("always");
	EXPECT_TRUE(statsOf(rebuilt)["map_rebuild"]["done"].as<bool>());
	EXPECT_FALSE(statsOf(incremental)["map_rebuild"]["done"].as<bool>());
	for (const char* name : {"map_low.bt", "map_high.bt", "persons.csv", "detections.txt", "trajectory.txt"})
	{
		EXPECT_GT(test::fileBytes(incremental / name).size(), 100u) << name;
		EXPECT_EQ(test::fileBytes(incremental / name), test::fileBytes(rebuilt / name)) << name;
	}
}
