// Checkpoints and resume on the real Bonn sequence with the default
// configuration (odometry, detection on its worker thread, per-person
// regions), and with the detector scheduled on change: a run stopped in the
// middle and resumed from its checkpoint ends with the same files, byte for
// byte, as a run that was never stopped.
// scripts/kill-test.sh does the same with SIGKILL at random instants.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/io/vector_loadsave.h>
#include <mrpt/serialization/CArchive.h>

#include <atomic>
#include <fstream>
#include <functional>
#include <map>
#include <optional>

#include "DefaultIni.h"
#include "SerializationCopy.h"
#include "TestData.h"
#include "avm/io/RunFolder.h"
#include "avm/plugin/CAdaptiveOctoMap.h"
#include "avm/pipeline/CheckpointWriter.h"
#include "avm/pipeline/MappingPipeline.h"

using namespace avm;
namespace fs = std::filesystem;

namespace
{
/** The default configuration on 150 frames, without pictures. */
mrpt::config::CConfigFileMemory defaultIniOn150Frames()
{
	auto ini = test::defaultIni();
	ini.write("pipeline", "max_frames", "150");
	ini.write("pipeline", "picture_size", "0");
	return ini;
}

using Progress = std::function<void(double, std::size_t)>;

/** A run as avm-map makes it: with the checkpoints of its ini connected. */
pipeline::RunSummary runWithCheckpoints(const mrpt::config::CConfigFileBase& ini, const fs::path& out,
	const std::atomic<bool>* stop = nullptr, const Progress& progress = {})
{
	pipeline::MappingPipeline p(ini, AVM_SOURCE_DIR);
	pipeline::CheckpointWriter checkpoints(out, p.options().checkpointIntervalSeconds);
	p.addObserver(checkpoints);
	return p.run(test::bonnRawlog(), out, stop, progress);
}

/** A resume as avm-map makes it: from the checkpoint of out's writer, connected. */
pipeline::RunSummary resumeWithCheckpoints(
	pipeline::MappingPipeline& p, const fs::path& out, const Progress& progress = {})
{
	pipeline::CheckpointWriter checkpoints(out, p.options().checkpointIntervalSeconds);
	p.addObserver(checkpoints);
	return p.resume(checkpoints.file(), out, nullptr, progress);
}

const char* const kRunFiles[] = {"trajectory.txt", "trajectory_status.txt", "detections.txt", "persons.csv",
	"person_shapes.ply", "map_low.bt", "map_high.bt"};

/** All of the map's state (trees, regions, person tracks, surface sketch). */
std::string serialized(const CAdaptiveOctoMap& map) { return test::serializedBytes(map); }

/** The default configuration, [pipeline] detection_schedule = `schedule`,
 *  stopped at frame 100 and resumed, against the same run never stopped. */
void expectAResumedRunToEndLikeARunNeverStopped(const std::string& schedule)
{
	const auto dir = test::scratchDir("pipeline-checkpoint-" + schedule);
	auto ini = defaultIniOn150Frames();
	ini.write("pipeline", "detection_schedule", schedule);
	ini.write("pipeline", "checkpoint_interval_s", "0");
	// The map made again at the end: the resumed run's rebuild replays the
	// persons and frames of the part before its checkpoint too.
	ini.write("pipeline", "rebuild_map", "always");
	const auto uninterrupted = dir / "uninterrupted";
	pipeline::MappingPipeline(ini, AVM_SOURCE_DIR).run(test::bonnRawlog(), uninterrupted);
	EXPECT_FALSE(fs::exists(io::RunFolder(uninterrupted).checkpoint())) << "checkpoint_interval_s = 0 writes none";

	// Stopped at frame 100, when persons and their regions are in the map
	// and detections are in flight; checkpoints every 0.2 s before that.
	ini.write("pipeline", "checkpoint_interval_s", "0.2");
	const auto stopped = dir / "stopped";
	std::atomic<bool> stop{false};
	const auto first = runWithCheckpoints(ini, stopped, &stop,
		[&](double, std::size_t frames)
		{
			if (frames == 100) stop = true;
		});
	ASSERT_TRUE(first.interrupted);
	EXPECT_TRUE(fs::exists(io::RunFolder(stopped).checkpoint())) << "an interrupted run removed its checkpoint";
	EXPECT_EQ(first.frames, 100u);
	EXPECT_GE(first.checkpoint.count, 3u) << "before the first frame, at least one on the way, after the last";
	EXPECT_GT(first.persons, 0u);

	const auto checkpointed = pipeline::CheckpointWriter(stopped).checkpointedRun();
	EXPECT_EQ(checkpointed.rawlog, fs::absolute(test::bonnRawlog()));
	mrpt::config::CConfigFileMemory resumedIni(checkpointed.ini);
	EXPECT_EQ(resumedIni.read_int("pipeline", "max_frames", 0), 150);
	pipeline::MappingPipeline resumedPipeline(resumedIni, AVM_SOURCE_DIR);
	const auto resumed = resumeWithCheckpoints(resumedPipeline, stopped);
	ASSERT_TRUE(resumed.resumedAfterFrame);
	EXPECT_EQ(*resumed.resumedAfterFrame, 99u);
	EXPECT_EQ(resumed.frames, 150u);
	EXPECT_FALSE(resumed.interrupted);
	EXPECT_FALSE(fs::exists(io::RunFolder(stopped).checkpoint())) << "a finished run keeps its checkpoint";
	EXPECT_FALSE(first.mapRebuild) << "an interrupted run is not rebuilt";
	ASSERT_TRUE(resumed.mapRebuild);
	EXPECT_EQ(resumed.mapRebuild->frames, 150u);
	for (const char* name : kRunFiles)
	{
		EXPECT_GT(test::fileBytes(uninterrupted / name).size(), 100u) << name;
		EXPECT_EQ(test::fileBytes(uninterrupted / name), test::fileBytes(stopped / name)) << name;
	}
}
}  // namespace

