// The whole application on the real Bonn sequence with ground-truth poses:
// one run of the default configuration, which every test here reads (the
// tests run in one process, tests/pipeline/CMakeLists.txt).
#include <gtest/gtest.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/containers/yaml.h>
#include <mrpt/io/vector_loadsave.h>
#include <mrpt/opengl/COctoMapVoxels.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CPointCloud.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/serialization/CArchive.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

#include "DefaultIni.h"
#include "TestData.h"
#include "TrajectoryStatus.h"
#include "avm/persons/PersonColour.h"
#include "avm/io/DepthCamera.h"
#include "avm/io/RawlogFrameReader.h"
#include "avm/io/RgbdFrame.h"
#include "avm/io/RunFolder.h"
#include "avm/io/Trajectory.h"
#include "avm/plugin/CAdaptiveOctoMap.h"
#include "avm/persons/PersonsCsv.h"
#include "avm/pipeline/MappingPipeline.h"

using namespace avm;
namespace fs = std::filesystem;

namespace
{
struct PersonDetection
{
	std::size_t frame;
	double x, y, w, h;
	/** The person it was taken for and the region it placed, if any. */
	std::optional<std::uint32_t> personId;
	mrpt::math::TBoundingBox region;
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
		std::string cls, bar;
		ss >> d.frame >> t >> cls >> score >> d.x >> d.y >> d.w >> d.h >> bar;
		std::uint32_t id = 0;
		if (ss >> id >> d.region.min.x >> d.region.min.y >> d.region.min.z >> d.region.max.x >> d.region.max.y >>
			d.region.max.z)
			d.personId = id;
		if (cls == "person") out.push_back(d);
	}
	return out;
}

/** [m^3] The occupied leaves' volume of a tree. */
double occupiedVolume(const octomap::OcTree& t)
{
	double v = 0;
	for (auto it = t.begin_leafs(); it != t.end_leafs(); ++it)
		if (t.isNodeOccupied(*it)) v += std::pow(it.getSize(), 3);
	return v;
}

/** [m^3] The voxels' volume of one set of a scene's voxels. */
double occupiedVolume(const mrpt::opengl::COctoMapVoxels& voxels, std::size_t set)
{
	double v = 0;
	for (std::size_t i = 0; i < voxels.getVoxelCount(set); ++i) v += std::pow(voxels.getVoxel(set, i).side_length, 3);
	return v;
}

struct FrameInMap
{
	std::size_t points = 0, exact = 0, near = 0;
};

/** The sub300 rawlog's first frame against a map's trees: its depth points
 *  (one pixel in 8 each way, 0.3-4.5 m: within the map's 5 m range) placed
 *  at its ground-truth pose, how many fall in an occupied voxel of either
 *  tree, and how many in or next to one (a point on a voxel's face). */
FrameInMap firstFrameInMap(const octomap::OcTree& low, const octomap::OcTree& high)
{
	io::RawlogFrameReader reader(test::bonnRawlog());
	const auto first = reader.next();
	if (!first || !first->groundTruth) throw std::runtime_error("the first frame has no ground truth");
	const auto& obs = *first->observation;
	const auto camera = io::DepthCamera::of(obs);
	const auto sensor = *first->groundTruth + obs.sensorPose;
	const auto occupied = [](const octomap::OcTree& t, const mrpt::math::TPoint3D& p, int reach)
	{
		const double r = t.getResolution();
		for (int dx = -reach; dx <= reach; ++dx)
			for (int dy = -reach; dy <= reach; ++dy)
				for (int dz = -reach; dz <= reach; ++dz)
				{
					const auto* n = t.search(p.x + dx * r, p.y + dy * r, p.z + dz * r);
					if (n && t.isNodeOccupied(n)) return true;
				}
		return false;
	};
	FrameInMap out;
	for (int v = 0; v < camera.height; v += 8)
		for (int u = 0; u < camera.width; u += 8)
		{
			const double d = obs.rangeImage(v, u) * obs.rangeUnits;
			if (d <= 0.3 || d >= 4.5) continue;
			const auto p = sensor.composePoint(camera.unproject(u, v, d));
			++out.points;
			out.exact += occupied(low, p, 0) || occupied(high, p, 0);
			out.near += occupied(low, p, 1) || occupied(high, p, 1);
		}
	return out;
}

struct DefaultRun
{
	fs::path out;
	pipeline::RunSummary summary;
};

