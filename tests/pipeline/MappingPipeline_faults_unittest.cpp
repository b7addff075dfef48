// Faults: avm-map killed at any moment leaves the previous complete outputs or
// the new complete ones, never a truncated file; Ctrl-C stops and saves.
#include <gtest/gtest.h>
#include <mrpt/containers/yaml.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <octomap/OcTree.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/serialization/CArchive.h>

#include <chrono>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "TestData.h"
#include "avm/io/RawlogFrameReader.h"
#include "avm/io/Trajectory.h"
#include "avm/plugin/CAdaptiveOctoMap.h"
#include "avm/pipeline/MappingPipeline.h"

extern char** environ;

using namespace avm;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace
{
/** Starts avm-map on the first `frames` Bonn frames (ground truth, no detector). */
pid_t startMap(const fs::path& out, int frames = 90)
{
	const std::string bin = test::binary("avm-map").string(), ini = std::string(AVM_SOURCE_DIR) + "/ini/default.ini",
					  rawlog = test::bonnRawlog().string(), outDir = out.string();
	std::vector<std::string> args = {bin, "-q", "-c", ini, "-s", "pipeline:detect_every_n=0", "-s",
		"pipeline:pose_source=gt", "-s", "pipeline:max_frames=" + std::to_string(frames), "-r", rawlog, "-o", outDir};
	std::vector<char*> argv;
	for (auto& a : args) argv.push_back(a.data());
	argv.push_back(nullptr);
	posix_spawn_file_actions_t actions;
	posix_spawn_file_actions_init(&actions);
	posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
	posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
	pid_t pid = 0;
	const int err = posix_spawn(&pid, bin.c_str(), &actions, nullptr, argv.data(), environ);
	posix_spawn_file_actions_destroy(&actions);
	if (err != 0) throw std::runtime_error("cannot start " + bin);
	return pid;
}

int waitFor(pid_t pid)
{
	int status = 0;
	waitpid(pid, &status, 0);
	return status;
}

/** Every output that exists is complete: it loads. Returns how many exist. */
int expectCompleteOutputs(const fs::path& out, const std::string& when)
{
	int present = 0;
	const auto check = [&](const char* name, auto&& loads)
	{
		if (!fs::exists(out / name)) return;
		++present;
		EXPECT_TRUE(loads(out / name)) << name << " is damaged " << when;
	};
	const auto loadTree = [](const fs::path& f)
	{
		octomap::OcTree t(0.1);
		return t.readBinary(f.string());
	};
	check("map_low.bt", loadTree);
	check("map_high.bt", loadTree);
	check("map.3Dscene",
		[](const fs::path& f)
		{
			mrpt::opengl::COpenGLScene scene;
			return scene.loadFromFile(f.string());
		});
	check("stats.json",
		[](const fs::path& f)
		{
			try
			{
				return mrpt::containers::yaml::FromFile(f.string())["frames"].as<int>() > 0;
			}
			catch (const std::exception&)
			{
				return false;
			}
		});
	check("trajectory.txt",
		[](const fs::path& f)
		{
			try
			{
				return !io::readTumTrajectory(f).empty();
			}
			catch (const std::exception&)
			{
				return false;
			}
		});
	check("map_top.png", [](const fs::path& f) { return !cv::imread(f.string()).empty(); });
	return present;
}
}  // namespace

TEST(MappingPipelineFaults, KilledAtAnyMomentLeavesCompleteOutputs)
{
	const auto out = test::scratchDir("map-kill") / "out";
	const auto start = Clock::now();
	ASSERT_EQ(WEXITSTATUS(waitFor(startMap(out))), 0);
	const double runSeconds = std::chrono::duration<double>(Clock::now() - start).count();
	ASSERT_EQ(expectCompleteOutputs(out, "after a complete run"), 6);

	// Kill during the run and around the moment the outputs are written.
	for (const double fraction : {0.2, 0.6, 0.9, 0.95, 0.98, 1.0, 1.02, 1.05})
	{
		const pid_t pid = startMap(out);
		std::this_thread::sleep_for(std::chrono::duration<double>(fraction * runSeconds));
		kill(pid, SIGKILL);
		waitFor(pid);
		EXPECT_EQ(expectCompleteOutputs(out, "after SIGKILL at " + std::to_string(fraction) + " of the run"), 6);
	}
	// The next run clears the temporaries the killed runs left behind.
	ASSERT_EQ(WEXITSTATUS(waitFor(startMap(out))), 0);
	for (const auto& e : fs::directory_iterator(out))
		EXPECT_EQ(e.path().filename().string().find(".partial-"), std::string::npos) << e.path();
}

