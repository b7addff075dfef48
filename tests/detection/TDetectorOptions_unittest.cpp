#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <filesystem>
#include <fstream>

#include "avm/detection/TDetectorOptions.h"
#include "avm/io/IniOptions.h"

using namespace avm::detection;

TEST(TDetectorOptions, SaveAndLoadRoundTripWithTheSameKeys)
{
	TDetectorOptions a;
	a.model = "some/model.onnx";
	a.layout = OutputLayout::Yolov8;
	a.classes = "person, traffic light";
	a.score_threshold = 0.5;
	a.input_width = 640;
	mrpt::config::CConfigFileMemory cfg;
	a.saveToConfigFile(cfg, "detection");
	TDetectorOptions b;
	b.loadFromConfigFile(cfg, "detection");
	EXPECT_EQ(b.model, a.model);
	EXPECT_EQ(b.layout, OutputLayout::Yolov8);
	EXPECT_EQ(b.classIds(), (std::vector<int>{0, 9}));
	EXPECT_DOUBLE_EQ(b.score_threshold, 0.5);
	EXPECT_EQ(b.input_width, 640);
	std::vector<std::string> keys;
	cfg.getAllKeys("detection", keys);
	EXPECT_EQ(keys.size(), 10u);
}

TEST(TDetectorOptions, BadValuesNameSectionAndKey)
{
	const std::pair<const char*, const char*> bad[] = {{"score_threshold", "1.5"}, {"nms_threshold", "0"},
		{"input_width", "400"}, {"layout", "yolov9"}, {"classes", "person, unicorn"}, {"threads", "-2"}};
	for (const auto& [key, value] : bad)
	{
		mrpt::config::CConfigFileMemory cfg(std::string("[det]\n") + key + " = " + value + "\n");
		TDetectorOptions o;
		try
		{
			o.loadFromConfigFile(cfg, "det");
			ADD_FAILURE() << key << " = " << value << " accepted";
		}
		catch (const std::invalid_argument& e)
		{
			EXPECT_NE(std::string(e.what()).find(std::string("[det] ") + key), std::string::npos) << e.what();
		}
	}
}

TEST(TDetectorOptions, RelativeModelPathsStartAtTheGivenRoot)
{
	EXPECT_EQ(resolveModelPath("datasets/models/m.onnx", "/repo"), "/repo/datasets/models/m.onnx");
	EXPECT_EQ(resolveModelPath("/abs/m.onnx", "/repo"), "/abs/m.onnx");
	EXPECT_EQ(resolveModelPath("", "/repo"), "");
}

TEST(TDetectorOptions, QuotedEmptyModelMeansTheHogDetector)
{
	mrpt::config::CConfigFileMemory cfg("[detection]\nmodel = \"\"   // HOG\n");
	TDetectorOptions o;
	o.loadFromConfigFile(cfg, "detection");
	EXPECT_EQ(o.model, "");
}

// MRPT's read_int/read_double read "abc" as 0; the options say what is wrong.
TEST(TDetectorOptions, ValuesThatAreNotNumbersAreReportedAsSuch)
{
	const std::pair<const char*, const char*> bad[] = {
		{"input_width", "abc"}, {"score_threshold", "high"}, {"threads", "1.5"}, {"hog_hit_threshold", ""}};
	for (const auto& [key, value] : bad)
	{
		mrpt::config::CConfigFileMemory cfg(std::string("[detection]\n") + key + " = " + value + "\n");
		TDetectorOptions o;
		try
		{
			o.loadFromConfigFile(cfg, "detection");
			ADD_FAILURE() << key << " = " << value << " accepted";
		}
		catch (const std::invalid_argument& e)
		{
			const std::string what = e.what();
			EXPECT_EQ(what.rfind(std::string("[detection] ") + key + " = ", 0), 0u) << what;
			EXPECT_TRUE(what.find("not a number") != std::string::npos ||
						what.find("not a whole number") != std::string::npos ||
						what.find("empty value") != std::string::npos)
				<< what;
		}
	}
}

// hog_hit_threshold's default 0 is saved as "0": a file's 0.5 was once taken
// for a bad whole number ("not a whole number") when the key types were
// guessed from the saved defaults; the declared type decides.
TEST(TDetectorOptions, AFractionWhereTheDefaultIsWholeLoadsFromAFile)
{
	const auto file = std::filesystem::path(testing::TempDir()) / "detect-fraction.ini";
	std::ofstream(file) << "[detection]\nhog_hit_threshold = 0.5\n";
	std::vector<std::string> unknown;
	const auto o = avm::io::loadOptionsFromFile<TDetectorOptions>(file, "detection", unknown);
	EXPECT_EQ(o.hog_hit_threshold, 0.5);
	EXPECT_TRUE(unknown.empty());
	std::filesystem::remove(file);
}
