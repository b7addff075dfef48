// avm-eval: ATE (after SE(3) alignment), RPE per second and the camera's acceleration of a TUM trajectory
// against a TUM ground truth; with --maps, the occupied space two avm-map runs share.
#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <cstdio>
#include <iostream>

#include "avm/io/ProgramMain.h"
#include "avm/evaluation/MapComparison.h"
#include "avm/evaluation/TrajectoryEvaluation.h"

int main(int argc, char** argv)
{
	return avm::io::runProgram("avm-eval",
		"ATE (SE(3)-aligned), RPE and camera acceleration of a TUM trajectory against TUM ground truth; with "
		"--maps, the occupied space of two avm-map output folders.",
		[&](avm::io::CommandLine& cmd)
		{
			TCLAP::UnlabeledValueArg<std::string> argEst("ESTIMATE",
				"estimated trajectory (TUM); with --maps, an avm-map output folder", true, "", "EST.txt", cmd);
			TCLAP::UnlabeledValueArg<std::string> argGt("GROUNDTRUTH",
				"ground truth (TUM); with --maps, another avm-map output folder", true, "", "GT.txt", cmd);
			TCLAP::SwitchArg argMaps("", "maps",
				"compare the occupied space of two avm-map runs instead (both trees, at the high resolution, a low "
				"voxel as the high voxels it covers): voxels of each and their intersection over union",
				cmd);
			TCLAP::ValueArg<double> argMaxDt(
				"", "max-dt", "max timestamp difference of a match [s] (default 0.02)", false, 0.02, "S", cmd);
			TCLAP::ValueArg<std::size_t> argFrom(
				"", "from", "index of the first estimated pose evaluated (default 0)", false, 0, "N", cmd);
			TCLAP::ValueArg<std::size_t> argMax(
				"", "max-frames", "number of estimated poses evaluated, 0 = all (default 0)", false, 0, "N", cmd);
			TCLAP::ValueArg<double> argDelta("", "rpe-delta", "RPE time step [s] (default 1)", false, 1.0, "S", cmd);
			cmd.parse(argc, argv);
			if (argMaps.getValue())
			{
				const auto c = avm::evaluation::compareOccupiedSpace(argEst.getValue(), argGt.getValue());
				std::printf("occupied space  %zu / %zu voxels of %.3f m, IoU %.4f\n", c.spaceA, c.spaceB,
					c.highResolution, c.spaceIoU);
				std::printf("low tree        %zu / %zu voxels of %.3f m, IoU %.4f\n", c.lowA, c.lowB, c.lowResolution,
					c.lowIoU);
				std::printf("high tree       %zu / %zu voxels of %.3f m, IoU %.4f\n", c.highA, c.highB,
					c.highResolution, c.highIoU);
				return 0;
			}

			avm::evaluation::TEvaluationOptions opt;
			opt.maxTimeDifference = argMaxDt.getValue();
			opt.firstFrame = argFrom.getValue();
			opt.maxFrames = argMax.getValue();
			opt.rpeDelta = argDelta.getValue();
			const auto est = avm::io::readTumTrajectory(argEst.getValue());
			const auto gt = avm::io::readTumTrajectory(argGt.getValue());
			std::cout << avm::evaluation::formatReport(avm::evaluation::evaluateTrajectory(est, gt, opt));
			return 0;
		});
}
