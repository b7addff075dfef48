// The files a run of avm-map ends in, written from the run's summary and
// record after the last frame, each complete or absent (io::writeFileAtomically):
// map_low.bt, map_high.bt, map.3Dscene (the map), trajectory.txt,
// trajectory_status.txt, detections.txt, persons.csv, map_top.png, map_perspective.png, stats.json
// and avm-map.log.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "FrameProcessor.h"
#include "avm/io/JsonWriter.h"
#include "avm/io/Trajectory.h"
#include "avm/plugin/CAdaptiveOctoMap.h"
#include "avm/pipeline/MappingPipeline.h"

namespace avm::pipeline::detail
{
/** What a run leaves besides the map and its summary. */
struct RunRecord
{
	std::filesystem::path rawlog;
	const TPipelineOptions* options = nullptr;
	std::string detector;  //!< the detector's description, "none" without one
	io::Trajectory trajectory;
	std::vector<bool> trackedPoses;  //!< per pose: false = bridged by the odometry's motion model
	std::vector<PersonDetectionRecord> personDetections;
	std::vector<double> peakMemoryPerReplay;  //!< [MiB] at the end of each replay
	std::string log;                          //!< avm-map.log
};

/** Writes every output into outDir (which exists and is writable);
 *  `observersStats` writes the observers' sections of stats.json. */
void writeRunOutputs(const std::filesystem::path& outDir, const RunSummary& summary, const RunRecord& record,
	const CAdaptiveOctoMap& map, const std::function<void(io::JsonWriter&)>& observersStats);

/** Checks that outDir can be created and written, and removes temporaries
 *  that killed runs left in it. Throws std::runtime_error naming the folder. */
void prepareOutputFolder(const std::filesystem::path& outDir);
}  // namespace avm::pipeline::detail
