// avm-map: maps an RGB-D rawlog with the adaptive dual-resolution map.
// The work happens in avm::pipeline::MappingPipeline; this is the shell.
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/vector_loadsave.h>
#include <opencv2/core/utility.hpp>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <vector>

#include "avm/evaluation/ReferenceMapsObserver.h"
#include "avm/io/ProgramMain.h"
#include "avm/io/RunFolder.h"
#include "avm/pipeline/CheckpointWriter.h"
#include "avm/pipeline/MappingPipeline.h"
#include "avm/viewer/LiveView.h"

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

/** avm-map's arguments, declared on the program's command line. */
struct Arguments
{
	explicit Arguments(avm::io::CommandLine& cmd)
		: config("c", "config", "ini file (e.g. ini/default.ini); required unless --resume", false, "", "INI", cmd),
		  rawlog("r", "rawlog", "input rawlog of CObservation3DRangeScan; required unless --resume", false, "",
			  "RAWLOG", cmd),
		  out("o", "out", "output folder (default: output)", false, "output", "DIR", cmd),
		  resume("", "resume",
			  "continue the run whose output folder is DIR from its last "
			  "checkpoint (its configuration and rawlog "
			  "come from the checkpoint); the outputs go to DIR",
			  false, "", "DIR", cmd),
		  continueFrom("", "continue",
			  "map the rawlog as the next session of the finished run whose output folder is PREV (read, never "
			  "written): it starts with PREV's maps, persons and keyframes, places its frames among PREV's keyframes "
			  "and maps on in PREV's world; --config defaults to PREV's configuration",
			  false, "", "PREV", cmd),
		  poses("p", "poses", "pose source, overrides [pipeline] pose_source", false, "", "vo|gt", cmd),
		  set("s", "set",
			  "override one ini value, e.g. --set pipeline:detect_every_n=1 "
			  "(repeatable)",
			  false, "SECTION:KEY=VALUE", cmd),
		  quiet("q", "quiet", "no progress bar", cmd),
		  gui("", "gui",
			  "live 3D view of the run (sets [pipeline] gui = true); closing it "
			  "ends the run as Ctrl-C does; at the end it shows the finished map "
			  "until closed or a key is pressed",
			  cmd),
		  guiNoWait("", "gui-no-wait", "with --gui: close the view and exit when the run ends (scripts)", cmd),
		  guiShot("", "gui-screenshot",
			  "with --gui: after the last frame, save the X server's picture "
			  "of the view as this PNG, and exit when the run ends",
			  false, "", "PNG", cmd)
	{
	}

	/** --resume excludes the arguments the checkpoint holds; without it,
   *  --rawlog is required, and --config unless --continue (PREV's then). */
	void check() const
	{
		if (resume.isSet())
		{
			for (const TCLAP::Arg* a :
				std::initializer_list<const TCLAP::Arg*>{&config, &rawlog, &out, &poses, &set, &continueFrom})
				if (a->isSet())
					throw std::invalid_argument("--resume: --" + a->getName() +
												" is not allowed with it (the checkpoint holds the run's "
												"configuration, rawlog and folder)");
			return;
		}
		std::vector<const TCLAP::Arg*> required{&rawlog};
		if (!continueFrom.isSet()) required.push_back(&config);
		std::string missing;
		for (const TCLAP::Arg* a : required)
			if (!a->isSet())  // shortID() brackets an optional argument: "[-r <RAWLOG>]"
				missing += (missing.empty() ? " " : ", ") + a->shortID().substr(1, a->shortID().size() - 2);
		if (!missing.empty())
			throw std::invalid_argument(
				"missing required argument" + missing + " (or --resume DIR; see avm-map --help)");
	}

	TCLAP::ValueArg<std::string> config, rawlog, out, resume, continueFrom, poses;
	TCLAP::MultiArg<std::string> set;
	TCLAP::SwitchArg quiet, gui, guiNoWait;
	TCLAP::ValueArg<std::string> guiShot;
};

/** The pipeline of the ini with the overrides applied; an option error names
 *  where its value came from (the ini file or --set). */
