// avm-tum2rawlog: a TUM RGB-D layout folder -> MRPT rawlog of
// CObservation3DRangeScan (+ CObservationRobotPose ground truth).
#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <cstdio>
#include <iostream>

#include "avm/io/ProgramMain.h"
#include "avm/io/TumToRawlog.h"

int main(int argc, char** argv)
{
	return avm::io::runProgram("avm-tum2rawlog",
		"Converts a TUM RGB-D layout folder (rgb.txt + depth.txt, or associations.txt; "
		"groundtruth.txt optional) into an MRPT rawlog.",
		[&](avm::io::CommandLine& cmd)
		{
			TCLAP::UnlabeledValueArg<std::string> argDir(
				"DATASET_DIR", "TUM layout folder", true, "", "DATASET_DIR", cmd);
			TCLAP::UnlabeledValueArg<std::string> argOut("OUT", "output .rawlog", true, "", "OUT.rawlog", cmd);
			TCLAP::ValueArg<std::string> argCamera("", "camera",
				"intrinsics preset: bonn, tum-fr1, tum-fr2, tum-fr3 (default: bonn)", false, "bonn", "NAME", cmd);
			TCLAP::ValueArg<double> argFx("", "fx", "focal length x [px], overrides the preset", false, 0, "PX", cmd);
			TCLAP::ValueArg<double> argFy("", "fy", "focal length y [px]", false, 0, "PX", cmd);
			TCLAP::ValueArg<double> argCx("", "cx", "principal point x [px]", false, 0, "PX", cmd);
			TCLAP::ValueArg<double> argCy("", "cy", "principal point y [px]", false, 0, "PX", cmd);
			TCLAP::ValueArg<double> argDepthFactor(
				"", "depth-factor", "depth PNG value per metre (default 5000)", false, 0, "N", cmd);
			TCLAP::ValueArg<double> argTolerance(
				"", "max-dt", "RGB/depth association tolerance [s] (default 0.02)", false, 0.02, "S", cmd);
			TCLAP::ValueArg<std::string> argBody("", "gt-body",
				"pose of the camera in the ground-truth body: bonn, none, or a file with a 4x4 matrix (default none)",
				false, "none", "bonn|none|FILE", cmd);
			TCLAP::SwitchArg argNoGt("", "no-gt", "ignore groundtruth.txt", cmd);
			TCLAP::SwitchArg argTrim("", "trim-to-ground-truth",
				"leave out the frames before the first and after the last ground-truth pose (listed as skipped) "
				"instead of failing on them",
				cmd);
			TCLAP::ValueArg<std::string> argFrames("", "frames",
				"only the frames FIRST..LAST (0-based, of the trimmed sequence with --trim-to-ground-truth, also with "
				"--no-gt): one session cut from a sequence",
				false, "", "FIRST:LAST", cmd);
			TCLAP::SwitchArg argEmbed("", "embed-images", "store colour images inside the rawlog", cmd);
			TCLAP::ValueArg<int> argCompression(
				"", "compression", "gzip level of the rawlog 1..9, 0 = plain file (default 1)", false, 1, "0-9", cmd);
			TCLAP::SwitchArg argQuiet("q", "quiet", "no progress bar", cmd);
			cmd.parse(argc, argv);

			avm::io::TumConversionOptions opt;
			opt.camera = avm::io::cameraPreset(argCamera.getValue());
			auto& K = opt.camera.intrinsics;
			K.setIntrinsicParamsFromValues(argFx.isSet() ? argFx.getValue() : K.fx(),
				argFy.isSet() ? argFy.getValue() : K.fy(), argCx.isSet() ? argCx.getValue() : K.cx(),
				argCy.isSet() ? argCy.getValue() : K.cy());
			if (argDepthFactor.isSet())
			{
				if (!(argDepthFactor.getValue() > 0)) throw std::runtime_error("--depth-factor must be > 0");
				opt.camera.depthFactor = argDepthFactor.getValue();
			}
			if (!(argTolerance.getValue() > 0)) throw std::runtime_error("--max-dt must be > 0");
			opt.maxTimeDifference = argTolerance.getValue();
			opt.groundTruthBodyToCamera = avm::io::groundTruthBodyToCamera(argBody.getValue());
			opt.useGroundTruth = !argNoGt.getValue();
			opt.trimToGroundTruth = argTrim.getValue();
			if (argFrames.isSet())
			{
				std::size_t first = 0, last = 0;
				char end = 0;
				if (std::sscanf(argFrames.getValue().c_str(), "%zu:%zu%c", &first, &last, &end) != 2)
					throw std::runtime_error("--frames " + argFrames.getValue() + ": expected FIRST:LAST");
				opt.frames = std::pair(first, last);
			}
			opt.embedImages = argEmbed.getValue();
			opt.compressionLevel = argCompression.getValue();

			avm::io::ProgressBar bar(argQuiet.getValue());
			const auto summary = avm::io::convertTumToRawlog(argDir.getValue(), argOut.getValue(), opt,
				[&bar](std::size_t done, std::size_t total)
				{ bar.show(double(done) / double(total), std::to_string(done) + "/" + std::to_string(total)); });

			std::cout << "frames:       " << summary.frames << "\n"
					  << "rawlog:       " << summary.rawlog.string() << "\n";
			if (!opt.embedImages) std::cout << "images:       " << summary.imagesDir.string() << "\n";
			std::cout << "ground truth: "
					  << (summary.withGroundTruth ? summary.groundTruthFile.string() : std::string("none")) << "\n"
					  << "skipped:      " << summary.skipped.size() << "\n";
			for (const auto& s : summary.skipped) std::cout << "  " << s << "\n";
			return 0;
		});
}
