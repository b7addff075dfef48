// avm-trail: the trail moving people leave in a map: occupied volume where a
// reference built without the people's pixels says the space is free, for
// avm-map outputs and for single OctoMaps of the same frames, against both
// yardsticks (the persons' own pixels, whole boxes: avm/evaluation/TrailShare.h).
#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <fstream>
#include <iostream>

#include "avm/io/IniOptions.h"
#include "avm/io/ProgramMain.h"
#include "avm/evaluation/TrailCauses.h"
#include "avm/persons/PersonLayer.h"
#include "avm/evaluation/TrailPixels.h"
#include "avm/evaluation/TrailShare.h"

namespace
{
/** The tables on stdout; the last --pixels map's voxels to `pixelsCsv` if given. */
void print(const avm::evaluation::TrailResult& result, const std::vector<avm::evaluation::TrailCauses>& causes,
	const std::vector<avm::evaluation::TrailPixels>& pixels, const std::string& pixelsCsv)
{
	std::cout << avm::evaluation::toMarkdown(result);
	for (const auto& c : causes) std::cout << "\n" << avm::evaluation::toMarkdown(c);
	for (const auto& p : pixels) std::cout << "\n" << avm::evaluation::toMarkdown(p);
	if (pixelsCsv.empty() || pixels.empty()) return;
	std::ofstream csv(pixelsCsv);
	csv << pixels.back().voxelsCsv;
	if (!csv) throw std::runtime_error(pixelsCsv + ": cannot be written");
}
}  // namespace

int main(int argc, char** argv)
{
	return avm::io::runProgram("avm-trail", "Trail share of maps against a reference without the persons' pixels.",
		[&](avm::io::CommandLine& cmd)
		{
			TCLAP::UnlabeledValueArg<std::string> argRawlog("RAWLOG",
				"rawlog with ground truth and person labels on every frame (avm-detect --every 1)", true, "", "RAWLOG",
				cmd);
			TCLAP::MultiArg<std::string> argMap(
				"m", "map", "avm-map output folder (map_low.bt, map_high.bt) built with -p gt", false, "DIR", cmd);
			TCLAP::ValueArg<std::size_t> argFrames(
				"", "frames", "use the first N frames with ground truth (default all)", false, 0, "N", cmd);
			TCLAP::ValueArg<double> argRange(
				"", "max-range", "max range [m] of the references and single maps (default 5)", false, 5.0, "M", cmd);
			TCLAP::ValueArg<double> argHigh("", "high", "high resolution [m] (default 0.05)", false, 0.05, "M", cmd);
			TCLAP::ValueArg<double> argLow("", "low", "low resolution [m] (default 0.20)", false, 0.20, "M", cmd);
			TCLAP::ValueArg<std::string> argIni("c", "config",
				"the maps' ini: the person mask takes the person layer's keys (person_label, person_depth_band, "
				"min_person_pixels, ...) from [map_adaptiveOctoMap_00_insertOpts] (default: their built-in defaults)",
				false, "", "INI", cmd);
			TCLAP::SwitchArg argCauses("", "causes",
				"also say for each map where its trail comes from (which pixels ended in each trail voxel, and "
				"whether the run's person regions covered them then)",
				cmd);
			TCLAP::ValueArg<std::string> argAgainst("", "causes-against",
				"--causes: the yardstick whose trail is explained, person (the persons' own pixels cut) or box (whole "
				"boxes cut) (default person)",
				false, "person", "person|box", cmd);
			TCLAP::ValueArg<std::size_t> argLag(
				"", "lag", "--causes: the maps' detection_lag_frames (default 2)", false, 2, "FRAMES", cmd);
			TCLAP::ValueArg<double> argHorizon("", "horizon",
				"--causes: the maps' region_end_after_s, how long a region follows its person unseen [s] (default 1.5)",
				false, 1.5, "S", cmd);
			TCLAP::SwitchArg argPixels("", "pixels",
				"also say for each map what the pixels that ended in its trail voxels were, against the yardstick of "
				"--causes-against: the person's own (depth band), mixed (a depth edge next to the band), background "
				"behind or in front, a label with no sighting, uncut",
				cmd);
			TCLAP::ValueArg<double> argEdge("", "edge-ratio",
				"--pixels: a pixel is on a depth edge when its 3x3 depth range exceeds this fraction of its depth "
				"(default 0.05, the odometry's depth_edge_ratio)",
				false, 0.05, "F", cmd);
			TCLAP::ValueArg<std::string> argPixelsCsv("", "pixels-csv",
				"--pixels: also write each trail voxel's pixels by class to this CSV file (one map: the last -m)",
				false, "", "FILE", cmd);
			cmd.parse(argc, argv);

			avm::evaluation::TrailOptions opt;
			opt.rawlog = argRawlog.getValue();
			for (const auto& m : argMap.getValue()) opt.avmMaps.emplace_back(m);
			opt.maxFrames = argFrames.getValue();
			opt.maxRange = argRange.getValue();
			opt.highResolution = argHigh.getValue();
			opt.lowResolution = argLow.getValue();
			if (!(opt.maxRange > 0)) throw std::runtime_error("--max-range must be > 0");
			if (!(opt.highResolution > 0) || !(opt.lowResolution > opt.highResolution))
				throw std::runtime_error("--high must be > 0 and --low above it");
			if (argAgainst.getValue() != "person" && argAgainst.getValue() != "box")
				throw std::runtime_error("--causes-against must be person or box");
			const auto against = argAgainst.getValue() == "box" ? avm::evaluation::Yardstick::Boxes
																: avm::evaluation::Yardstick::PersonMask;
			if (argIni.isSet())
			{
				// The section also holds the map's own keys: no warning for them.
				std::vector<std::string> notPersonKeys;
				const auto people = avm::io::loadOptionsFromFile<avm::persons::TPersonLayerOptions>(
					argIni.getValue(), "map_adaptiveOctoMap_00_insertOpts", notPersonKeys);
				opt.personLabel = people.personLabel;
				opt.sighting = people.sighting;
			}
			avm::io::useImagesFolderOf(opt.rawlog);
			avm::io::ProgressBar bar(false);
			std::vector<avm::evaluation::TrailCauses> causes;
			std::vector<avm::evaluation::TrailPixels> pixels;
			const auto result = avm::evaluation::measureTrails(
				opt,
				[&bar](std::size_t done, std::size_t total)
				{ bar.show(double(done) / double(total), std::to_string(done) + "/" + std::to_string(total)); },
				[&](const avm::evaluation::TrailReference& high, const avm::evaluation::TrailReference& low)
				{
					for (const auto& dir : opt.avmMaps)
					{
						if (argCauses.getValue())
							causes.push_back(avm::evaluation::explainTrails(
								opt, dir, high, low, argLag.getValue(), argHorizon.getValue(), against));
						if (argPixels.getValue())
							pixels.push_back(
								avm::evaluation::classifyTrailPixels(opt, dir, high, low, against, argEdge.getValue()));
					}
				});
			print(result, causes, pixels, argPixelsCsv.getValue());
			return 0;
		});
}
