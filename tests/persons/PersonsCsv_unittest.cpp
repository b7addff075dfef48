// persons.csv written by avm-map and read back by avm-view: the same tracks,
// to the precision written, and a clear error for a file that is not one.
#include <gtest/gtest.h>

#include <fstream>

#include "TestData.h"
#include "avm/persons/PersonsCsv.h"

using namespace avm::persons;

TEST(PersonsCsv, TracksComeBackAsWritten)
{
	PersonTrack a;
	a.id = 1, a.firstFrame = 70, a.lastFrame = 299, a.firstTime = 1548266469.123456, a.lastTime = 1548266479.5;
	a.position = {1.234, -0.5, 0.9};
	a.box = mrpt::math::TBoundingBox({1.0, -0.8, 0.0}, {1.5, -0.2, 1.8});
	a.sightings = 120;
	PersonTrack b = a;
	b.id = 2, b.firstFrame = 200, b.sightings = 3, b.position = {-2.0, 3.0, 1.1}, b.still = true;

	const auto file = avm::test::scratchDir("PersonsCsv") / "persons.csv";
	std::ofstream(file) << personsCsvText({a, b});
	const auto back = readPersonsCsv(file);
	ASSERT_EQ(back.size(), 2u);
	for (std::size_t i = 0; i < 2; ++i)
	{
		const auto& w = i == 0 ? a : b;
		const auto& r = back[i];
		EXPECT_EQ(r.id, w.id);
		EXPECT_EQ(r.firstFrame, w.firstFrame);
		EXPECT_EQ(r.lastFrame, w.lastFrame);
		EXPECT_NEAR(r.firstTime, w.firstTime, 1e-6);
		EXPECT_NEAR(r.lastTime, w.lastTime, 1e-6);
		EXPECT_NEAR(r.position.distanceTo(w.position), 0, 1e-3);
		EXPECT_NEAR(r.box.min.distanceTo(w.box.min), 0, 1e-3);
		EXPECT_NEAR(r.box.max.distanceTo(w.box.max), 0, 1e-3);
		EXPECT_EQ(r.sightings, w.sightings);
		EXPECT_EQ(r.still, w.still);
	}
}

TEST(PersonsCsv, ABrokenLineIsNamedByFileAndLine)
{
	const auto file = avm::test::scratchDir("PersonsCsvBroken") / "persons.csv";
	std::ofstream(file) << personsCsvText({}) << "1,70,299,0,0,1,2\n";
	try
	{
		readPersonsCsv(file);
		FAIL() << "a truncated line was accepted";
	}
	catch (const std::runtime_error& e)
	{
		EXPECT_NE(std::string(e.what()).find(file.string() + ":2:"), std::string::npos) << e.what();
	}
	EXPECT_THROW(readPersonsCsv(file.parent_path() / "missing.csv"), std::runtime_error);
}
