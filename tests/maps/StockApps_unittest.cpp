// The plugin inside the stock MRPT apps (installed by scripts/install-deps.sh:
// mrpt-apps, xvfb), on a short cut of the Bonn rawlog. MRPT 2.5.8 finds
// external images only for a relative rawlog name, so every app runs with its
// working folder at the rawlog.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/vector_loadsave.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <octomap/OcTree.h>
#include <signal.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <string>
#include <sstream>
#include <thread>

#include "BonnFrames.h"
#include "avm/plugin/CAdaptiveOctoMap.h"
#include "avm/maps/OcTreeFile.h"
#include "avm/maps/OccupiedKeys.h"

namespace fs = std::filesystem;

namespace
{
const fs::path kPlugin = fs::path(AVM_LIB_DIR) / "libavm-adaptive-octomap.so";
const fs::path kIniDir = fs::path(AVM_SOURCE_DIR) / "ini";

struct RunResult
{
	int exitCode;
	std::string output;
};

RunResult run(const std::string& command)
{
	RunResult r{-1, {}};
	FILE* p = ::popen((command + " 2>&1").c_str(), "r");
	if (!p) return r;
	char buf[4096];
	while (std::fgets(buf, sizeof(buf), p)) r.output += buf;
	const int status = ::pclose(p);
	r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
	return r;
}

/** The stock app's path; the test fails (not skips) without it. */
std::string stockApp(const std::string& name)
{
	const auto r = run("command -v " + name);
	const std::string path = r.output.substr(0, r.output.find('\n'));
	if (r.exitCode != 0 || path.empty())
		throw std::runtime_error(name + " not found: install mrpt-apps (scripts/install-deps.sh)");
	return path;
}

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

/** The first 20 frames of the Bonn rawlog (40 entries with ground truth),
 *  cut by rawlog-edit itself, with its images folder beside it; one folder
 *  per test, so that ctest -j can run them side by side. */
const fs::path& shortRawlogDir()
{
	static fs::path dir;
	static std::once_flag once;
	std::call_once(once,
		[]
		{
			dir = avm::test::scratchDir(
				std::string("stock-apps-") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
			const auto source = avm::test::bonnRawlog();
			const auto r = run("cd " + quoted(source.parent_path()) + " && " + stockApp("rawlog-edit") +
							   " --cut --from-index 0 --to-index 39 -i " + quoted(source.filename()) + " -o " +
							   quoted(dir / "bonn_short.rawlog"));
			if (r.exitCode != 0 || !fs::exists(dir / "bonn_short.rawlog"))
				throw std::runtime_error("rawlog-edit --cut failed:\n" + r.output);
			fs::create_directory_symlink(
				fs::absolute(source.parent_path() / (source.stem().string() + "_Images")), dir / "bonn_short_Images");
		});
	return dir;
}

std::string readFile(const fs::path& p)
{
	std::ifstream f(p, std::ios::binary);
	std::ostringstream s;
	s << f.rdbuf();
	return s.str();
}
}  // namespace

TEST(StockApps, RawlogEditLoadsThePlugin)
{
	const auto& dir = shortRawlogDir();
	const auto app = stockApp("rawlog-edit");
	const auto ok = run("cd " + quoted(dir) + " && " + app + " -p " + quoted(kPlugin) + " --info -i bonn_short.rawlog");
	EXPECT_EQ(ok.exitCode, 0) << ok.output;
	EXPECT_EQ(ok.output.find("Error loading"), std::string::npos) << ok.output;
	EXPECT_NE(ok.output.find("Observations format"), std::string::npos) << ok.output;
	// The same check catches a plugin that does not load.
	const auto bad =
		run("cd " + quoted(dir) + " && " + app + " -p /nonexistent/libnothing.so --info -i bonn_short.rawlog");
	EXPECT_NE(bad.output.find("Error loading"), std::string::npos) << bad.output;
}

// RawLogViewer is a GUI: start it under xvfb-run, wait until the plugin is
// mapped into the process and it is still running a moment later, then stop it.
TEST(StockApps, RawLogViewerLoadsThePluginAndKeepsRunning)
{
	const auto& dir = shortRawlogDir();
	const auto pidFile = dir / "rawlogviewer.pid", log = dir / "rawlogviewer.log";
	fs::remove(pidFile);
	const std::string cmd = "cd " + quoted(dir) + " && (" + stockApp("xvfb-run") + " -a sh -c 'echo $$ > " +
							pidFile.string() + "; exec " + stockApp("RawLogViewer") + " -l " + kPlugin.string() +
							" bonn_short.rawlog' > " + quoted(log) + " 2>&1 &)";
	ASSERT_EQ(std::system(cmd.c_str()), 0);

	const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
	pid_t pid = 0;
	bool mapped = false;
	while (std::chrono::steady_clock::now() < deadline && !mapped)
	{
		std::this_thread::sleep_for(std::chrono::milliseconds(200));
		if (!pid && fs::exists(pidFile)) std::ifstream(pidFile) >> pid;
		if (pid)
			mapped = readFile("/proc/" + std::to_string(pid) + "/maps").find(kPlugin.filename().string()) !=
					 std::string::npos;
	}
	ASSERT_GT(pid, 0) << "RawLogViewer did not start:\n" << readFile(log);
	EXPECT_TRUE(mapped) << "the plugin never appeared in RawLogViewer's memory map:\n" << readFile(log);
	std::this_thread::sleep_for(std::chrono::seconds(3));
	const bool alive = ::kill(pid, 0) == 0;
	::kill(pid, SIGTERM);
	EXPECT_TRUE(alive) << "RawLogViewer exited early:\n" << readFile(log);
	std::this_thread::sleep_for(std::chrono::seconds(1));
	if (::kill(pid, 0) == 0) ::kill(pid, SIGKILL);
	const auto text = readFile(log);
	EXPECT_EQ(text.find("Error loading"), std::string::npos) << text;
	EXPECT_EQ(text.find("MRPT exception"), std::string::npos) << text;
}

// observations2map builds the map from a simplemap of ground-truth poses; its
// low tree must be byte for byte the one the same ini builds in-process.
TEST(StockApps, Observations2MapBuildsTheSameMapAsInProcess)
{
	const auto& dir = shortRawlogDir();
	const auto frames = avm::test::bonnFrames(20, 1);
	mrpt::maps::CSimpleMap sm;
	for (const auto& f : frames)
	{
		auto sf = mrpt::obs::CSensoryFrame::Create();
		sf->insert(f.obs);
		sm.insert(mrpt::poses::CPose3DPDFGaussian::Create(f.pose), sf);
	}
	ASSERT_TRUE(sm.saveToFile((dir / "bonn_gt.simplemap").string()));
	const auto ini = kIniDir / "map-observations2map.ini";
	fs::create_directories(dir / "o2m");
	const auto r = run("cd " + quoted(dir) + " && LD_PRELOAD=" + quoted(kPlugin) + " " + stockApp("observations2map") +
					   " " + quoted(ini) + " bonn_gt.simplemap o2m/bonn < /dev/null");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const auto prefix = dir / "o2m" / "bonn_avm__CAdaptiveOctoMap_00";
	for (const auto* suffix : {"_low.bt", "_high.bt", ".3Dscene"})
		ASSERT_TRUE(fs::exists(prefix.string() + suffix)) << prefix.string() + suffix << "\n" << r.output;

	mrpt::config::CConfigFileMemory cfg(readFile(ini));
	mrpt::maps::TSetOfMetricMapInitializers inits;
	inits.loadFromConfigFile(cfg, "MappingApplication");
	mrpt::maps::CMultiMetricMap multi;
	multi.setListOfMaps(inits);
	auto map = multi.mapByClass<avm::CAdaptiveOctoMap>();
	ASSERT_TRUE(map);
	for (const auto& f : frames) ASSERT_TRUE(map->insertObservation(*f.obs, f.pose));
	const auto expected = avm::binaryTreeBytes(*map->tree(avm::Resolution::Low));
	const auto written = readFile(prefix.string() + "_low.bt");
	EXPECT_GT(map->lowResolutionStats().occupiedLeaves, 100u);
	EXPECT_EQ(written.size(), expected.size());
	EXPECT_TRUE(written == expected) << "observations2map's low tree differs from the in-process one";
}

// icp-slam needs points3D for its own ICP (its points map does not unproject
// depth images): rawlog-edit adds them, then icp-slam runs with the adaptive
// map next to its points map and writes it at the end.
TEST(StockApps, IcpSlamRunsWithTheAdaptiveMap)
{
	const auto& dir = shortRawlogDir();
	const auto gen = run("cd " + quoted(dir) + " && " + stockApp("rawlog-edit") +
						 " --generate-3d-pointclouds -i bonn_short.rawlog -o bonn_short_pts.rawlog");
	ASSERT_EQ(gen.exitCode, 0) << gen.output;
	fs::remove_all(dir / "LOG_ICP-SLAM");
	const auto r = run("cd " + quoted(dir) + " && LD_PRELOAD=" + quoted(kPlugin) + " " + stockApp("icp-slam") + " " +
					   quoted(kIniDir / "map-icp-slam.ini") + " bonn_short_pts.rawlog");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("Fit:"), std::string::npos) << "icp-slam never ran ICP:\n" << r.output;
	const auto prefix = dir / "LOG_ICP-SLAM" / "_finalmaps_.txt_avm__CAdaptiveOctoMap_00";
	for (const auto* suffix : {"_low.bt", "_high.bt", ".3Dscene"})
		ASSERT_TRUE(fs::exists(prefix.string() + suffix)) << prefix.string() + suffix;
	octomap::OcTree low(0.1);
	ASSERT_TRUE(low.readBinary(prefix.string() + "_low.bt"));
	EXPECT_DOUBLE_EQ(low.getResolution(), 0.2);
	std::size_t occupied = 0;
	for (auto it = low.begin_leafs(); it != low.end_leafs(); ++it) occupied += low.isNodeOccupied(*it);
	EXPECT_GT(occupied, 100u) << "icp-slam inserted (almost) nothing into the adaptive map";
}

