// avm-bench-map: insertion time and map size of avm::CAdaptiveOctoMap next to
// octomap's insertPointCloud, on the same frames and ground-truth poses.
#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <iostream>

#include "avm/io/ProgramMain.h"
#include "avm/evaluation/MapBenchmark.h"

int main(int argc, char** argv)
{
	return avm::io::runProgram("avm-bench-map", "Times map insertion: avm adaptive map vs octomap insertPointCloud.",
		[&](avm::io::CommandLine& cmd)
		{
			TCLAP::UnlabeledValueArg<std::string> argRawlog(
				"RAWLOG", "rawlog with ground truth (avm-tum2rawlog)", true, "", "RAWLOG", cmd);
			TCLAP::ValueArg<std::size_t> argFrames(
				"", "frames", "use the first N frames (default all)", false, 0, "N", cmd);
			TCLAP::ValueArg<double> argRange(
				"", "max-range", "max range [m] of every map (default 5)", false, 5.0, "M", cmd);
			TCLAP::MultiArg<double> argRegion("", "region",
				"region box x0 y0 z0 x1 y1 z1 [m] when the rawlog has no person labels (6 values)", false, "M", cmd);
			TCLAP::ValueArg<unsigned> argThreads("", "threads",
				"also time the region policy with N insertion threads (default 1: not)", false, 1, "N", cmd);
			TCLAP::ValueArg<std::size_t> argTurn("", "turn",
				"frames each map inserts before the next map's turn (default 1: every frame goes to every map in turn, "
				"the caches cold as in avm-map; e.g. 10: warm, as when a process only maps)",
				false, 1, "N", cmd);
			TCLAP::SwitchArg argPlain(
				"", "with-plain", "also time insertPointCloud without discretize at the high resolution (slow)", cmd);
			cmd.parse(argc, argv);

			avm::evaluation::MapBenchmarkOptions opt;
			opt.rawlog = argRawlog.getValue();
			opt.maxFrames = argFrames.getValue();
			opt.maxRange = argRange.getValue();
			opt.withPlainOctomap = argPlain.getValue();
			opt.regionThreads = argThreads.getValue();
			opt.framesPerTurn = argTurn.getValue();
			if (opt.framesPerTurn < 1) throw std::runtime_error("--turn must be >= 1");
			if (opt.regionThreads < 1 || opt.regionThreads > 16)
				throw std::runtime_error("--threads must be in [1, 16]");
			if (!(opt.maxRange > 0)) throw std::runtime_error("--max-range must be > 0");
			if (const auto& r = argRegion.getValue(); !r.empty())
			{
				if (r.size() != 6) throw std::runtime_error("--region needs 6 values (give --region six times)");
				opt.region = mrpt::math::TBoundingBox({r[0], r[1], r[2]}, {r[3], r[4], r[5]});
			}
			avm::io::useImagesFolderOf(opt.rawlog);
			avm::io::ProgressBar bar(false);
			const auto result = avm::evaluation::runMapBenchmark(opt, [&bar](std::size_t done, std::size_t total)
				{ bar.show(double(done) / double(total), std::to_string(done) + "/" + std::to_string(total)); });
			std::cout << avm::evaluation::toMarkdown(result);
			return 0;
		});
}
