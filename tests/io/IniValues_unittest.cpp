// Ini values read as what they are (io::parseIniValue, readIniValue) and
// errors as the programs print them (io::errorMessage, rethrowNamingIniSource),
// MRPT's call-stack wrappers included.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/exceptions.h>

#include <cstdint>

#include "avm/io/ErrorMessage.h"
#include "avm/io/IniOptions.h"

using namespace avm;

namespace
{
/** The message parseIniValue<T> throws for `text`, or "" when it reads it. */
template <class T>
std::string rejection(const std::string& text)
{
	try
	{
		io::parseIniValue<T>("s", "k", text);
	}
	catch (const std::invalid_argument& e)
	{
		return e.what();
	}
	return "";
}

void throwsInsideMrpt() { THROW_EXCEPTION("[s] k = 1: thrown by THROW_EXCEPTION"); }
void wrappedByMrpt(void (*f)())
{
	MRPT_START
	f();
	MRPT_END
}
void throwsPlain() { throw std::invalid_argument("[s] k = 2: a plain error"); }
}  // namespace

TEST(IniValues, NumbersAreRead)
{
	EXPECT_EQ(io::parseIniValue<int>("s", "k", " 42 "), 42);
	EXPECT_EQ(io::parseIniValue<int>("s", "k", "-7"), -7);
	EXPECT_EQ(io::parseIniValue<int>("s", "k", "1e3"), 1000);
	EXPECT_EQ(io::parseIniValue<unsigned>("s", "k", "+5"), 5u);
	EXPECT_EQ(io::parseIniValue<std::int64_t>("s", "k", "8000000000"), 8000000000);
	EXPECT_DOUBLE_EQ(io::parseIniValue<double>("s", "k", "0.25"), 0.25);
	EXPECT_DOUBLE_EQ(io::parseIniValue<double>("s", "k", "-1e-3"), -1e-3);
	EXPECT_TRUE(io::parseIniValue<bool>("s", "k", "True"));
	EXPECT_TRUE(io::parseIniValue<bool>("s", "k", "yes"));
	EXPECT_FALSE(io::parseIniValue<bool>("s", "k", "0"));
}

TEST(IniValues, EachBadValueIsNamedForWhatItIs)
{
	EXPECT_EQ(rejection<int>("abc"), "[s] k = abc: not a number");
	EXPECT_EQ(rejection<double>("0.5m"), "[s] k = 0.5m: not a number");
	EXPECT_EQ(rejection<double>("0x10"), "[s] k = 0x10: not a number");
	EXPECT_EQ(rejection<double>("nan"), "[s] k = nan: not a number");
	EXPECT_EQ(rejection<int>(""), "[s] k = \"\": empty value, a number needed");
	EXPECT_EQ(rejection<double>("  "), "[s] k = \"\": empty value, a number needed");
	EXPECT_EQ(rejection<bool>(""), "[s] k = \"\": empty value, true or false needed");
	EXPECT_EQ(rejection<bool>("maybe"), "[s] k = maybe: not true or false");
	EXPECT_EQ(rejection<int>("2.5"), "[s] k = 2.5: not a whole number");
	EXPECT_EQ(rejection<int>("3000000000"), "[s] k = 3000000000: out of range (-2147483648..2147483647)");
	EXPECT_EQ(rejection<unsigned>("-1"), "[s] k = -1: out of range (0..4294967295)");
	EXPECT_EQ(rejection<double>("1e999"), "[s] k = 1e999: out of range of a number");
}

TEST(IniValues, ReadIniValueKeepsTheDefaultOfAnAbsentKey)
{
	const mrpt::config::CConfigFileMemory ini("[s]\nk = 12 // a comment\nempty =\n");
	EXPECT_EQ(io::readIniValue(ini, "s", "k", 1), 12);
	EXPECT_EQ(io::readIniValue(ini, "s", "K", 1), 12) << "MRPT reads keys without regard to case";
	EXPECT_EQ(io::readIniValue(ini, "s", "absent", 7), 7);
	EXPECT_THROW(io::readIniValue(ini, "s", "empty", 7), std::invalid_argument);
}

TEST(ErrorMessages, MrptsCallStackAndLocationAreLeftOut)
{
	for (auto thrower : {throwsInsideMrpt, throwsPlain}) try
		{
			wrappedByMrpt(thrower);
			FAIL() << "nothing thrown";
		}
		catch (const std::exception& e)
		{
			ASSERT_NE(std::string(e.what()).find("Call stack backtrace"), std::string::npos) << e.what();
			EXPECT_EQ(io::errorMessage(e),
				thrower == throwsPlain ? "[s] k = 2: a plain error" : "[s] k = 1: thrown by THROW_EXCEPTION");
		}
}

TEST(ErrorMessages, LinesAreJoined)
{
	EXPECT_EQ(io::errorMessage(std::runtime_error("first\n  second \n\nthird\n")), "first; second; third");
}

TEST(ErrorMessages, AnIniKeyErrorIsNamedWithItsFileAndKeepsTheOriginal)
{
	try
	{
		io::namingIniFile("run.ini", [] { wrappedByMrpt(throwsPlain); });
		FAIL() << "nothing thrown";
	}
	catch (const std::invalid_argument& e)
	{
		EXPECT_STREQ(e.what(), "run.ini: [s] k = 2: a plain error");
		try
		{
			std::rethrow_if_nested(e);
			FAIL() << "the original is not nested";
		}
		catch (const mrpt::ExceptionWithCallBackBase& original)
		{
			EXPECT_EQ(original.originalWhat, "[s] k = 2: a plain error");
		}
	}
	// Other errors name their own file already and go on unchanged.
	EXPECT_THROW(
		io::namingIniFile("run.ini", [] { throw std::out_of_range("model.onnx: not found"); }), std::out_of_range);
	EXPECT_EQ(io::namingIniFile("run.ini", [] { return 5; }), 5);
}