// A finished avm-map run handed on the MRPT way: observations2map builds a
// point map, an OctoMap and the adaptive map from its keyframes.simplemap
// (ini/map-keyframes-observations2map.ini), and they hold the space the run
// mapped.
TEST(StockApps, Observations2MapBuildsMapsFromARunsKeyframes)
{
	const auto dir = avm::test::scratchDir("stock-apps-keyframes");
	const fs::path session = fs::path(AVM_SESSION_RAWLOGS) / "first";
	fs::create_directories(dir / "out");
	const auto r = run("cd " + quoted(dir) + " && LD_PRELOAD=" + quoted(kPlugin) + " " + stockApp("observations2map") +
					   " " + quoted(kIniDir / "map-keyframes-observations2map.ini") + " " +
					   quoted(session / "keyframes.simplemap") + " out/keyframes < /dev/null");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const auto find = [&](const std::string& ending)
	{
		for (const auto& e : fs::directory_iterator(dir / "out"))
		{
			const std::string name = e.path().filename().string();
			if (name.size() >= ending.size() && name.compare(name.size() - ending.size(), ending.size(), ending) == 0)
				return e.path();
		}
		ADD_FAILURE() << "observations2map wrote no *" << ending << "\n" << r.output;
		return fs::path();
	};
	std::ifstream points(find("CSimplePointsMap_02.txt"));
	const auto lines = std::count(std::istreambuf_iterator<char>(points), std::istreambuf_iterator<char>(), '\n');
	EXPECT_GT(lines, 20000) << "points of the keyframes";
	const auto octoMap = avm::readBinaryTree(find("COctoMap_01_binary.bt"));
	std::size_t occupied = 0;
	for (auto it = octoMap->begin_leafs(); it != octoMap->end_leafs(); ++it) occupied += octoMap->isNodeOccupied(*it);
	EXPECT_GT(occupied, 1000u) << "occupied leaves of MRPT's OctoMap";
	// The keyframes alone describe most of the space all the frames mapped.
	const auto all = [](double, double, double) { return true; };
	const auto keyframes = avm::occupiedFinestKeys(*avm::readBinaryTree(find("CAdaptiveOctoMap_00_low.bt")), all);
	const auto mapped = avm::occupiedFinestKeys(*avm::readBinaryTree(session / "map_low.bt"), all);
	EXPECT_GT(keyframes.size(), 500u);
	EXPECT_GT(avm::intersectionOverUnion(keyframes, mapped), 0.6);
}
