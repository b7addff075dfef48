// The whole application on the real Bonn sequence with ground-truth poses.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/containers/yaml.h>
#include <mrpt/io/vector_loadsave.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <octomap/OcTree.h>

#include <fstream>
#include <mutex>
#include <sstream>

#include "TestData.h"
#include "avm/io/RawlogFrameReader.h"
#include "avm/io/RgbdFrame.h"
#include "avm/io/Trajectory.h"
#include "avm/maps/CAdaptiveOctoMap.h"
#include "avm/pipeline/MappingPipeline.h"

using namespace avm;
namespace fs = std::filesystem;

namespace
{
struct PersonDetection
{
	std::size_t frame;
	double x, y, w, h;
};

std::vector<PersonDetection> personsIn(const fs::path& detectionsTxt)
{
	std::ifstream in(detectionsTxt);
	std::vector<PersonDetection> out;
	for (std::string line; std::getline(in, line);)
	{
		if (line.empty() || line[0] == '#') continue;
		std::istringstream ss(line);
		PersonDetection d;
		double t, score;
		std::string cls;
		ss >> d.frame >> t >> cls >> score >> d.x >> d.y >> d.w >> d.h;
		if (cls == "person") out.push_back(d);
	}
	return out;
}

struct DefaultRun
{
	fs::path out;
	pipeline::RunSummary summary;
};

/** One run of the default configuration, shared by the tests of a process.
 *  Not SetUpTestSuite: gtest reports its exceptions as skipped tests. The
 *  folder is named after the test because ctest -j runs each test in its own
 *  process, side by side. */
const DefaultRun& defaultRun()
{
	static DefaultRun run;
	static std::once_flag once;
	std::call_once(once, [] {
		run.out = test::scratchDir(
			std::string("pipeline-gt-") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
		// ini/default.ini as shipped, with the model of ../shared: the tests
		// do not depend on scripts/get-data.sh having been run.
		mrpt::config::CConfigFileMemory ini;
		ini.setContent(mrpt::io::file_get_contents((fs::path(AVM_SOURCE_DIR) / "ini/default.ini").string()));
		ini.write("detection", "model", test::sharedFile("models/yolox_nano.onnx").string());
		pipeline::MappingPipeline p(ini, AVM_SOURCE_DIR);
		p.setPoseSource(pipeline::PoseSource::GroundTruth);
		run.summary = p.run(test::bonnRawlog(), run.out);
	});
	return run;
}
}  // namespace

TEST(PipelineOnBonn, MapsEveryFrameAndSwitchesAfterThePersonAppears)
{
	const auto& [out, summary] = defaultRun();
	EXPECT_EQ(summary.frames, 300u);
	const auto persons = personsIn(out / "detections.txt");
	ASSERT_FALSE(persons.empty()) << "no person detected in the whole sequence";
	// People walk in after frame ~70: the switch follows the first detection.
	ASSERT_TRUE(summary.switchFrame);
	EXPECT_GE(*summary.switchFrame, persons.front().frame);
	EXPECT_GE(*summary.switchFrame, 50u);
	EXPECT_LE(*summary.switchFrame, persons.front().frame + 10);
	EXPECT_GT(summary.regions, 0u);
}

TEST(PipelineOnBonn, ARegionEnclosesThePerson)
{
	const auto& [out, summary] = defaultRun();
	// The 3D point at the centre of a detected person's box, placed with that
	// frame's ground truth, lies inside one of the map's high-resolution regions.
	const auto persons = personsIn(out / "detections.txt");
	ASSERT_FALSE(persons.empty());
	const auto& target = persons[persons.size() / 2];
	io::RawlogFrameReader reader(test::bonnRawlog());
	std::optional<io::RgbdFrame> frame;
	while ((frame = reader.next()) && frame->index != target.frame) {}
	ASSERT_TRUE(frame && frame->groundTruth);
	const cv::Mat depth = io::depthInMetres(*frame->observation);
	const auto& K = frame->observation->cameraParams;
	// Median depth of the box's central third: the person, not the background.
	std::vector<float> ds;
	for (int v = int(target.y + target.h / 3); v < int(target.y + 2 * target.h / 3); ++v)
		for (int u = int(target.x + target.w / 3); u < int(target.x + 2 * target.w / 3); ++u)
			if (v >= 0 && u >= 0 && v < depth.rows && u < depth.cols && depth.at<float>(v, u) > 0)
				ds.push_back(depth.at<float>(v, u));
	ASSERT_GT(ds.size(), 50u);
	std::nth_element(ds.begin(), ds.begin() + ds.size() / 2, ds.end());
	const double d = ds[ds.size() / 2], u = target.x + target.w / 2, v = target.y + target.h / 2;
	const auto p = frame->groundTruth->composePoint({(u - K.cx()) * d / K.fx(), (v - K.cy()) * d / K.fy(), d});

	const auto yaml = mrpt::containers::yaml::FromFile((out / "stats.json").string());
	bool inside = false;
	const auto regions = yaml["regions"];
	for (int i = 0; i < static_cast<int>(regions.size()); ++i)
	{
		const auto lo = regions(i)["min"], hi = regions(i)["max"];
		bool in = true;
		for (int k = 0; k < 3; ++k)
		{
			const double v = k == 0 ? p.x : (k == 1 ? p.y : p.z);
			in &= lo(k).as<double>() <= v && v <= hi(k).as<double>();
		}
		inside |= in;
	}
	EXPECT_TRUE(inside) << "person at " << p.asString() << " (frame " << target.frame << ") in no region";
}

TEST(PipelineOnBonn, AllOutputsExistAndLoad)
{
	const auto& [out, summary] = defaultRun();
	for (const char* name : {"map_low.bt", "map_high.bt", "map.3Dscene", "trajectory.txt", "detections.txt",
							 "stats.json", "map_top.png", "map_perspective.png", "avm-map.log"})
		EXPECT_TRUE(fs::exists(out / name)) << name;

	octomap::OcTree low(0.1), high(0.1);
	ASSERT_TRUE(low.readBinary((out / "map_low.bt").string()));
	ASSERT_TRUE(high.readBinary((out / "map_high.bt").string()));
	// People walk through most of the near field here, so their merged
	// region holds most of the map; the low tree keeps the rest.
	EXPECT_GT(low.size(), 10u);
	EXPECT_GT(high.size(), 1000u);
	EXPECT_DOUBLE_EQ(low.getResolution(), 0.20);
	EXPECT_DOUBLE_EQ(high.getResolution(), 0.05);

	mrpt::opengl::COpenGLScene scene;
	ASSERT_TRUE(scene.loadFromFile((out / "map.3Dscene").string()));
	ASSERT_TRUE(scene.getViewport("main"));
	EXPECT_GT(scene.getViewport("main")->size(), 0u) << "empty scene";

	const auto stats = mrpt::containers::yaml::FromFile((out / "stats.json").string());
	EXPECT_EQ(stats["frames"].as<int>(), 300);
	EXPECT_GT(stats["fps"].as<double>(), 0.0);
	// Detection, odometry-free mapping and reading of 300 frames take well
	// over a millisecond of CPU a frame; the whole run is in the figure.
	EXPECT_GT(stats["cpu_ms_per_frame"].as<double>(), 1.0);
	const double stolen = stats["cpu_stolen_percent"].as<double>();
	EXPECT_TRUE(stolen >= 0 && stolen <= 100) << stolen;
	for (const char* stage : {"detection", "map"})
		EXPECT_GT(stats["stages"][stage]["mean_ms"].as<double>(), 0.0) << stage;
	EXPECT_GT(stats["map"]["low"]["occupied_voxels"].as<int>(), 0);
	EXPECT_GT(stats["map"]["high"]["occupied_voxels"].as<int>(), 0);
	EXPECT_EQ(stats["switch_frame"].as<int>(), static_cast<int>(*summary.switchFrame));

	const auto trajectory = io::readTumTrajectory(out / "trajectory.txt");
	EXPECT_EQ(trajectory.size(), 300u);
	const auto gt = io::readTumTrajectory(test::bonnRawlog().parent_path() / "bonn_sub300_groundtruth.txt");
	ASSERT_EQ(gt.size(), trajectory.size());
	EXPECT_LT((trajectory.back().pose - gt.back().pose).translation().norm(), 1e-5)
		<< "--poses gt must write the ground truth as the trajectory";
}

TEST(PipelineReadAhead, SameFramesInTheSameOrderAsReadingInTheLoop)
{
	// Two replays cut short at frame 400: the reader thread crosses a replay
	// boundary and is stopped mid-sequence. Its map and trajectory must be
	// those of reading on the loop's thread, byte for byte.
	const auto dir = test::scratchDir("pipeline-read-ahead");
	const auto runWith = [&](const std::string& readAhead) {
		mrpt::config::CConfigFileMemory ini(
			"[pipeline]\npose_source=gt\ndetect_every_n=0\npicture_size=0\nrepeat=2\nmax_frames=400\n"
			"read_ahead_frames=" + readAhead + "\n[map]\nadaptiveOctoMap_count=1\n");
		pipeline::MappingPipeline p(ini, AVM_SOURCE_DIR);
		const auto out = dir / ("read-ahead-" + readAhead);
		EXPECT_EQ(p.run(test::bonnRawlog(), out).frames, 400u);
		return out;
	};
	const auto inLoop = runWith("0"), ahead = runWith("3");
	const auto bytes = [](const fs::path& file) {
		std::ifstream in(file, std::ios::binary);
		return std::string(std::istreambuf_iterator<char>(in), {});
	};
	for (const char* name : {"trajectory.txt", "map_low.bt"})
	{
		EXPECT_GT(bytes(inLoop / name).size(), 1000u) << name;
		EXPECT_EQ(bytes(inLoop / name), bytes(ahead / name)) << name;
	}
}

TEST(PipelineAsyncMapping, SameMapAsInsertingInTheLoop)
{
	// Synchronous detection on every third frame makes the regions, and the
	// frames they are added before, the same in both runs; the mapping thread
	// must not change the map, byte for byte, high-resolution tree included.
	const auto dir = test::scratchDir("pipeline-async-mapping");
	const auto runWith = [&](const std::string& async) {
		mrpt::config::CConfigFileMemory ini(
			"[pipeline]\npose_source=gt\ndetect_every_n=3\nasync_detection=false\npicture_size=0\nmax_frames=150\n"
			"async_mapping=" + async + "\n[detection]\nmodel=" + test::sharedFile("models/yolox_nano.onnx").string() +
			"\ninput_width=320\ninput_height=256\n[map]\nadaptiveOctoMap_count=1\n");
		pipeline::MappingPipeline p(ini, AVM_SOURCE_DIR);
		const auto out = dir / ("async-mapping-" + async);
		const auto summary = p.run(test::bonnRawlog(), out);
		EXPECT_EQ(summary.frames, 150u);
		EXPECT_TRUE(summary.switchFrame) << "the person appears before frame 150";
		return out;
	};
	const auto inLoop = runWith("false"), async = runWith("true");
	const auto bytes = [](const fs::path& file) {
		std::ifstream in(file, std::ios::binary);
		return std::string(std::istreambuf_iterator<char>(in), {});
	};
	for (const char* name : {"map_low.bt", "map_high.bt", "detections.txt", "trajectory.txt"})
	{
		EXPECT_GT(bytes(inLoop / name).size(), 100u) << name;
		EXPECT_EQ(bytes(inLoop / name), bytes(async / name)) << name;
	}
}
