// One declaration per key drives load, save, validation and documentation
// (io::IniKeys): what is saved loads back, a failed check names section, key
// and value, and the documentation says unit and default.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "avm/io/IniKeys.h"

using namespace avm;

namespace
{
enum class Mode
{
	Fast,
	Exact
};
std::string toString(Mode m) { return m == Mode::Fast ? "fast" : "exact"; }
Mode modeFromString(const std::string& s)
{
	if (s == "fast") return Mode::Fast;
	if (s == "exact") return Mode::Exact;
	throw std::invalid_argument("unknown mode '" + s + "'");
}

struct Limits
{
	double low = 0.5, high = 2.0;
};

struct Sample
{
	unsigned count = 3;
	double ratio = 0.25;
	bool on = true;
	std::string name = "x";
	Mode mode = Mode::Fast;
	Limits limits;
};

io::IniKeys<Sample> sampleKeys()
{
	io::IniKeys<Sample> keys;
	keys.number<int>(
			"count", &Sample::count, "frames", "frames per step", {[](int v) { return v >= 1; }, "must be >= 1"})
		.number(
			"ratio", &Sample::ratio, "", "share kept", {[](double v) { return v > 0 && v <= 1; }, "must be in (0, 1]"})
		.number("on", &Sample::on, "", "switch")
		.text("name", &Sample::name, "what it is called",
			{[](const std::string& s) { return !s.empty(); }, "must not be empty"})
		.choice(
			"mode", &Sample::mode, modeFromString, [](Mode m) { return toString(m); }, "fast | exact")
		.number("low", &Sample::limits, &Limits::low, "m", "lower limit")
		.number("high", &Sample::limits, &Limits::high, "m", "upper limit")
		.check(
			"high", [](const Sample& s) { return s.limits.high > s.limits.low; },
			[](const Sample& s) { return "must be above low (" + io::iniText(s.limits.low) + ")"; });
	return keys;
}

std::string loadError(const std::string& text)
{
	mrpt::config::CConfigFileMemory ini("[s]\n" + text + "\n");
	Sample s;
	try
	{
		sampleKeys().load(s, ini, "s");
	}
	catch (const std::invalid_argument& e)
	{
		return e.what();
	}
	return "";
}
}  // namespace

TEST(IniKeys, SavedValuesLoadBackExactly)
{
	Sample a;
	a.count = 7;
	a.ratio = 0.1;
	a.on = false;
	a.name = "y";
	a.mode = Mode::Exact;
	a.limits = {1.25, 3};
	mrpt::config::CConfigFileMemory ini;
	sampleKeys().save(a, ini, "s");
	EXPECT_EQ(ini.read_string("s", "ratio", ""), "0.1");
	EXPECT_EQ(ini.read_string("s", "on", ""), "false");
	Sample b;
	sampleKeys().load(b, ini, "s");
	EXPECT_EQ(b.count, 7u);
	EXPECT_EQ(b.ratio, 0.1);
	EXPECT_FALSE(b.on);
	EXPECT_EQ(b.name, "y");
	EXPECT_EQ(b.mode, Mode::Exact);
	EXPECT_EQ(b.limits.low, 1.25);
	EXPECT_EQ(b.limits.high, 3.0);
}

TEST(IniKeys, AbsentKeysKeepTheirValues)
{
	EXPECT_EQ(loadError(""), "");
	EXPECT_EQ(loadError("ratio = 1"), "");
}

TEST(IniKeys, ErrorsNameSectionKeyValueAndWhy)
{
	EXPECT_EQ(loadError("count = -1"), "[s] count = -1: must be >= 1");
	EXPECT_EQ(loadError("count = abc"), "[s] count = abc: not a number");
	EXPECT_EQ(loadError("ratio = 1.5"), "[s] ratio = 1.5: must be in (0, 1]");
	EXPECT_EQ(loadError("on = maybe"), "[s] on = maybe: not true or false");
	EXPECT_EQ(loadError("mode = slow"), "[s] mode = slow: unknown mode 'slow'");
	EXPECT_EQ(loadError("high = 0.25"), "[s] high = 0.25: must be above low (0.5)");
}

TEST(IniKeys, ValidateChecksValuesSetInCode)
{
	Sample s;
	s.ratio = 0;
	EXPECT_THROW(sampleKeys().validate(s, "s"), std::invalid_argument);
}

TEST(IniKeys, DocumentationGivesUnitAndDefault)
{
	const auto docs = sampleKeys().documentation(Sample());
	ASSERT_EQ(docs.size(), 7u);
	EXPECT_EQ(docs[0].comment(), "frames per step [frames] (default 3)");
	EXPECT_EQ(docs[1].comment(), "share kept (default 0.25)");
	EXPECT_EQ(docs[4].comment(), "fast | exact (default fast)");
	const std::string text = io::documentIniSection("s", docs);
	EXPECT_EQ(text.substr(0, text.find('\n', 4) + 1), "[s]\ncount = 3     // frames per step [frames] (default 3)\n");
	// The documentation is an ini file the keys load.
	mrpt::config::CConfigFileMemory ini(text);
	Sample s;
	EXPECT_NO_THROW(sampleKeys().load(s, ini, "s"));
}

// A key's old name is still read, as the key, with a warning that names
// both; where both are set the new name wins; saving writes the new name only.
TEST(IniKeys, ARenamedKeyIsStillReadUnderItsOldName)
{
	auto keys = sampleKeys();
	keys.renamed("steps", "count");
	EXPECT_EQ(keys.oldKeyNames(), std::vector<std::string>{"steps"});
	Sample s;
	mrpt::config::CConfigFileMemory old("[s]\nsteps = 9\n");
	testing::internal::CaptureStderr();
	keys.load(s, old, "s");
	EXPECT_EQ(
		testing::internal::GetCapturedStderr(), "warning: [s] steps is now called count: read as count; rename it\n");
	EXPECT_EQ(s.count, 9u);

	mrpt::config::CConfigFileMemory both("[s]\nsteps = 9\ncount = 4\n");
	testing::internal::CaptureStderr();
	keys.load(s, both, "s");
	EXPECT_EQ(testing::internal::GetCapturedStderr(),
		"warning: [s] steps is now called count, which is set too: steps ignored\n");
	EXPECT_EQ(s.count, 4u);

	mrpt::config::CConfigFileMemory saved;
	keys.save(s, saved, "s");
	EXPECT_EQ(io::readIniText(saved, "s", "count"), std::optional<std::string>("4"));
	EXPECT_FALSE(io::readIniText(saved, "s", "steps"));
}
