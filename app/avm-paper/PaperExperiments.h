// The paper's evaluation (Choi & Shin 2025) re-run on a real rawlog with
// MappingPipeline, written as doc/results.md:
//  - Table 1: occupied voxels of the low-only, high-only and adaptive maps
//    (paper: 641 / 6415 / 4225 at 1.5 m / 0.5 m), for the paper policy and for
//    the region policy;
//  - Table 2: map size when the high-resolution share of the run is 0, 30, 50,
//    70, 100 % (the switch forced at 100, 70, 50, 30, 0 % of the frames)
//    (paper: 0.454, 1.1, 1.4, 1.6, 1.7 KB);
//  - avm's per-person regions (ini/default.ini, follow and persist, and the
//    paper policy at the same resolutions) against single-resolution
//    OctoMaps built from the same frames and poses in the same run: memory,
//    .bt bytes, occupied voxels, detail inside and outside the regions, map
//    stage time, and the person tracks;
//  - all with ground-truth and with odometry poses, and the odometry's ATE.
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <filesystem>
#include <string>
#include <vector>

namespace avm::apps::paper
{
struct PaperExperimentSettings
{
	std::filesystem::path rawlog;
	std::filesystem::path baseIni;      //!< ini/paper.ini
	std::filesystem::path regionIni;    //!< ini/default.ini, for the per-person regions
	std::filesystem::path projectRoot;  //!< for the model path
	std::filesystem::path workDir;      //!< one folder per run
	std::filesystem::path results;      //!< doc/results.md (pictures beside it in results/)
	std::string command;                //!< the command line, quoted in the results
	/** The section of `results` this run writes, titled so (e.g. "The whole
	 *  sequence"); empty: the whole document. Either way the sections other
	 *  runs wrote into `results` are kept. */
	std::string section;
	bool withOdometry = true;  //!< also every run with odometry poses
};

/** Runs every experiment and writes the results. Throws on any failed run. */
void reproducePaper(const PaperExperimentSettings& settings, mrpt::system::COutputLogger& log);
}  // namespace avm::apps::paper
