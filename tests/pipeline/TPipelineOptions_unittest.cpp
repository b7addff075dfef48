// [pipeline] read as what its values are: a word where a number belongs is
// "not a number", not a 0 that switches detection off.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include "avm/pipeline/MappingPipeline.h"

using namespace avm;

namespace
{
/** The message loading [pipeline] from `text` throws, or "" when it loads. */
std::string loadError(const std::string& text)
{
	mrpt::config::CConfigFileMemory ini("[pipeline]\n" + text + "\n");
	pipeline::TPipelineOptions o;
	try
	{
		o.loadFromConfigFile(ini, "pipeline");
	}
	catch (const std::invalid_argument& e)
	{
		return e.what();
	}
	return "";
}
}  // namespace

TEST(TPipelineOptions, SaveAndLoadRoundTrip)
{
	pipeline::TPipelineOptions a;
	a.poseSource = pipeline::PoseSource::GroundTruth;
	a.detectEveryN = 5;
	a.asyncMapping = false;
	a.maxFrames = 123;
	a.referenceMaps = true;
	a.mapSection = "maps";
	mrpt::config::CConfigFileMemory ini;
	a.saveToConfigFile(ini, "pipeline");
	pipeline::TPipelineOptions b;
	b.loadFromConfigFile(ini, "pipeline");
	EXPECT_EQ(b.poseSource, pipeline::PoseSource::GroundTruth);
	EXPECT_EQ(b.detectEveryN, 5u);
	EXPECT_FALSE(b.asyncMapping);
	EXPECT_EQ(b.maxFrames, 123u);
	EXPECT_TRUE(b.referenceMaps);
	EXPECT_EQ(b.mapSection, "maps");
}

TEST(TPipelineOptions, ValuesThatAreNotNumbersAreReportedAsSuch)
{
	EXPECT_EQ(loadError("detect_every_n = abc"), "[pipeline] detect_every_n = abc: not a number");
	EXPECT_EQ(loadError("max_frames = 1.5"), "[pipeline] max_frames = 1.5: not a whole number");
	EXPECT_EQ(loadError("picture_size ="), "[pipeline] picture_size = \"\": empty value, a number needed");
	EXPECT_EQ(loadError("async_mapping = maybe"), "[pipeline] async_mapping = maybe: not true or false");
}

TEST(TPipelineOptions, ValuesOutOfRangeNameSectionKeyAndRange)
{
	EXPECT_EQ(loadError("detect_every_n = -2"), "[pipeline] detect_every_n = -2: must be >= 0 (0 = no detection)");
	EXPECT_EQ(loadError("detection_lag_frames = 31"), "[pipeline] detection_lag_frames = 31: must be 0..30 frames");
	EXPECT_EQ(loadError("pose_source = slam"), "[pipeline] pose_source = slam: must be vo or gt");
	EXPECT_EQ(loadError("read_ahead_frames = 3"), "");
	EXPECT_EQ(loadError("detection_schedule = sometimes"),
		"[pipeline] detection_schedule = sometimes: must be fixed or on_change");
	EXPECT_EQ(loadError("detect_moved_share = 0"), "[pipeline] detect_moved_share = 0: must be in (0, 1]");
	EXPECT_EQ(loadError("detect_change_depth = -1"), "[pipeline] detect_change_depth = -1: must be in (0, 10] m");
}

// The on_change schedule runs the detector at most every detect_every_n-th
// frame and at least every detect_max_interval-th: the second cannot be the
// shorter.
TEST(TPipelineOptions, TheLongestDetectionIntervalIsNoShorterThanTheShortest)
{
	EXPECT_EQ(loadError("detect_every_n = 4\ndetect_max_interval = 3"),
		"[pipeline] detect_max_interval = 3: must be >= detect_every_n");
	EXPECT_EQ(loadError("detect_every_n = 4\ndetect_max_interval = 4"), "");
	EXPECT_EQ(loadError("detect_max_interval = 31"), "[pipeline] detect_max_interval = 31: must be 1..30 frames");
}

// gui and gui_fps: what avm-map makes its live view from (avm/viewer/LiveView.h).
TEST(TPipelineOptions, ReadsGuiAndGuiFpsAndNamesABadValue)
{
	mrpt::config::CConfigFileMemory ini("[pipeline]\ngui = true\ngui_fps = 10\n");
	pipeline::TPipelineOptions o;
	EXPECT_FALSE(o.gui);
	EXPECT_DOUBLE_EQ(o.guiFps, 5.0);
	o.loadFromConfigFile(ini, "pipeline");
	EXPECT_TRUE(o.gui);
	EXPECT_DOUBLE_EQ(o.guiFps, 10.0);
	EXPECT_EQ(loadError("gui_fps = 0"), "[pipeline] gui_fps = 0: out of range (0, 60]");
	EXPECT_EQ(loadError("gui_fps = 61"), "[pipeline] gui_fps = 61: out of range (0, 60]");
	EXPECT_EQ(loadError("gui_fps = abc"), "[pipeline] gui_fps = abc: not a number");
	EXPECT_EQ(loadError("gui = maybe"), "[pipeline] gui = maybe: not true or false");
}