/** One run of the default configuration, shared by the tests of the
 *  process. Not SetUpTestSuite: gtest reports its exceptions as skipped
 *  tests. The folder is named after the first test, which a run of one test
 *  (--gtest_filter) makes its own. */
const DefaultRun& defaultRun()
{
	static DefaultRun run;
	static std::once_flag once;
	std::call_once(once,
		[]
		{
			run.out = test::scratchDir(
				std::string("pipeline-gt-") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
			pipeline::MappingPipeline p(test::defaultIni(), AVM_SOURCE_DIR);
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

TEST(PipelineOnBonn, EachSightingPlacesItsPersonsRegionAroundThePerson)
{
	const auto& [out, summary] = defaultRun();
	// The 3D point at the centre of a detected person's box, placed with that
	// frame's ground truth, lies inside the region that detection placed.
	auto persons = personsIn(out / "detections.txt");
	persons.erase(
		std::remove_if(persons.begin(), persons.end(), [](const auto& p) { return !p.personId; }), persons.end());
	ASSERT_GT(persons.size(), 20u);
	io::RawlogFrameReader reader(test::bonnRawlog());
	std::size_t checked = 0, inside = 0;
	for (std::size_t i = 0; i < persons.size(); i += persons.size() / 10)
	{
		const auto& target = persons[i];
		std::optional<io::RgbdFrame> frame;
		while ((frame = reader.next()) && frame->index != target.frame)
		{
		}
		ASSERT_TRUE(frame && frame->groundTruth);
		const cv::Mat depth = io::depthInMetres(*frame->observation);
		const auto& K = frame->observation->cameraParams;
		// Median depth of the box's central third: the person, not the background.
		std::vector<float> ds;
		for (int v = int(target.y + target.h / 3); v < int(target.y + 2 * target.h / 3); ++v)
			for (int u = int(target.x + target.w / 3); u < int(target.x + 2 * target.w / 3); ++u)
				if (v >= 0 && u >= 0 && v < depth.rows && u < depth.cols && depth.at<float>(v, u) > 0)
					ds.push_back(depth.at<float>(v, u));
		if (ds.size() < 50) continue;
		std::nth_element(ds.begin(), ds.begin() + ds.size() / 2, ds.end());
		const double d = ds[ds.size() / 2], u = target.x + target.w / 2, v = target.y + target.h / 2;
		const auto p = frame->groundTruth->composePoint({(u - K.cx()) * d / K.fx(), (v - K.cy()) * d / K.fy(), d});
		++checked;
		if (target.region.containsPoint(p))
			++inside;
		else
			std::cout << "person at " << p.asString() << " (frame " << target.frame << ") outside its region "
					  << target.region.asString() << "\n";
	}
	EXPECT_GE(checked, 8u);
	EXPECT_GE(inside, checked - 1) << "a person's box may cover a nearer object now and then";
}

// Persons as tracks on the real run: a person crossing the view keeps one
// id, and every track lies in the mapped space.
TEST(PipelineOnBonn, PersonTracksCrossTheViewAndLieInTheMappedSpace)
{
	const auto& [out, summary] = defaultRun();
	const auto tracks = persons::readPersonsCsv(out / "persons.csv");
	ASSERT_FALSE(tracks.empty());
	EXPECT_EQ(tracks.size(), summary.persons);
	// persons.csv lists the tracks confirmed by track_min_sightings sightings,
	// each with as many as detections.txt gives it; a track seen less often
	// placed its region but is no person.
	const auto minSightings = static_cast<std::size_t>(
		test::defaultIni().read_int("map_adaptiveOctoMap_00_insertOpts", "track_min_sightings", 0));
	ASSERT_GE(minSightings, 2u);
	std::map<std::uint32_t, std::size_t> detectionsOf;
	for (const auto& d : personsIn(out / "detections.txt"))
		if (d.personId) ++detectionsOf[*d.personId];
	for (const auto& t : tracks)
	{
		EXPECT_GE(t.sightings, minSightings) << "person " << t.id;
		EXPECT_EQ(t.sightings, detectionsOf[t.id]) << "person " << t.id;
	}
	std::size_t unconfirmed = 0;
	for (const auto& [id, n] : detectionsOf)
		if (std::none_of(tracks.begin(), tracks.end(), [id = id](const auto& t) { return t.id == id; }))
		{
			EXPECT_LT(n, minSightings) << "track " << id << " is missing from persons.csv";
			++unconfirmed;
		}
	std::cout << tracks.size() << " persons, " << unconfirmed << " tracks seen too few times to be one\n";
	// People walk through the view for the last 230 frames; some detector
	// box sequence there is one person for over 100 frames.
	std::size_t longest = 0;
	for (const auto& t : tracks) longest = std::max(longest, t.lastFrame - t.firstFrame);
	EXPECT_GE(longest, 100u);
	EXPECT_LE(tracks.size(), 15u) << "a person crossing the view split into many tracks";

	const auto stats = mrpt::containers::yaml::FromFile((out / "stats.json").string());
	EXPECT_EQ(stats["persons"].size(), tracks.size());
	octomap::OcTree low(0.1);
	ASSERT_TRUE(low.readBinary((out / "map_low.bt").string()));
	double lo[3], hi[3];
	low.getMetricMin(lo[0], lo[1], lo[2]);
	low.getMetricMax(hi[0], hi[1], hi[2]);
	for (const auto& t : tracks)
	{
		const double p[3] = {t.position.x, t.position.y, t.position.z};
		for (int k = 0; k < 3; k++)
		{
			EXPECT_GE(p[k], lo[k] - 0.5) << "person " << t.id;
			EXPECT_LE(p[k], hi[k] + 0.5) << "person " << t.id;
		}
	}
	// Regions are per person, never a box around several.
	std::vector<mrpt::math::TBoundingBox> boxes;
	for (std::size_t i = 0; i < stats["regions"].size(); i++)
	{
		const auto region = stats["regions"](i);
		EXPECT_GT(region["person"].as<int>(), 0);
		for (std::size_t b = 0; b < region["boxes"].size(); b++)
		{
			const auto lo = region["boxes"](b)["min"], hi = region["boxes"](b)["max"];
			boxes.push_back({{lo(0).as<double>(), lo(1).as<double>(), lo(2).as<double>()},
				{hi(0).as<double>(), hi(1).as<double>(), hi(2).as<double>()}});
		}
	}
	ASSERT_FALSE(boxes.empty()) << "people are in view at the end of the sequence";
	// Space held once: every high leaf lies in a region of the end, every low
	// leaf outside them (what left a region went back to the low tree).
	const auto inRegions = [&](double x, double y, double z)
	{
		for (const auto& b : boxes)
			if (x > b.min.x && x < b.max.x && y > b.min.y && y < b.max.y && z > b.min.z && z < b.max.z) return true;
		return false;
	};
	octomap::OcTree high(0.1);
	ASSERT_TRUE(high.readBinary((out / "map_high.bt").string()));
	std::size_t strayHigh = 0, lowInside = 0;
	for (auto it = high.begin_leafs(); it != high.end_leafs(); ++it)
		if (!inRegions(it.getX(), it.getY(), it.getZ())) ++strayHigh;
	for (auto it = low.begin_leafs(); it != low.end_leafs(); ++it)
		if (it.getSize() <= 0.2 + 1e-6 && inRegions(it.getX(), it.getY(), it.getZ())) ++lowInside;
	EXPECT_EQ(strayHigh, 0u);
	EXPECT_EQ(lowInside, 0u);
}

// Every output a user opens, read back as they would: each file there and
// loadable, and holding what the run reports (the trajectory a pose per frame
// mapped, the trees, the scene and stats.json the same map), and the map the
// room the camera saw: the first frame's depth points (no one in view yet)
// fall in occupied voxels.
TEST(PipelineOnBonn, AllOutputsExistLoadAndHoldWhatTheRunSaw)
{
	const auto& [out, summary] = defaultRun();
	// A finished run's files, as RunFolder::outputs() names them (avm-map's summary lists those).
	const std::vector<std::string> names = {"map_low.bt", "map_high.bt", "map.3Dscene", "trajectory.txt",
		"trajectory_status.txt", "detections.txt", "persons.csv", "person_shapes.ply", "stats.json", "map_top.png",
		"map_perspective.png", "avm-map.log", "keyframes.simplemap", "session.bin"};
	std::vector<std::string> outputs;
	for (const auto& file : io::RunFolder(out).outputs()) outputs.push_back(file.filename().string());
	EXPECT_EQ(outputs, names);
	for (const auto& name : names) EXPECT_TRUE(fs::exists(out / name)) << name;
	// What a next run continues: the run's configuration and rawlog, and its keyframes.
	EXPECT_EQ(pipeline::readSessionRun(out).rawlog, fs::absolute(test::bonnRawlog()));
	mrpt::maps::CSimpleMap keyframes;
	ASSERT_TRUE(keyframes.loadFromFile((out / "keyframes.simplemap").string()));
	EXPECT_GT(keyframes.size(), 5u) << "the camera moves 0.85 m: a keyframe every 8 cm or 8 degrees";

	// A pose per frame mapped, the ground truth's (--poses gt), and a status line each: 1 tracked, 0 bridged.
	const auto stats = mrpt::containers::yaml::FromFile((out / "stats.json").string());
	const auto trajectory = io::readTumTrajectory(out / "trajectory.txt");
	EXPECT_EQ(summary.frames, 300u);
	EXPECT_EQ(stats["frames"].as<std::size_t>(), summary.frames);
	ASSERT_EQ(trajectory.size(), summary.frames);
	const auto gt = io::readTumTrajectory(test::bonnRawlog().parent_path() / "bonn_sub300_groundtruth.txt");
	ASSERT_EQ(gt.size(), trajectory.size());
	for (std::size_t i = 0; i < gt.size(); i += 50)
		EXPECT_LT((trajectory[i].pose - gt[i].pose).translation().norm(), 1e-5) << "pose " << i;
	const auto tracked = test::trackedFlagsIn(out / "trajectory_status.txt");
	ASSERT_EQ(tracked.size(), trajectory.size());
	for (std::size_t i = 0; i < tracked.size(); ++i) ASSERT_TRUE(tracked[i] == 0 || tracked[i] == 1) << "line " << i;
	EXPECT_EQ(std::count(tracked.begin(), tracked.end(), 0), 0);

	// The trees octovis opens, the scene SceneViewer3D opens and stats.json
	// hold the same map: the scene a voxel per leaf stats.json counts, the
	// .bt files (maximum-likelihood pruned: fewer, larger leaves) the same
	// occupied volume.
	octomap::OcTree low(0.1), high(0.1);
	ASSERT_TRUE(low.readBinary((out / "map_low.bt").string()));
	ASSERT_TRUE(high.readBinary((out / "map_high.bt").string()));
	EXPECT_DOUBLE_EQ(low.getResolution(), 0.20);
	EXPECT_DOUBLE_EQ(high.getResolution(), 0.05);
	mrpt::opengl::COpenGLScene scene;
	ASSERT_TRUE(scene.loadFromFile((out / "map.3Dscene").string()));
	const auto voxels = scene.getByClass<mrpt::opengl::COctoMapVoxels>();
	ASSERT_TRUE(voxels) << "map.3Dscene has no voxels";
	ASSERT_GE(voxels->getVoxelSetCount(), 2u);
	const std::size_t lowOccupied = stats["map"]["low"]["occupied_voxels"].as<std::size_t>(),
					  highOccupied = stats["map"]["high"]["occupied_voxels"].as<std::size_t>();
	EXPECT_EQ(voxels->getVoxelCount(0), lowOccupied);
	EXPECT_EQ(voxels->getVoxelCount(1), highOccupied);
	EXPECT_NEAR(occupiedVolume(low), occupiedVolume(*voxels, 0), 1e-6 * occupiedVolume(*voxels, 0));
	EXPECT_NEAR(occupiedVolume(high), occupiedVolume(*voxels, 1), 1e-6 * occupiedVolume(*voxels, 1));
	// The room: hundreds of 0.20 m voxels of walls, floor and desks; the
	// people in view at the end: thousands of 0.05 m ones.
	EXPECT_GT(lowOccupied, 300u);
	EXPECT_LT(lowOccupied, 20000u);
	EXPECT_GT(highOccupied, 500u);
	EXPECT_EQ(stats["switch_frame"].as<int>(), static_cast<int>(*summary.switchFrame));

	// The first frame (no one in view) as the map holds it: its depth points
	// within the map's range, at its pose, in occupied voxels of either tree.
	const auto [points, exact, near] = firstFrameInMap(low, high);
	std::cout << "of the first frame's " << points << " depth points, " << exact << " in occupied voxels, " << near
			  << " in or next to one\n";
	// 80 % and 97 % measured: the rest lie near a voxel's face, or where
	// later frames' rays passed and cleared.
	ASSERT_GT(points, 1000u);
	EXPECT_GT(double(exact), 0.75 * double(points));
	EXPECT_GT(double(near), 0.95 * double(points));

	// The run's timing: detection, odometry-free mapping and reading of 300
	// frames take well over a millisecond of CPU a frame.
	EXPECT_GT(stats["fps"].as<double>(), 0.0);
	EXPECT_GT(stats["cpu_ms_per_frame"].as<double>(), 1.0);
	const double stolen = stats["cpu_stolen_percent"].as<double>();
	EXPECT_TRUE(stolen >= 0 && stolen <= 100) << stolen;
	for (const char* stage : {"detection", "map"})
		EXPECT_GT(stats["stages"][stage]["mean_ms"].as<double>(), 0.0) << stage;
}

// Each person's last shape on the real run: in person_shapes.ply (which
// MRPT's PLY reader opens), one point per high-resolution voxel, inside the
// person's last region box, and in map.3Dscene.
TEST(PipelineOnBonn, EachPersonsLastShapeIsWrittenAtTheRegionsResolutionInTheirRegion)
{
	const auto& [out, summary] = defaultRun();
	const auto tracks = persons::readPersonsCsv(out / "persons.csv");
	ASSERT_FALSE(tracks.empty());
	const double margin = test::defaultIni().read_double("map_adaptiveOctoMap_00_insertOpts", "region_margin", -1);
	ASSERT_GE(margin, 0);
	const double resolution = 0.05;  // the high tree's (AllOutputsExistLoadAndHoldWhatTheRunSaw)

	std::istringstream ply(test::fileBytes(out / "person_shapes.ply"));
	std::string line;
	while (std::getline(ply, line) && line != "end_header")
	{
	}
	std::map<std::uint32_t, std::set<std::array<long, 3>>> voxelsOf;
	std::size_t points = 0;
	for (; std::getline(ply, line); ++points)
	{
		double p[3];
		unsigned r, g, b, id;
		ASSERT_EQ(std::sscanf(line.c_str(), "%lf %lf %lf %u %u %u %u", &p[0], &p[1], &p[2], &r, &g, &b, &id), 7)
			<< line;
		EXPECT_EQ(mrpt::img::TColor(r, g, b), persons::kPersonColour) << line;
		const auto track = std::find_if(tracks.begin(), tracks.end(), [&](const auto& t) { return t.id == id; });
		ASSERT_NE(track, tracks.end()) << "no person " << id << " in persons.csv";
		// persons.csv's boxes are to the mm, the file's points to 0.1 mm.
		const double lo[3] = {track->box.min.x, track->box.min.y, track->box.min.z},
					 hi[3] = {track->box.max.x, track->box.max.y, track->box.max.z};
		std::array<long, 3> key{};
		for (int k = 0; k < 3; k++)
		{
			EXPECT_GE(p[k], lo[k] - margin - 1e-3) << "person " << id << ": " << line;
			EXPECT_LE(p[k], hi[k] + margin + 1e-3) << "person " << id << ": " << line;
			const double cell = p[k] / resolution - 0.5;
			EXPECT_NEAR(cell, std::round(cell), 1e-2) << "not a voxel centre: " << line;
			key[k] = std::lround(cell);
		}
		EXPECT_TRUE(voxelsOf[id].insert(key).second) << "two points in one voxel: " << line;
	}
	for (const auto& t : tracks) EXPECT_GT(voxelsOf[t.id].size(), 50u) << "person " << t.id << " has no shape";

	mrpt::opengl::CPointCloudColoured cloud;
	ASSERT_TRUE(cloud.loadFromPlyFile((out / "person_shapes.ply").string())) << cloud.getLoadPLYErrorString();
	EXPECT_EQ(cloud.size(), points);

	mrpt::opengl::COpenGLScene scene;
	ASSERT_TRUE(scene.loadFromFile((out / "map.3Dscene").string()));
	const auto shapes = scene.getByClass<mrpt::opengl::CPointCloud>();
	ASSERT_TRUE(shapes) << "map.3Dscene has no person shapes";
	EXPECT_EQ(shapes->getName(), CAdaptiveOctoMap::kPersonShapesName);
	EXPECT_EQ(shapes->size(), points);
	EXPECT_EQ(shapes->getColor_u8(), persons::kPersonColour);
}
