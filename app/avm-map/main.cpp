// avm-map: maps an RGB-D rawlog with the adaptive dual-resolution map.
// The work happens in avm::pipeline::MappingPipeline; this is the shell.
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/vector_loadsave.h>
#include <mrpt/system/progress.h>
#include <opencv2/core/utility.hpp>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <iostream>
#include <memory>
#include <optional>
#include <vector>

#include "avm/io/ProgramMain.h"
#include "avm/pipeline/MappingPipeline.h"
#include "avm/viewer/MapView.h"

namespace
{
// Set by SIGINT/SIGTERM: the run stops after the current frame and saves.
// A signal handler can reach nothing but a static.
std::atomic<bool> stopRequested{false};
extern "C" void onSignal(int) { stopRequested = true; }
std::string readIni(const std::string& file)
{
	if (!std::filesystem::is_regular_file(file)) throw std::runtime_error(file + ": ini file not found");
	return mrpt::io::file_get_contents(file);
}

/** One --set SECTION:KEY=VALUE. */
struct Override
{
	std::string section, key, value;
};

Override parseOverride(const std::string& assignment)
{
	const auto colon = assignment.find(':'), equals = assignment.find('=');
	if (colon == std::string::npos || equals == std::string::npos || equals < colon || colon == 0 ||
		equals == colon + 1)
		throw std::invalid_argument("--set " + assignment + ": expected SECTION:KEY=VALUE");
	return {
		assignment.substr(0, colon), assignment.substr(colon + 1, equals - colon - 1), assignment.substr(equals + 1)};
}

/** Where the value an option error names came from: a --set that gave
 *  [section] key, or else the ini file. */
std::string sourceOf(const std::string& message, const std::string& iniFile, const std::vector<Override>& overrides)
{
	for (const auto& o : overrides)
		if (message.rfind("[" + o.section + "] " + o.key + " =", 0) == 0) return "--set";
	return iniFile;
}
}  // namespace