TEST(MappingPipelineFaults, InterruptStopsAndSavesWhatWasMapped)
{
	const auto out = test::scratchDir("map-interrupt") / "out";
	const pid_t pid = startMap(out, 300);
	// The run writes its first checkpoint once its signal handler is installed:
	// a fixed wait sent SIGINT before that on a loaded machine, killing the
	// program instead of stopping it. Then let some frames be mapped.
	const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
	while (!fs::exists(out / "checkpoint.bin") && std::chrono::steady_clock::now() < deadline)
		std::this_thread::sleep_for(std::chrono::milliseconds(20));
	ASSERT_TRUE(fs::exists(out / "checkpoint.bin")) << "the run wrote no checkpoint in 120 s";
	std::this_thread::sleep_for(std::chrono::milliseconds(500));
	kill(pid, SIGINT);
	const int status = waitFor(pid);
	ASSERT_TRUE(WIFEXITED(status));
	EXPECT_EQ(WEXITSTATUS(status), 130);
	EXPECT_EQ(expectCompleteOutputs(out, "after Ctrl-C"), 6);
	const auto stats = mrpt::containers::yaml::FromFile((out / "stats.json").string());
	EXPECT_TRUE(stats["interrupted"].as<bool>());
	EXPECT_LT(stats["frames"].as<int>(), 300);
}

TEST(MappingPipelineFaults, NanPosesAndEmptyDepthNeverReachTheMap)
{
	// Three real frames: the second with a NaN ground-truth pose, the third
	// with depth all zeros. The map must equal the map of the first alone.
	const auto dir = test::scratchDir("map-nan");
	const auto src = test::bonnRawlog();
	fs::create_directory_symlink(src.parent_path() / (src.stem().string() + "_Images"), dir / "three_Images");
	{
		io::RawlogFrameReader reader(src);
		mrpt::io::CFileGZOutputStream file((dir / "three.rawlog").string());
		auto out = mrpt::serialization::archiveFrom(file);
		for (int i = 0; i < 3; ++i)
		{
			auto f = reader.next();
			ASSERT_TRUE(f && f->groundTruth);
			auto pose = mrpt::obs::CObservationRobotPose::Create();
			pose->timestamp = f->observation->timestamp;
			auto p = *f->groundTruth;
			if (i == 1) p.x(std::numeric_limits<double>::quiet_NaN());
			pose->pose = mrpt::poses::CPose3DPDFGaussian(p);
			if (i == 2) f->observation->rangeImage.fill(0);
			out << *f->observation << *pose;
		}
	}
	const auto runOn = [&](const std::string& maxFrames)
	{
		mrpt::config::CConfigFileMemory ini(
			"[pipeline]\npose_source=gt\ndetect_every_n=0\npicture_size=0\nmax_frames=" + maxFrames +
			"\n[map]\nadaptiveOctoMap_count=1\n");
		pipeline::MappingPipeline p(ini, AVM_SOURCE_DIR);
		io::useImagesFolderOf(dir / "three.rawlog");
		const auto summary = p.run(dir / "three.rawlog", dir / ("out" + maxFrames));
		return std::make_pair(summary, p.map().lowResolutionStats());
	};
	const auto [all, allStats] = runOn("0");
	const auto [first, firstStats] = runOn("1");
	EXPECT_EQ(all.skippedFrames, 1u) << "the NaN pose frame";
	EXPECT_EQ(all.frames, 2u);
	EXPECT_GT(firstStats.occupiedLeaves, 100u);
	EXPECT_EQ(allStats.occupiedLeaves, firstStats.occupiedLeaves);
	EXPECT_EQ(allStats.freeLeaves, firstStats.freeLeaves);
}
