// avm-eval: ATE (after SE(3) alignment), RPE per second and the camera's acceleration of a TUM trajectory
// against a TUM ground truth; with --maps, the occupied space two avm-map runs share; with --walk-ins, how
// soon a run's detector finds the persons who walk into view.
#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "avm/io/ProgramMain.h"
#include "avm/evaluation/MapComparison.h"
#include "avm/evaluation/TrajectoryEvaluation.h"
#include "avm/evaluation/WalkIns.h"

namespace
{
void printWalkIns(const std::vector<avm::evaluation::WalkIn>& walkIns)
{
	std::size_t found = 0, frames = 0, most = 0;
	for (const auto& w : walkIns)
	{
		std::printf("walk-in  person %u at frame %zu (the reference saw them on %zu of the 30 frames from it): ",
			w.person, w.frame, w.framesSeen);
		if (!w.foundAt)
		{
			std::printf("never found\n");
			continue;
		}
		const std::size_t after = *w.foundAt - w.frame;
		std::printf("found at frame %zu (%zu frames later)\n", *w.foundAt, after);
		++found;
		frames += after;
		most = std::max(most, after);
	}
	std::printf("walk-ins %zu, found %zu, frames to find them: total %zu, mean %.2f, most %zu\n", walkIns.size(), found,
		frames, found ? double(frames) / double(found) : 0.0, most);
}
}  // namespace

int main(int argc, char** argv)
{
	return avm::io::runProgram("avm-eval",
		"ATE (SE(3)-aligned), RPE and camera acceleration of a TUM trajectory against TUM ground truth; with "
		"--maps, the occupied space of two avm-map output folders.",
		[&](avm::io::CommandLine& cmd)
		{
			TCLAP::UnlabeledValueArg<std::string> argEst("ESTIMATE",
				"estimated trajectory (TUM); with --maps or --walk-ins, an avm-map output folder", true, "", "EST.txt",
				cmd);
			TCLAP::UnlabeledValueArg<std::string> argGt("GROUNDTRUTH",
				"ground truth (TUM); with --maps, another avm-map output folder; with --walk-ins, the output folder of "
				"a run of the same rawlog with the detector on every frame",
				true, "", "GT.txt", cmd);
			TCLAP::SwitchArg argMaps("", "maps",
				"compare the occupied space of two avm-map runs instead (both trees, at the high resolution, a low "
				"voxel as the high voxels it covers): voxels of each and their intersection over union",
				cmd);
			TCLAP::SwitchArg argWalkIns("", "walk-ins",
				"the persons who walk into view in the reference run (GROUNDTRUTH: its detector on every frame, "
				"detect_every_n = 1) and the frame the run's detector (ESTIMATE) first found each at",
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
			if (argWalkIns.getValue())
			{
				printWalkIns(avm::evaluation::walkInsFound(argEst.getValue(), argGt.getValue()));
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