int main(int argc, char** argv)
{
	bool viewOpened = false;
	const int status = avm::io::runProgram("avm-map",
		"Maps an RGB-D rawlog: odometry -> person detection -> adaptive octree map.",
		[&](avm::io::CommandLine& cmd)
		{
			TCLAP::ValueArg<std::string> argConfig(
				"c", "config", "ini file (e.g. ini/default.ini); required unless --resume", false, "", "INI", cmd);
			TCLAP::ValueArg<std::string> argRawlog("r", "rawlog",
				"input rawlog of CObservation3DRangeScan; required unless --resume", false, "", "RAWLOG", cmd);
			TCLAP::ValueArg<std::string> argOut(
				"o", "out", "output folder (default: output)", false, "output", "DIR", cmd);
			TCLAP::ValueArg<std::string> argResume("", "resume",
				"continue the run whose output folder is DIR from its last checkpoint (its configuration and rawlog "
				"come from the checkpoint); the outputs go to DIR",
				false, "", "DIR", cmd);
			TCLAP::ValueArg<std::string> argPoses(
				"p", "poses", "pose source, overrides [pipeline] pose_source", false, "", "vo|gt", cmd);
			TCLAP::MultiArg<std::string> argSet("s", "set",
				"override one ini value, e.g. --set pipeline:detect_every_n=1 (repeatable)", false, "SECTION:KEY=VALUE",
				cmd);
			TCLAP::SwitchArg argQuiet("q", "quiet", "no progress bar", cmd);
			TCLAP::SwitchArg argGui("", "gui",
				"live 3D view of the run (sets [pipeline] gui = true); closing it ends the run as Ctrl-C does", cmd);
			TCLAP::ValueArg<std::string> argGuiShot("", "gui-screenshot",
				"with --gui: after the last frame, save the X server's picture of the view as this PNG", false, "",
				"PNG", cmd);
			cmd.parse(argc, argv);

			const bool resume = argResume.isSet();
			if (resume)
			{
				for (const TCLAP::Arg* a :
					std::initializer_list<const TCLAP::Arg*>{&argConfig, &argRawlog, &argOut, &argPoses, &argSet})
					if (a->isSet())
						throw std::invalid_argument("--resume: --" + a->getName() +
													" is not allowed with it (the checkpoint holds the run's "
													"configuration, rawlog and folder)");
			}
			else if (!argConfig.isSet() || !argRawlog.isSet())
			{
				std::string missing;
				for (const TCLAP::Arg* a : std::initializer_list<const TCLAP::Arg*>{&argRawlog, &argConfig})
					if (!a->isSet())  // shortID() brackets an optional argument: "[-r <RAWLOG>]"
						missing += (missing.empty() ? " " : ", ") + a->shortID().substr(1, a->shortID().size() - 2);
				throw std::invalid_argument(
					"missing required argument" + missing + " (or --resume DIR; see avm-map --help)");
			}
			std::optional<avm::pipeline::CheckpointedRun> checkpointed;
			if (resume) checkpointed = avm::pipeline::readCheckpointedRun(argResume.getValue());
			const std::string iniSource =
				resume ? avm::pipeline::checkpointFile(argResume.getValue()).string() : argConfig.getValue();
			const std::string outDir = resume ? argResume.getValue() : argOut.getValue();
			avm::io::useImagesFolderOf(resume ? checkpointed->rawlog : std::filesystem::path(argRawlog.getValue()));

			mrpt::config::CConfigFileMemory ini(resume ? checkpointed->ini : readIni(argConfig.getValue()));
			std::vector<Override> overrides;
			for (const auto& assignment : argSet.getValue()) overrides.push_back(parseOverride(assignment));
			if (argGui.getValue()) overrides.push_back(parseOverride("pipeline:gui=true"));
			for (const auto& o : overrides) ini.write(o.section, o.key, o.value);
			// The pipeline reads every option (the map's inside MRPT's
			// CMultiMetricMap, which wraps errors in its call-stack report).
			std::unique_ptr<avm::pipeline::MappingPipeline> loaded;
			try
			{
				loaded = std::make_unique<avm::pipeline::MappingPipeline>(ini, AVM_PROJECT_ROOT);
			}
			catch (const std::exception& e)
			{
				avm::io::rethrowNamingIniSource(sourceOf(avm::io::errorMessage(e), iniSource, overrides), e);
			}
			auto& pipeline = *loaded;
			viewOpened = pipeline.opensView();
			// Process-wide: the ini's OpenCV threads apply to the whole run.
			if (pipeline.openCvThreads() > 0) cv::setNumThreads(pipeline.openCvThreads());
			pipeline.setMinLoggingLevel(mrpt::system::LVL_INFO);
			if (argPoses.isSet()) pipeline.setPoseSource(avm::pipeline::poseSourceFromString(argPoses.getValue()));
			if (argGuiShot.isSet()) pipeline.setViewScreenshot(argGuiShot.getValue());

			std::signal(SIGINT, onSignal);
			std::signal(SIGTERM, onSignal);
			const bool bar = !argQuiet.getValue() && ::isatty(STDERR_FILENO);
			const auto start = std::chrono::steady_clock::now();
			const auto showProgress = [&](double fraction, std::size_t frames)
			{
				if (!bar) return;
				const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
				const double left = fraction > 0 ? s * (1 - fraction) / fraction : 0;
				std::fprintf(stderr, "\r%s %zu frames, %.1f fps, %.0f s left ",
					mrpt::system::progress(fraction, 30).c_str(), frames, frames / std::max(s, 1e-9), left);
			};
			const auto summary = resume ? pipeline.resume(outDir, &stopRequested, showProgress)
										: pipeline.run(argRawlog.getValue(), outDir, &stopRequested, showProgress);
			if (bar) std::fputc('\n', stderr);

			if (summary.resumedAfterFrame)
				std::cout << "resumed:     after frame " << *summary.resumedAfterFrame << "\n";
			std::cout << "frames:      " << summary.frames << (summary.interrupted ? " (interrupted, saved)" : "")
					  << "\n"
					  << "speed:       " << summary.fps << " fps, real-time factor " << summary.realTimeFactor << "\n"
					  << "switch:      "
					  << (summary.switchFrame ? "frame " + std::to_string(*summary.switchFrame) : std::string("never"))
					  << ", " << summary.regions << " person regions\n";
			std::printf(
				"stages [ms]: odometry mean %.1f median %.1f p95 %.1f | detection mean %.1f median %.1f p95 %.1f "
				"(%zu runs) | map mean %.1f median %.1f p95 %.1f\n",
				summary.odometry.meanMs, summary.odometry.medianMs, summary.odometry.p95Ms, summary.detection.meanMs,
				summary.detection.medianMs, summary.detection.p95Ms, summary.detection.count, summary.map.meanMs,
				summary.map.medianMs, summary.map.p95Ms);
			std::printf("memory:      peak %.0f MiB\n", summary.peakMemoryMb);
			std::printf("cpu:         %.1f ms a frame (all threads)", summary.cpuMsPerFrame);
			if (summary.stolenCpuShare)
				std::printf(
					"; %.0f%% of the machine's CPU time went to other virtual machines", 100 * *summary.stolenCpuShare);
			std::printf("\n");
			std::fflush(stdout);
			if (summary.ateRmse)
				std::cout << "odometry:    ATE RMSE " << *summary.ateRmse << " m against the rawlog's ground truth\n";
			std::cout << "outputs in:  " << outDir
					  << " (map_low.bt, map_high.bt, map.3Dscene, trajectory.txt, detections.txt, stats.json, "
						 "map_top.png, map_perspective.png, avm-map.log, checkpoint.bin)\n";
			return summary.interrupted ? 130 : 0;
		});
	if (viewOpened) avm::viewer::exitAfterView(status);
	return status;
}
