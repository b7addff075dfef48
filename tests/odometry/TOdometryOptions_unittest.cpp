#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <fstream>

#include "TestData.h"
#include "avm/odometry/OdometryRun.h"
#include "avm/odometry/TOdometryOptions.h"
#include "avm/odometry/VisualOdometry.h"

using namespace avm;

TEST(TOdometryOptions, SaveAndLoadUseTheSameKeys)
{
	odometry::TOdometryOptions a;
	a.num_features = 777;
	a.mask_people = false;
	a.huber_delta = 1.5;
	mrpt::config::CConfigFileMemory cfg;
	a.saveToConfigFile(cfg, "odometry");
	odometry::TOdometryOptions b;
	b.loadFromConfigFile(cfg, "odometry");
	EXPECT_EQ(b.num_features, 777);
	EXPECT_FALSE(b.mask_people);
	EXPECT_DOUBLE_EQ(b.huber_delta, 1.5);
	std::vector<std::string> keys;
	cfg.getAllKeys("odometry", keys);
	EXPECT_EQ(keys.size(), 43u);
}

TEST(TOdometryOptions, BadValueNamesSectionAndKey)
{
	mrpt::config::CConfigFileMemory cfg("[vo]\nwindow_size = 1\n");
	odometry::TOdometryOptions o;
	try
	{
		o.loadFromConfigFile(cfg, "vo");
		ADD_FAILURE() << "window_size = 1 accepted";
	}
	catch (const std::invalid_argument& e)
	{
		EXPECT_NE(std::string(e.what()).find("[vo] window_size = 1"), std::string::npos) << e.what();
	}
	o = {};
	o.max_depth = 0.1;
	EXPECT_THROW(o.validate("odometry"), std::invalid_argument);
	EXPECT_THROW(odometry::VisualOdometry{o}, std::invalid_argument);
	o = {};
	o.refine_rounds = 0;
	EXPECT_THROW(odometry::VisualOdometry{o}, std::invalid_argument);
	o = {};
	o.pyramid_scale = 0.5;  // OpenCV would reject it too, but with its own message
	EXPECT_THROW(odometry::VisualOdometry{o}, std::invalid_argument);
	EXPECT_THROW(
		odometry::VisualOdometry({}, mrpt::poses::CPose3D(std::nan(""), 0, 0, 0, 0, 0)), std::invalid_argument);
	// The motion prior (on by default) needs keyframes that keep their tracked pose.
	mrpt::config::CConfigFileMemory prior("[odometry]\nkeyframe_tracked_pose = false\n");
	o = {};
	try
	{
		o.loadFromConfigFile(prior, "odometry");
		ADD_FAILURE() << "motion_prior_sigma without keyframe_tracked_pose accepted";
	}
	catch (const std::invalid_argument& e)
	{
		EXPECT_NE(std::string(e.what()).find("keyframe_tracked_pose"), std::string::npos) << e.what();
	}
}

TEST(TOdometryOptions, ProjectIniLoadsWithoutUnknownKeys)
{
	std::vector<std::string> unknown;
	const auto o =
		odometry::loadOdometryOptions(std::string(AVM_SOURCE_DIR) + "/ini/odometry.ini", "odometry", unknown);
	EXPECT_TRUE(unknown.empty()) << unknown.front();
	EXPECT_TRUE(o.mask_people);
	// The built-in odometry is ini/default.ini's.
	const auto fromDefaultIni =
		odometry::loadOdometryOptions(std::string(AVM_SOURCE_DIR) + "/ini/default.ini", "odometry", unknown);
	EXPECT_TRUE(unknown.empty()) << unknown.front();
	mrpt::config::CConfigFileMemory builtIn, fromFile;
	odometry::TOdometryOptions().saveToConfigFile(builtIn, "odometry");
	fromDefaultIni.saveToConfigFile(fromFile, "odometry");
	EXPECT_EQ(fromFile.getContent(), builtIn.getContent());

	const auto dir = test::scratchDir("odometry-ini");
	std::ofstream(dir / "typo.ini") << "[odometry]\nnum_featurs = 10\n";
	odometry::loadOdometryOptions(dir / "typo.ini", "odometry", unknown);
	ASSERT_EQ(unknown.size(), 1u);
	EXPECT_EQ(unknown.front(), "num_featurs");
	EXPECT_THROW(odometry::loadOdometryOptions(dir / "missing.ini", "odometry", unknown), std::runtime_error);
}