std::unique_ptr<avm::pipeline::MappingPipeline> loadPipeline(
	mrpt::config::CConfigFileMemory& ini, const std::string& iniSource, const std::vector<Override>& overrides)
{
	for (const auto& o : overrides) ini.write(o.section, o.key, o.value);
	// The pipeline reads every option (the map's inside MRPT's
	// CMultiMetricMap, which wraps errors in its call-stack report).
	try
	{
		return std::make_unique<avm::pipeline::MappingPipeline>(ini, AVM_PROJECT_ROOT);
	}
	catch (const std::exception& e)
	{
		avm::io::rethrowNamingIniSource(sourceOf(avm::io::errorMessage(e), iniSource, overrides), e);
	}
	return nullptr;  // not reached: rethrowNamingIniSource throws
}

/** What watches the run: its checkpoints, with reference_maps the reference
 *  maps, and with --gui the live view. */
struct RunObservers
{
	RunObservers(const std::filesystem::path& outDir, double checkpointIntervalSeconds)
		: checkpoints(outDir, checkpointIntervalSeconds)
	{
	}
	void connect(avm::pipeline::MappingPipeline& pipeline, Arguments& args, const std::filesystem::path& rawlog)
	{
		pipeline.addObserver(checkpoints);
		if (pipeline.options().referenceMaps) pipeline.addObserver(reference);
		if (!pipeline.options().gui) return;
		avm::viewer::TViewerOptions options;
		options.fps = pipeline.options().guiFps;
		options.title = "avm-map " + rawlog.filename().string();
		view.emplace(options, &stopRequested);
		if (args.guiShot.isSet()) view->setScreenshot(args.guiShot.getValue());
		view->setWaitsAtEnd(!args.guiShot.isSet() && !args.guiNoWait.getValue());
		pipeline.addObserver(*view);
	}
	avm::pipeline::CheckpointWriter checkpoints;
	avm::evaluation::ReferenceMapsObserver reference;
	std::optional<avm::viewer::LiveView> view;
};

using Progress = std::function<void(double, std::size_t)>;

/** `run` given a progress callback that draws the bar (none with --quiet). */
avm::pipeline::RunSummary withProgressBar(
	bool quiet, const std::function<avm::pipeline::RunSummary(const Progress&)>& run)
{
	avm::io::ProgressBar bar(quiet);
	const auto start = std::chrono::steady_clock::now();
	return run(
		[&](double fraction, std::size_t frames)
		{
			const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
			const double left = fraction > 0 ? s * (1 - fraction) / fraction : 0;
			char text[96];
			std::snprintf(
				text, sizeof(text), "%zu frames, %.1f fps, %.0f s left ", frames, frames / std::max(s, 1e-9), left);
			bar.show(fraction, text);
		});
}

/** What the run did, on stdout. */
void printSummary(const avm::pipeline::RunSummary& summary, const std::string& outDir)
{
	if (summary.resumedAfterFrame) std::cout << "resumed:     after frame " << *summary.resumedAfterFrame << "\n";
	if (const auto& c = summary.continuation)
		std::cout << "continued:   " << c->previous.string() << " (session " << c->session << ", " << c->posesBefore
				  << " poses before); " << c->unplacedFrames << " frames not placed, placed at frame "
				  << (c->placedAtFrame ? std::to_string(*c->placedAtFrame) : std::string("none")) << "\n";
	std::cout << "frames:      " << summary.frames << (summary.interrupted ? " (interrupted, saved)" : "") << "\n"
			  << "speed:       " << summary.fps << " fps, real-time factor " << summary.realTimeFactor << "\n"
			  << "switch:      "
			  << (summary.switchFrame ? "frame " + std::to_string(*summary.switchFrame) : std::string("never")) << ", "
			  << summary.regions << " person regions\n";
	std::cout << "stages [ms]: odometry " << avm::io::describeTimes(summary.odometry) << " | detection "
			  << avm::io::describeTimes(summary.detection) << " (" << summary.detection.count << " runs) | map "
			  << avm::io::describeTimes(summary.map) << "\n";
	std::printf("memory:      peak %.0f MiB\n", summary.peakMemoryMb);
	std::printf("cpu:         %.1f ms a frame (all threads)", summary.cpuMsPerFrame);
	if (summary.stolenCpuShare)
		std::printf("; %.0f%% of the machine's CPU time went to other virtual machines", 100 * *summary.stolenCpuShare);
	std::printf("\n");
	std::fflush(stdout);
	if (summary.ateRmse)
		std::cout << "odometry:    ATE RMSE " << *summary.ateRmse << " m against the rawlog's ground truth\n";
	const avm::io::RunFolder run(outDir);
	std::string files;
	for (const auto& file : run.outputs()) files += (files.empty() ? "" : ", ") + file.filename().string();
	if (summary.interrupted) files += ", " + run.checkpoint().filename().string() + " for --resume";
	std::cout << "outputs in:  " << outDir << " (" << files << ")\n";
}
}  // namespace

