// The live view's text laid out for the window's width (avm/viewer/StatusText.h):
// the finished view's status lines, which ran past the right edge of a 1024 px
// window ("finished: a key (b", "low 2867 hig"), and any line in a narrower one.
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>

#include "avm/viewer/StatusText.h"

using namespace avm::viewer;

namespace
{
mrpt::opengl::TFontParams fontOf(float heightPx)
{
	mrpt::opengl::TFontParams f;
	f.vfont_scale = heightPx;
	return f;
}

/** The words of `lines`, in order: what a reader gets from them, however broken. */
std::vector<std::string> wordsOf(const std::vector<std::string>& lines)
{
	std::vector<std::string> words;
	for (const auto& line : lines)
	{
		std::istringstream in(line);
		for (std::string w; in >> w;) words.push_back(w);
	}
	return words;
}

/** A finished run's snapshot as avm-map shows it: every stage time, the note. */
MapSnapshot finishedRun()
{
	MapSnapshot s;
	s.status.frame = 300;
	s.status.frames = 300;
	s.status.fps = 29.7;
	s.status.stageMs = {{"odometry", 18.6}, {"detection", 42.1}, {"map", 10.4}};
	s.status.switchFrame = 74;
	s.status.note = "finished: a key (but f l h m r) or closing the window exits";
	s.mapMemoryBytes = 3u << 20;
	s.lowOccupied.resize(12867);
	s.highOccupied.resize(2867);
	return s;
}
}  // namespace

TEST(StatusText, TheMonoFontsWidthGrowsWithTheTextAndTheFontsHeight)
{
	const auto f14 = fontOf(14), f28 = fontOf(28);
	const double one = textWidthPx("a", f14);
	// 13 px a character at 14 px, as the Xvfb screen shows it.
	EXPECT_NEAR(one, 13.0, 0.5);
	EXPECT_NEAR(textWidthPx(std::string(40, 'a'), f14), 40 * one, 1e-6);
	EXPECT_NEAR(textWidthPx(std::string(40, 'W'), f14), 40 * one, 1e-6) << "a fixed-width font";
	EXPECT_NEAR(textWidthPx("abc", f28), 2 * textWidthPx("abc", f14), 1e-6);
	EXPECT_EQ(textWidthPx("", f14), 0.0);
}

TEST(StatusText, ALineTooLongIsBrokenBetweenItsFieldsAndLosesNoWord)
{
	const auto font = fontOf(14);
	const std::string line =
		"frame 300/300  29.7 fps  odometry 18.6 ms  detection 42.1 ms  map 10.4 ms  finished: a key (but f l h m r) "
		"or closing the window exits";
	for (const double width : {1024.0, 640.0, 400.0})
	{
		const auto lines = fitToWidth({line}, width, font, kStatusMargin);
		EXPECT_GT(lines.size(), 1u) << width;
		for (const auto& l : lines) EXPECT_LE(textWidthPx(l, font), width - 2 * kStatusMargin) << width << ": " << l;
		EXPECT_EQ(wordsOf(lines), wordsOf({line})) << width;
		// Broken between fields while they fit: no field starts mid-line unless its line holds more than one.
		EXPECT_EQ(lines.front().rfind("frame 300/300", 0), 0u) << lines.front();
		for (std::size_t k = 1; k < lines.size(); ++k)
			EXPECT_EQ(lines[k].rfind("  ", 0), 0u) << "a continued line is indented: " << lines[k];
	}
	// A wide window keeps it whole; an empty line stays.
	EXPECT_EQ(fitToWidth({line, ""}, 3000, font, kStatusMargin), (std::vector<std::string>{line, ""}));
}

TEST(StatusText, AFieldWiderThanTheWindowBreaksAtItsWordsAndAWordIsCut)
{
	const auto font = fontOf(14);
	// 13.07 px a character: 9 characters to a 146 px window with 8 px margins.
	const auto lines = fitToWidth({"finished: a key (but f l h m r)  abcdefghijklmnopqrstuvwxyz  end"}, 146, font, 8);
	for (const auto& l : lines) EXPECT_LE(textWidthPx(l, font), 130.0) << l;
	EXPECT_EQ(lines.front(), "finished:");
	EXPECT_NE(std::find(lines.begin(), lines.end(), "  abcdefg"), lines.end()) << "the word cut to its line";
	EXPECT_EQ(lines.back(), "  end");
}

TEST(StatusText, TheFinishedViewsTextFitsTheWindowAndNoLinesOverlap)
{
	ViewToggles toggles;
	toggles.freeSpace = true;  // "free from the next snapshot": the longest of what is shown
	for (const double width : {1024.0, 640.0})
	{
		const auto messages = statusMessages(finishedRun(), toggles, true, width);
		std::string all;
		std::vector<double> ys;
		for (const auto& m : messages)
		{
			EXPECT_LE(m.x + textWidthPx(m.text, m.font), width - kStatusMargin) << width << ": " << m.text;
			EXPECT_EQ(std::count(ys.begin(), ys.end(), m.y), 0) << "two lines at y " << m.y;
			ys.push_back(m.y);
			all += m.text + "\n";
		}
		const auto words = wordsOf({all});
		for (const std::string w : {"exits", "[paused]", "2867", "high", "snapshot", "view"})
			EXPECT_NE(std::find(words.begin(), words.end(), w), words.end()) << width << ": " << w << " in\n" << all;
	}
	// At 1024 px the two status lines need more than two lines: what was cut.
	const auto wide = statusMessages(finishedRun(), {}, false, 1024);
	const auto bottom = std::count_if(wide.begin(), wide.end(), [](const StatusMessage& m) { return m.y >= 0; });
	EXPECT_GT(bottom, 2);
}
