// avm-odometry: the visual odometry over a rawlog (the odometry benchmark).
// Writes the TUM trajectory (camera optical frame) and per-frame stats, and
// prints ms per frame. Runs on one thread (OpenCV and Ceres).
#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <opencv2/core/utility.hpp>

#include <iostream>

#include "avm/io/IniOptions.h"
#include "avm/io/ProgramMain.h"
#include "avm/detection/Detector.h"
#include "avm/odometry/OdometryRun.h"

int main(int argc, char** argv)
{
	using namespace avm;
	return avm::io::runProgram("avm-odometry",
		"RGB-D visual odometry over a rawlog: TUM trajectory, per-frame stats, timing.",
		[&](avm::io::CommandLine& cmd)
		{
			TCLAP::UnlabeledValueArg<std::string> argRawlog("RAWLOG", "input rawlog", true, "", "IN.rawlog", cmd);
			TCLAP::UnlabeledValueArg<std::string> argOut(
				"TRAJECTORY", "output TUM trajectory", true, "", "OUT.txt", cmd);
			TCLAP::ValueArg<std::string> argConfig(
				"c", "config", "ini with an [odometry] section (default: built-in defaults)", false, "", "FILE", cmd);
			TCLAP::ValueArg<std::string> argStats(
				"", "stats", "per-frame CSV (time, inliers, RMSE, status)", false, "", "FILE.csv", cmd);
			TCLAP::ValueArg<std::string> argLoops("", "loops",
				"per-loop CSV (frames, measured and tracked relative poses, their errors against the rawlog's ground "
				"truth)",
				false, "", "FILE.csv", cmd);
			TCLAP::ValueArg<std::string> argPersons("", "persons",
				"person boxes from: detector, labels (pixelLabels \"person\"), none (default detector)", false,
				"detector", "detector|labels|none", cmd);
			TCLAP::ValueArg<std::string> argModel("", "model",
				"detector ONNX model (default ../shared/models/yolox_nano.onnx)", false,
				"../shared/models/yolox_nano.onnx", "FILE", cmd);
			TCLAP::SwitchArg argNoMask("", "no-mask", "do not mask people (sets mask_people = false)", cmd);
			TCLAP::SwitchArg argStages("", "stage-times", "print the time per stage (CTimeLogger table)", cmd);
			TCLAP::ValueArg<std::size_t> argMax(
				"", "max-frames", "frames to process, 0 = all (default 0)", false, 0, "N", cmd);
			cmd.parse(argc, argv);

			cv::setNumThreads(1);
			odometry::TOdometryOptions options;
			if (argConfig.isSet())
			{
				std::vector<std::string> unknown;
				options = odometry::loadOdometryOptions(argConfig.getValue(), "odometry", unknown);
				for (const auto& k : unknown)
					std::cerr << "avm-odometry: warning: " << argConfig.getValue() << ": "
							  << io::unknownKeyWarning("odometry", k) << "\n";
			}
			if (argNoMask.getValue()) options.mask_people = false;

			odometry::PersonBoxSource persons;
			std::unique_ptr<detection::DetectorBase> detector;
			if (argPersons.getValue() == "detector")
			{
				detection::TDetectorOptions dopt;
				dopt.model = argModel.getValue();
				dopt.threads = 1;
				detector = detection::createDetector(dopt);
				persons = [&](const io::RgbdFrame& f)
				{
					std::vector<cv::Rect> boxes;
					for (const auto& d : detection::personsOnly(detector->detect(io::colourImage(*f.observation))))
						boxes.push_back(d.box);
					return boxes;
				};
			}
			else if (argPersons.getValue() == "labels")
				persons = [](const io::RgbdFrame& f) { return odometry::personBoxesFromLabels(*f.observation); };
			else if (argPersons.getValue() != "none")
				throw std::invalid_argument(
					"--persons must be detector, labels or none, not '" + argPersons.getValue() + "'");

			io::useImagesFolderOf(argRawlog.getValue());
			const auto run = odometry::runOdometry(argRawlog.getValue(), options, persons, argMax.getValue());
			io::writeTumTrajectory(
				argOut.getValue(), run.trajectory(), "avm-odometry camera optical frame in the world");
			if (argStats.isSet()) run.writeFrameStats(argStats.getValue());
			if (argLoops.isSet()) run.writeLoops(argLoops.getValue());
			std::cout << run.timingSummary() << run.loopSummary();
			if (argStages.getValue()) std::cout << run.stageTimes;
			return 0;
		});
}
