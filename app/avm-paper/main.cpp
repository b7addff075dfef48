// avm-paper: re-runs the paper's evaluation on a rawlog and writes doc/results.md.
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <opencv2/core/utility.hpp>

#include <iostream>

#include "avm/io/ProgramMain.h"
#include "PaperExperiments.h"

int main(int argc, char** argv)
{
	return avm::io::runProgram("avm-paper",
		"Re-runs the paper's Table 1 and Table 2 on a rawlog and writes the results.",
		[&](avm::io::CommandLine& cmd)
		{
			TCLAP::ValueArg<std::string> argRawlog(
				"r", "rawlog", "input rawlog (with ground truth)", true, "", "RAWLOG", cmd);
			TCLAP::ValueArg<std::string> argIni("c", "config", "base ini (default ini/paper.ini)", false,
				std::string(AVM_PROJECT_ROOT) + "/ini/paper.ini", "INI", cmd);
			TCLAP::ValueArg<std::string> argWork(
				"w", "work", "folder for the runs' outputs", false, "output/paper", "DIR", cmd);
			TCLAP::ValueArg<std::string> argResults("o", "results",
				"markdown to write (pictures beside it in results/)", false,
				std::string(AVM_PROJECT_ROOT) + "/doc/results.md", "FILE", cmd);
			TCLAP::SwitchArg argNoVo("", "no-odometry", "ground-truth poses only", cmd);
			TCLAP::ValueArg<std::string> argSection("", "section",
				"write the results as this titled section of the results file (e.g. \"The whole sequence\"), "
				"keeping the rest of it; without it the whole file is written (the sections other runs wrote are kept)",
				false, "", "TITLE", cmd);
			cmd.parse(argc, argv);

			avm::apps::paper::PaperExperimentSettings s;
			s.rawlog = argRawlog.getValue();
			s.baseIni = argIni.getValue();
			s.regionIni = std::string(AVM_PROJECT_ROOT) + "/ini/default.ini";
			s.projectRoot = AVM_PROJECT_ROOT;
			s.workDir = argWork.getValue();
			s.results = argResults.getValue();
			s.withOdometry = !argNoVo.getValue();
			s.section = argSection.getValue();
			s.command = "scripts/reproduce-paper.sh " + s.rawlog.stem().string();
			// OpenCV's thread count is process-wide: one, as ini/default.ini's
			// [detection] threads, so the runs measure what avm-map does.
			cv::setNumThreads(1);
			avm::io::useImagesFolderOf(s.rawlog);
			mrpt::system::COutputLogger log("avm-paper");
			log.setMinLoggingLevel(mrpt::system::LVL_INFO);
			// Every run starts from the base ini: an option error is one of its keys.
			avm::io::namingIniFile(s.baseIni.string(), [&] { avm::apps::paper::reproducePaper(s, log); });
			std::cout << "results: " << s.results.string() << "\n";
			return 0;
		});
}