TEST(PipelineCheckpoint, AResumedRunEndsLikeARunThatWasNeverStopped)
{
	expectAResumedRunToEndLikeARunNeverStopped("fixed");
}

// The schedule's last look (the detector's last frame, sampled) goes into the
// checkpoint: the resumed run calls the detector on the same frames.
TEST(PipelineCheckpoint, AResumedRunWithTheDetectorOnChangeEndsLikeARunThatWasNeverStopped)
{
	expectAResumedRunToEndLikeARunNeverStopped("on_change");
}

TEST(PipelineCheckpoint, AMissingOrDamagedCheckpointIsNamedAndNothingIsWritten)
{
	const auto dir = test::scratchDir("pipeline-checkpoint-damaged");
	const auto empty = dir / "empty";
	fs::create_directories(empty);
	try
	{
		pipeline::CheckpointWriter(empty).checkpointedRun();
		FAIL() << "no checkpoint, no error";
	}
	catch (const std::runtime_error& e)
	{
		EXPECT_NE(
			std::string(e.what()).find((empty / "checkpoint.bin").string() + ": no checkpoint"), std::string::npos)
			<< e.what();
	}

	// An interrupted run: a finished one removes its checkpoint.
	auto ini = defaultIniOn150Frames();
	ini.write("pipeline", "detect_every_n", "0");
	const auto run = dir / "run";
	std::atomic<bool> stop{false};
	runWithCheckpoints(ini, run, &stop, [&](double, std::size_t frames) { stop = frames >= 10; });
	const auto file = io::RunFolder(run).checkpoint();
	const std::string whole = test::fileBytes(file);
	ASSERT_GT(whole.size(), 1000u);
	fs::remove(run / "trajectory.txt");
	std::ofstream(file, std::ios::binary | std::ios::trunc) << whole.substr(0, whole.size() / 2);
	pipeline::MappingPipeline p(ini, AVM_SOURCE_DIR);
	try
	{
		p.resume(file, run);
		FAIL() << "a checkpoint cut in half resumed";
	}
	catch (const std::runtime_error& e)
	{
		EXPECT_NE(std::string(e.what()).find(file.string() + ": cannot resume from this checkpoint"), std::string::npos)
			<< e.what();
	}
	EXPECT_FALSE(fs::exists(run / "trajectory.txt")) << "a failed resume writes no outputs";
}

// The files at the end are not enough: what a resumed map gets wrong can heal
// before the run ends (space that moves between the trees again), or live
// where no output file looks (the surface sketch). So the map itself, after
// every frame after the resume. Stopped after frame 79: regions are active,
// and at frame 80 a detection is applied and its persons' regions move, so
// the resumed map must change tree for space it has never changed itself.
// Mapping in the loop (async_mapping = false) so that the map can be read
// between two frames; the default configuration otherwise.
TEST(PipelineCheckpoint, AResumedMapIsTheUninterruptedMapAfterEveryFrame)
{
	constexpr std::size_t kStopAfter = 80, kFrames = 90;
	const auto dir = test::scratchDir("pipeline-checkpoint-every-frame");
	auto ini = defaultIniOn150Frames();
	ini.write("pipeline", "max_frames", std::to_string(kFrames));
	ini.write("pipeline", "async_mapping", "false");
	ini.write("pipeline", "checkpoint_interval_s", "0");

	std::map<std::size_t, std::string> uninterrupted;  // frames mapped -> the map then
	{
		pipeline::MappingPipeline p(ini, AVM_SOURCE_DIR);
		p.run(test::bonnRawlog(), dir / "uninterrupted", nullptr,
			[&](double, std::size_t frames)
			{
				if (frames > kStopAfter) uninterrupted[frames] = serialized(p.map());
			});
	}
	ASSERT_EQ(uninterrupted.size(), kFrames - kStopAfter);

	ini.write("pipeline", "checkpoint_interval_s", "1000");  // one before the first frame, one after the last
	const auto stopped = dir / "stopped";
	std::atomic<bool> stop{false};
	runWithCheckpoints(ini, stopped, &stop,
		[&](double, std::size_t frames)
		{
			if (frames == kStopAfter) stop = true;
		});

	pipeline::MappingPipeline resumedPipeline(ini, AVM_SOURCE_DIR);
	std::size_t compared = 0;
	std::optional<std::size_t> firstDifference;
	const auto resumed = resumeWithCheckpoints(resumedPipeline, stopped,
		[&](double, std::size_t frames)
		{
			const auto it = uninterrupted.find(frames);
			if (it == uninterrupted.end()) return;
			++compared;
			if (!firstDifference && serialized(resumedPipeline.map()) != it->second) firstDifference = frames;
		});
	ASSERT_TRUE(resumed.resumedAfterFrame);
	EXPECT_EQ(*resumed.resumedAfterFrame, kStopAfter - 1);
	EXPECT_FALSE(resumedPipeline.map().highResolutionRegions().empty()) << "the test needs persons' regions";
	EXPECT_EQ(compared, kFrames - kStopAfter);
	EXPECT_FALSE(firstDifference) << "the resumed map differs from the uninterrupted one after " << *firstDifference
								  << " frames";
	for (const char* name : kRunFiles)
		EXPECT_TRUE(test::fileBytes(dir / "uninterrupted" / name) == test::fileBytes(stopped / name)) << name;
}