int main(int argc, char** argv)
{
	bool viewOpened = false;
	const int status = avm::io::runProgram("avm-map",
		"Maps an RGB-D rawlog: odometry -> person detection -> adaptive octree "
		"map.",
		[&](avm::io::CommandLine& cmd)
		{
			Arguments args(cmd);
			cmd.parse(argc, argv);
			args.check();

			const bool resume = args.resume.isSet(), continues = args.continueFrom.isSet();
			// The run whose configuration this one reads when no --config is given.
			std::optional<avm::pipeline::CheckpointedRun> earlier;
			std::string iniSource = args.config.getValue();
			if (resume)
			{
				const avm::pipeline::CheckpointWriter checkpoint(args.resume.getValue());
				earlier = checkpoint.checkpointedRun();
				iniSource = checkpoint.file().string();
			}
			else if (continues)
			{
				earlier = avm::pipeline::readSessionRun(args.continueFrom.getValue());
				if (!args.config.isSet())
					iniSource = avm::io::RunFolder(args.continueFrom.getValue()).session().string();
			}
			const std::string outDir = resume ? args.resume.getValue() : args.out.getValue();
			const std::filesystem::path rawlog =
				resume ? earlier->rawlog : std::filesystem::path(args.rawlog.getValue());
			avm::io::useImagesFolderOf(rawlog);

			mrpt::config::CConfigFileMemory ini(
				earlier && !args.config.isSet() ? earlier->ini : readIni(args.config.getValue()));
			std::vector<Override> overrides;
			for (const auto& assignment : args.set.getValue()) overrides.push_back(parseOverride(assignment));
			if (args.gui.getValue()) overrides.push_back(parseOverride("pipeline:gui=true"));
			const auto loaded = loadPipeline(ini, iniSource, overrides);
			auto& pipeline = *loaded;
			// Process-wide: the ini's OpenCV threads apply to the whole run.
			if (pipeline.openCvThreads() > 0) cv::setNumThreads(pipeline.openCvThreads());
			pipeline.setMinLoggingLevel(mrpt::system::LVL_INFO);
			if (args.poses.isSet())
				pipeline.setPoseSource(avm::pipeline::poseSourceFromString(args.poses.getValue()));
			else if (continues && !args.config.isSet())
				pipeline.setPoseSource(earlier->poseSource);  // PREV's, as its configuration

			RunObservers observers(outDir, pipeline.options().checkpointIntervalSeconds);
			observers.connect(pipeline, args, rawlog);
			viewOpened = observers.view.has_value();

			std::signal(SIGINT, onSignal);
			std::signal(SIGTERM, onSignal);
			const auto summary = withProgressBar(args.quiet.getValue(),
				[&](const Progress& progress)
				{
					if (resume) return pipeline.resume(observers.checkpoints.file(), outDir, &stopRequested, progress);
					if (continues)
						return pipeline.continueRun(
							args.continueFrom.getValue(), rawlog, outDir, &stopRequested, progress);
					return pipeline.run(rawlog, outDir, &stopRequested, progress);
				});
			printSummary(summary, outDir);
			return summary.interrupted ? 130 : 0;
		});
	if (viewOpened) avm::viewer::exitAfterView(status);
	return status;
}
