// The detector scheduled by what changed in view ([pipeline] detection_schedule
// = on_change) on the real Bonn sequence, where a person walks in at frame 72:
// fewer detector runs than every third frame, the person found as soon, and
// the run the same with the detector on its worker thread or not.
#include <gtest/gtest.h>

#include <string>

#include "DefaultIni.h"
#include "TestData.h"
#include "avm/evaluation/WalkIns.h"
#include "avm/pipeline/MappingPipeline.h"

using namespace avm;
namespace fs = std::filesystem;

namespace
{
constexpr std::size_t kFrames = 100;

/** The default configuration on the first kFrames frames, with `changes`
 *  ("section:key=value"), its outputs written to `out`. */
pipeline::RunSummary runWith(const fs::path& out, const std::vector<std::string>& changes)
{
	auto ini = test::defaultIni();
	ini.write("pipeline", "max_frames", std::to_string(kFrames));
	ini.write("pipeline", "picture_size", "0");
	for (const auto& c : changes)
	{
		const auto colon = c.find(':'), equals = c.find('=');
		ini.write(c.substr(0, colon), c.substr(colon + 1, equals - colon - 1), c.substr(equals + 1));
	}
	return pipeline::MappingPipeline(ini, AVM_SOURCE_DIR).run(test::bonnRawlog(), out);
}
}  // namespace

TEST(PipelineDetectionSchedule, OnChangeFindsTheWalkInAsSoonAsEveryThirdFrameWithFewerRuns)
{
	const auto dir = test::scratchDir("pipeline-detection-schedule");
	const auto everyFrame = runWith(dir / "every-frame", {"pipeline:detect_every_n=1"});
	EXPECT_EQ(everyFrame.detectionRuns, kFrames);
	const auto everyThird = runWith(dir / "every-third", {});
	const auto onChange = runWith(dir / "on-change", {"pipeline:detection_schedule=on_change"});

	EXPECT_LT(onChange.detectionRuns, everyThird.detectionRuns * 3 / 4);
	EXPECT_GE(onChange.detectionRuns, kFrames / 6) << "at least every detect_max_interval-th frame";
	EXPECT_GT(onChange.detectionsStartedBy.count("moved") ? onChange.detectionsStartedBy.at("moved") : 0, 0u)
		<< "the person walking in calls the detector";
	EXPECT_EQ(everyThird.detectionsStartedBy.at("every_n"), everyThird.detectionRuns);

	const auto walkIns = evaluation::walkInsFound(dir / "on-change", dir / "every-frame");
	ASSERT_FALSE(walkIns.empty()) << "a person walks in at frame 72";
	EXPECT_EQ(walkIns.front().frame, 72u);
	for (const auto& w : walkIns)
	{
		ASSERT_TRUE(w.foundAt) << "person " << w.person << " walking in at frame " << w.frame << " never found";
		// Every third frame finds a person within two frames of the first
		// the detector can see them on.
		EXPECT_LE(*w.foundAt - w.frame, 2u) << "person " << w.person << " walking in at frame " << w.frame;
	}
}

TEST(PipelineDetectionSchedule, OnChangeRunsTheSameWithTheDetectorOnItsThreadOrNot)
{
	const auto dir = test::scratchDir("pipeline-detection-schedule-threads");
	const auto async = dir / "async", inLoop = dir / "in-loop";
	const auto a = runWith(async, {"pipeline:detection_schedule=on_change"});
	const auto b = runWith(inLoop, {"pipeline:detection_schedule=on_change", "pipeline:async_detection=false"});
	EXPECT_EQ(a.detectionsStartedBy, b.detectionsStartedBy);
	for (const char* name : {"detections.txt", "trajectory.txt", "map_high.bt"})
	{
		EXPECT_GT(test::fileBytes(async / name).size(), 100u) << name;
		EXPECT_EQ(test::fileBytes(async / name), test::fileBytes(inLoop / name)) << name;
	}
}
