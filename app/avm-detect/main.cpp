// avm-detect: person detection on an image or over a rawlog (labelled rawlog +
// detection list), and the detector latency benchmark.
#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#include <iostream>

#include "DetectApp.h"
#include "avm/detection/Detector.h"
#include "avm/io/IniOptions.h"
#include "avm/io/ProgramMain.h"

using namespace avm::detection;
using namespace avm::apps::detect;

int main(int argc, char** argv)
{
	return avm::io::runProgram("avm-detect", "Detects persons (COCO classes) on an image or every frame of a rawlog.",
		[&](avm::io::CommandLine& cmd)
		{
			TCLAP::ValueArg<std::string> argConfig(
				"c", "config", "ini with a [detection] section (e.g. ini/detect.ini)", false, "", "INI", cmd);
			TCLAP::ValueArg<std::string> argModel(
				"m", "model", "ONNX model (overrides the ini; \"\" = HOG people detector)", false, "", "FILE", cmd);
			TCLAP::ValueArg<std::string> argRoot("", "root",
				"folder that relative ini model paths start from (default: working folder)", false, "", "DIR", cmd);
			TCLAP::ValueArg<std::string> argImage("i", "image", "detect on this image", false, "", "FILE", cmd);
			TCLAP::ValueArg<std::string> argAnnotated(
				"a", "annotate", "with --image: write the image with the boxes drawn (PNG)", false, "", "OUT.png", cmd);
			TCLAP::ValueArg<std::string> argRawlog(
				"r", "rawlog", "detect over this rawlog", false, "", "IN.rawlog", cmd);
			TCLAP::ValueArg<std::string> argOut("o", "out",
				"with --rawlog: labelled rawlog to write (+ OUT_detections.txt, OUT_Images link)", false, "",
				"OUT.rawlog", cmd);
			TCLAP::ValueArg<unsigned> argEvery(
				"", "every", "with --out: run the detector on every N-th frame (default 1)", false, 1, "N", cmd);
			TCLAP::SwitchArg argBench(
				"", "bench", "with --rawlog: time the detector per frame with 1 and 2 OpenCV threads", cmd);
			TCLAP::ValueArg<unsigned> argBenchFrames(
				"", "bench-frames", "with --bench: frames to use (default 0 = all)", false, 0, "N", cmd);
			TCLAP::SwitchArg argQuiet("q", "quiet", "no progress bar", cmd);
			cmd.parse(argc, argv);

			TDetectorOptions opt;
			if (argConfig.isSet())
			{
				std::vector<std::string> unknown;
				opt = avm::io::loadOptionsFromFile<TDetectorOptions>(argConfig.getValue(), "detection", unknown);
				for (const auto& k : unknown)
					std::cerr << "avm-detect: warning: " << argConfig.getValue() << ": "
							  << avm::io::unknownKeyWarning("detection", k) << "\n";
			}
			if (argModel.isSet())
				opt.model = argModel.getValue().empty() ? "" : std::filesystem::absolute(argModel.getValue()).string();
			if (opt.threads > 0) cv::setNumThreads(opt.threads);
			if (argImage.isSet() == argRawlog.isSet())
				throw std::runtime_error("give exactly one of --image and --rawlog");
			if (argRawlog.isSet()) avm::io::useImagesFolderOf(argRawlog.getValue());

			const auto detector = createDetector(opt, argRoot.getValue());
			std::cerr << "avm-detect: detector: " << detector->description() << "\n";
			if (argImage.isSet())
			{
				const cv::Mat bgr = cv::imread(argImage.getValue(), cv::IMREAD_COLOR);
				if (bgr.empty()) throw std::runtime_error(argImage.getValue() + ": cannot read as an image");
				const auto detections = detector->detect(bgr);
				for (const auto& d : detections) std::cout << formatDetection(d) << "\n";
				if (argAnnotated.isSet()) writeImage(argAnnotated.getValue(), drawDetections(bgr, detections));
				return 0;
			}
			if (argBench.getValue())
			{
				const auto images = loadColourImages(argRawlog.getValue(), argBenchFrames.getValue());
				std::vector<DetectorBenchmark> rows;
				for (int threads : {1, 2})
				{
					cv::setNumThreads(threads);
					rows.push_back(benchmarkDetector(*detector, images, threads));
				}
				std::cout << benchmarkTable(rows);
				return 0;
			}
			if (!argOut.isSet()) throw std::runtime_error("--rawlog needs --out OUT.rawlog (or --bench)");
			avm::io::ProgressBar bar(argQuiet.getValue());
			const auto summary = labelRawlog(*detector, argRawlog.getValue(), argOut.getValue(), argEvery.getValue(),
				[&bar](double fraction) { bar.show(fraction); });
			std::cout << summaryText(summary);
			return 0;
		});
}
