// avm-eval --walk-ins: who walks into view in a reference run's detections.txt
// and when another run found them; a missing or damaged file is named.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "TestData.h"
#include "avm/evaluation/WalkIns.h"

using namespace avm;
namespace fs = std::filesystem;

namespace
{
const char* const kHeader =
	"# frame timestamp class score x y w h | person id, region min_x min_y min_z max_x max_y max_z [m]\n";

/** An output folder whose detections.txt holds `lines` ("frame x y w h id"; id 0: no person placed). */
fs::path runWith(const fs::path& dir, const std::vector<std::string>& lines)
{
	fs::create_directories(dir);
	std::ofstream out(dir / "detections.txt");
	out << kHeader;
	for (const auto& l : lines)
	{
		std::size_t frame;
		double x, y, w, h;
		unsigned id;
		std::istringstream(l) >> frame >> x >> y >> w >> h >> id;
		out << frame << " 0.0 person 0.9 " << x << " " << y << " " << w << " " << h;
		if (id)
			out << " | " << id << " 0 0 0 1 1 1\n";
		else
			out << " | skipped: too few depth pixels\n";
	}
	return dir;
}
}  // namespace

TEST(WalkIns, ANewIdOnAPersonAlreadyInViewIsNoWalkInAndEachWalkInIsFoundWhereTheRunHasTheirBox)
{
	const auto dir = test::scratchDir("walk-ins");
	const auto reference =
		runWith(dir / "reference", {"10 0 0 50 200 1", "11 5 0 60 200 1", "12 10 0 70 200 1",
									   // the tracker gives person 1 a new id: the same box, not a walk-in
									   "13 12 0 70 200 2",
									   // person 3 steps out beside them, overlapping less than half
									   "14 12 0 70 200 2", "14 60 0 60 200 3", "15 70 0 70 200 3", "16 80 0 70 200 3",
									   // person 4 appears at frame 20, with no person placed on that frame
									   "20 400 0 60 200 0", "21 400 0 60 200 4"});
	const auto run = runWith(dir / "run", {"12 10 0 70 200 7", "16 80 0 70 200 8", "21 400 0 60 200 9"});
	const auto walkIns = evaluation::walkInsFound(run, reference);
	ASSERT_EQ(walkIns.size(), 3u);
	EXPECT_EQ(walkIns[0].person, 1u);
	EXPECT_EQ(walkIns[0].frame, 10u);
	EXPECT_EQ(walkIns[0].framesSeen, 5u) << "frames 10-14, id 1 then 2";
	ASSERT_TRUE(walkIns[0].foundAt);
	EXPECT_EQ(*walkIns[0].foundAt, 12u);
	EXPECT_EQ(walkIns[1].person, 3u);
	EXPECT_EQ(walkIns[1].frame, 14u);
	ASSERT_TRUE(walkIns[1].foundAt) << "followed by id through frames 15 and 16";
	EXPECT_EQ(*walkIns[1].foundAt, 16u);
	EXPECT_EQ(walkIns[2].person, 4u);
	EXPECT_EQ(walkIns[2].frame, 20u) << "their first box, though the map placed no person for it";
	ASSERT_TRUE(walkIns[2].foundAt);
	EXPECT_EQ(*walkIns[2].foundAt, 21u);
}

TEST(WalkIns, AMissingOrDamagedDetectionsFileIsNamed)
{
	const auto dir = test::scratchDir("walk-ins-bad");
	const auto good = runWith(dir / "good", {"1 0 0 10 10 1"});
	fs::create_directories(dir / "empty");
	try
	{
		evaluation::walkInsFound(dir / "empty", good);
		FAIL() << "no error for a folder without detections.txt";
	}
	catch (const std::runtime_error& e)
	{
		EXPECT_EQ(std::string(e.what()), (dir / "empty" / "detections.txt").string() + ": cannot be read");
	}
	fs::create_directories(dir / "damaged");
	std::ofstream(dir / "damaged" / "detections.txt") << kHeader << "3 0.0 person 0.9 1 2 three 4 | 1\n";
	try
	{
		evaluation::walkInsFound(good, dir / "damaged");
		FAIL() << "no error for a damaged line";
	}
	catch (const std::runtime_error& e)
	{
		EXPECT_EQ(
			std::string(e.what()), (dir / "damaged" / "detections.txt").string() + ":2: not a detections.txt line");
	}
}
