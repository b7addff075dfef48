// The application's runs on the real Bonn sequence compared with each other
// (read ahead or not, mapping on its own thread or not, the same run twice),
// and a tracking loss bridged in the trajectory avm-map writes.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <Eigen/Core>
#include <string>

#include "CoveredLens.h"
#include "DefaultIni.h"
#include "TestData.h"
#include "TrajectoryStatus.h"
#include "avm/io/ProgramMain.h"
#include "avm/io/RawlogFrameReader.h"
#include "avm/io/Trajectory.h"
#include "avm/pipeline/MappingPipeline.h"

using namespace avm;
namespace fs = std::filesystem;

TEST(PipelineReadAhead, SameFramesInTheSameOrderAsReadingInTheLoop)
{
	// Two replays cut short at frame 400: the reader thread crosses a replay
	// boundary and is stopped mid-sequence. Its map and trajectory must be
	// those of reading on the loop's thread, byte for byte.
	const auto dir = test::scratchDir("pipeline-read-ahead");
	const auto runWith = [&](const std::string& readAhead)
	{
		mrpt::config::CConfigFileMemory ini(
			"[pipeline]\npose_source=gt\ndetect_every_n=0\npicture_size=0\nrepeat=2\nmax_frames=400\n"
			"read_ahead_frames=" +
			readAhead + "\n[map]\nadaptiveOctoMap_count=1\n");
		pipeline::MappingPipeline p(ini, AVM_SOURCE_DIR);
		const auto out = dir / ("read-ahead-" + readAhead);
		EXPECT_EQ(p.run(test::bonnRawlog(), out).frames, 400u);
		return out;
	};
	const auto inLoop = runWith("0"), ahead = runWith("3");
	for (const char* name : {"trajectory.txt", "map_low.bt"})
	{
		EXPECT_GT(test::fileBytes(inLoop / name).size(), 1000u) << name;
		EXPECT_EQ(test::fileBytes(inLoop / name), test::fileBytes(ahead / name)) << name;
	}
}

TEST(PipelineAsyncMapping, SameMapAsInsertingInTheLoop)
{
	// Synchronous detection on every third frame makes the regions, and the
	// frames they are added before, the same in both runs; the mapping thread
	// must not change the map, byte for byte, high-resolution tree included.
	const auto dir = test::scratchDir("pipeline-async-mapping");
	const auto runWith = [&](const std::string& async)
	{
		mrpt::config::CConfigFileMemory ini(
			"[pipeline]\npose_source=gt\ndetect_every_n=3\nasync_detection=false\npicture_size=0\nmax_frames=150\n"
			"async_mapping=" +
			async + "\n[detection]\nmodel=" + test::sharedFile("models/yolox_nano.onnx").string() +
			"\ninput_width=320\ninput_height=256\n[map]\nadaptiveOctoMap_count=1\n");
		pipeline::MappingPipeline p(ini, AVM_SOURCE_DIR);
		const auto out = dir / ("async-mapping-" + async);
		const auto summary = p.run(test::bonnRawlog(), out);
		EXPECT_EQ(summary.frames, 150u);
		EXPECT_TRUE(summary.switchFrame) << "the person appears before frame 150";
		return out;
	};
	const auto inLoop = runWith("false"), async = runWith("true");
	for (const char* name : {"map_low.bt", "map_high.bt", "detections.txt", "trajectory.txt"})
	{
		EXPECT_GT(test::fileBytes(inLoop / name).size(), 100u) << name;
		EXPECT_EQ(test::fileBytes(inLoop / name), test::fileBytes(async / name)) << name;
	}
}

