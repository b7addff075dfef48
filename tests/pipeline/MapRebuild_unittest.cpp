// [pipeline] rebuild_map: the map made again from the rawlog at the final
// poses, so that it follows a trajectory the loop closures corrected.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/containers/yaml.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/io/vector_loadsave.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/serialization/CArchive.h>

#include <vector>

#include "DefaultIni.h"
#include "TestData.h"
#include "avm/io/ProgramMain.h"
#include "avm/io/RawlogFrameReader.h"
#include "avm/pipeline/MappingPipeline.h"

using namespace avm;
namespace fs = std::filesystem;

namespace
{
/** The default configuration without pictures or checkpoints. */
mrpt::config::CConfigFileMemory defaultIni()
{
	auto ini = test::defaultIni();
	ini.write("pipeline", "picture_size", "0");
	ini.write("pipeline", "checkpoint_interval_s", "0");
	return ini;
}

/** The Bonn frames 0..last played forward, then backward to frame 0, as one
 *  rawlog (timestamps at the sequence's mean rate; ground truth kept): the
 *  camera shows its start again. Colour stays in the fixture's images folder. */
fs::path writeForwardBackwardRawlog(const fs::path& dir, std::size_t last)
{
	io::RawlogFrameReader reader(test::bonnRawlog(), /*loadImages=*/false);
	std::vector<io::RgbdFrame> frames;
	while (auto f = reader.next())
		if (f->index <= last) frames.push_back(std::move(*f));
	const double t0 = frames.front().timestamp();
	const double dt = (frames.back().timestamp() - t0) / double(frames.size() - 1);
	std::vector<const io::RgbdFrame*> order;
	for (const auto& f : frames) order.push_back(&f);
	for (auto it = frames.rbegin() + 1; it != frames.rend(); ++it) order.push_back(&*it);

	const auto rawlog = dir / "forward_backward.rawlog";
	fs::create_directory_symlink(io::imagesDirectoryOf(test::bonnRawlog()), dir / "forward_backward_Images");
	mrpt::io::CFileOutputStream file(rawlog.string());
	auto out = mrpt::serialization::archiveFrom(file);
	for (std::size_t i = 0; i < order.size(); ++i)
	{
		const auto stamp = mrpt::Clock::fromDouble(t0 + double(i) * dt);
		auto obs = std::make_shared<mrpt::obs::CObservation3DRangeScan>(*order[i]->observation);
		obs->timestamp = stamp;
		out << *obs;
		auto gt = mrpt::obs::CObservationRobotPose::Create();
		gt->sensorLabel = "GROUND_TRUTH";
		gt->timestamp = stamp;
		gt->pose = mrpt::poses::CPose3DPDFGaussian(order[i]->groundTruth.value());
		out << *gt;
	}
	return rawlog;
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
		auto ini = defaultIni();
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

// After loops closed, the map is made at the corrected poses: it is no longer
// the map the run inserted at the drifted ones.
TEST(PipelineMapRebuild, AfterALoopClosesTheMapFollowsTheCorrectedTrajectory)
{
	const auto dir = test::scratchDir("pipeline-map-rebuild-loops");
	const auto rawlog = writeForwardBackwardRawlog(dir, 299);
	const auto runWith = [&](const std::string& when)
	{
		auto ini = defaultIni();
		ini.write("odometry", "loop_closure", "true");
		ini.write("pipeline", "rebuild_map", when);
		io::useImagesFolderOf(rawlog);
		pipeline::MappingPipeline p(ini, AVM_SOURCE_DIR);
		const auto out = dir / when;
		const auto summary = p.run(rawlog, out);
		EXPECT_EQ(summary.frames, 599u);
		std::cout << "rebuild_map = " << when << ": " << summary.loopsClosed << " loops closed, ATE "
				  << summary.ateRmse.value_or(-1) << " m";
		if (summary.mapRebuild)
			std::cout << "; map rebuilt, " << summary.mapRebuild->frames << " frames in " << summary.mapRebuild->seconds
					  << " s";
		std::cout << "\n";
		return std::pair{out, summary};
	};
	const auto [drifted, open] = runWith("never");
	const auto [corrected, closed] = runWith("after_loops");
	EXPECT_EQ(open.loopsClosed, closed.loopsClosed);
	ASSERT_GE(closed.loopsClosed, 1u);
	ASSERT_TRUE(closed.mapRebuild);
	EXPECT_EQ(closed.mapRebuild->frames, closed.frames);
	EXPECT_EQ(test::fileBytes(drifted / "trajectory.txt"), test::fileBytes(corrected / "trajectory.txt"));
	EXPECT_NE(test::fileBytes(drifted / "map_low.bt"), test::fileBytes(corrected / "map_low.bt"));
}