// Same input, same output: the default configuration (odometry, detection on
// its worker thread, mapping on its own) twice on the same frames gives the
// same trajectory, persons and maps, byte for byte. Detections are applied
// detection_lag_frames after their frame, whenever the worker finished them.
TEST(PipelineDeterminism, TheSameRawlogGivesTheSameRun)
{
	const auto dir = test::scratchDir("pipeline-determinism");
	const auto runOnce = [&](const std::string& name)
	{
		auto ini = test::defaultIni();
		ini.write("pipeline", "max_frames", "160");
		ini.write("pipeline", "picture_size", "0");
		pipeline::MappingPipeline p(ini, AVM_SOURCE_DIR);
		const auto out = dir / name;
		const auto summary = p.run(test::bonnRawlog(), out);
		EXPECT_GT(summary.persons, 0u);
		return out;
	};
	const auto a = runOnce("a"), b = runOnce("b");
	for (const char* name : {"trajectory.txt", "detections.txt", "persons.csv", "map_low.bt", "map_high.bt"})
	{
		EXPECT_GT(test::fileBytes(a / name).size(), 100u) << name;
		EXPECT_EQ(test::fileBytes(a / name), test::fileBytes(b / name)) << name;
	}
}

TEST(PipelineTrackingLoss, FramesBridgedThroughALossArePlacedBetweenItsEnds)
{
	// Bonn frames 0-119 with the lens covered on frames 60-66 (a grey image,
	// no depth): the odometry loses the track there and finds it again at
	// frame 67. The trajectory avm-map writes has the covered frames on the
	// way from frame 59 to frame 67, still marked bridged.
	constexpr std::size_t first = 60, last = 66, frames = 120;
	const auto dir = test::scratchDir("pipeline-tracking-loss");
	const auto rawlog = dir / "covered.rawlog";
	fs::create_directory_symlink(io::imagesDirectoryOf(test::bonnRawlog()), dir / "covered_Images");
	{
		io::useImagesFolderOf(test::bonnRawlog());
		io::RawlogFrameReader reader(test::bonnRawlog(), /*loadImages=*/false);
		mrpt::io::CFileOutputStream file(rawlog.string());
		auto out = mrpt::serialization::archiveFrom(file);
		while (auto f = reader.next())
		{
			if (f->index >= frames) break;
			if (f->index >= first && f->index <= last) test::coverLens(*f->observation);
			io::writeFrame(out, *f->observation, f->groundTruth.value());
		}
	}
	auto ini = test::defaultIni();
	ini.write("pipeline", "picture_size", "0");
	ini.write("pipeline", "checkpoint_interval_s", "0");
	io::useImagesFolderOf(rawlog);
	pipeline::MappingPipeline p(ini, AVM_SOURCE_DIR);
	const auto out = dir / "run";
	EXPECT_EQ(p.run(rawlog, out).frames, frames);

	const auto trajectory = io::readTumTrajectory(out / "trajectory.txt");
	ASSERT_EQ(trajectory.size(), frames);
	const auto tracked = test::trackedFlagsIn(out / "trajectory_status.txt");
	ASSERT_EQ(tracked.size(), frames);
	for (std::size_t i = 0; i < frames; ++i) EXPECT_EQ(tracked[i], i >= first && i <= last ? 0 : 1) << i;

	const auto centre = [&](std::size_t i)
	{
		const auto& p = trajectory[i].pose;
		return Eigen::Vector3d(p.x(), p.y(), p.z());
	};
	const Eigen::Vector3d from = centre(first - 1), to = centre(last + 1);
	const Eigen::Vector3d step = to - from;
	// A step well above the 0.1 mm asked of the frames between gives the way a
	// direction (the ground truth moves 14 mm).
	ASSERT_GT(step.norm(), 0.005) << "the camera moved during the cover";
	double previous = 0;
	for (std::size_t i = first; i <= last; ++i)
	{
		const Eigen::Vector3d d = centre(i) - from;
		const double along = d.dot(step) / step.squaredNorm();
		EXPECT_LT((d - along * step).norm(), 1e-4) << "frame " << i << " off the way from frame 59 to frame 67";
		EXPECT_GT(along, previous) << i;
		EXPECT_LT(along, 1.0) << i;
		previous = along;
	}
	EXPECT_NE(test::fileBytes(out / "avm-map.log").find("odometry back after 7 lost frames"), std::string::npos);
}
