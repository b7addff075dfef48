// The follow lifetime of the persons' regions: only time in view and after
// the person's last sighting counts, a sighting restarts the clock, a paused
// recording counts as a second, and a clock survives the stream.
#include <gtest/gtest.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>

#include "avm/persons/RegionClocks.h"

using avm::persons::RegionClocks;
using avm::persons::RegionInView;
using mrpt::math::TBoundingBox;

namespace
{
const auto always = [](const TBoundingBox&) { return true; };
const auto never = [](const TBoundingBox&) { return false; };
}  // namespace

TEST(RegionClocks, FollowRegionsAgeOnlyInViewAndAfterTheirLastSighting)
{
	RegionClocks clocks;
	const std::vector<RegionInView> regions{{1, TBoundingBox({0.0, 0.0, 0.0}, {0.6, 0.6, 1.8})}};
	clocks.seen(1, 10.0, true);
	EXPECT_TRUE(clocks.age(9.0, true, regions, 1.0, always).empty()) << "the first image has no time before it";
	// Time before the sighting does not count.
	EXPECT_TRUE(clocks.age(10.0, true, regions, 1.0, always).empty());
	EXPECT_NEAR(clocks.unseenInViewSeconds(1), 0.0, 1e-12);
	// Out of view: nothing counts.
	EXPECT_TRUE(clocks.age(10.9, true, regions, 1.0, never).empty());
	EXPECT_TRUE(clocks.age(20.0, true, regions, 1.0, never).empty());
	EXPECT_TRUE(clocks.age(20.6, true, regions, 1.0, always).empty());
	EXPECT_NEAR(clocks.unseenInViewSeconds(1), 0.6, 1e-9);
	// A sighting restarts the clock.
	clocks.seen(1, 20.7, false);
	EXPECT_TRUE(clocks.age(21.5, true, regions, 1.0, always).empty());
	EXPECT_NEAR(clocks.unseenInViewSeconds(1), 0.8, 1e-9);
	EXPECT_EQ(clocks.age(21.8, true, regions, 1.0, always), std::vector<std::uint32_t>{1});
	EXPECT_EQ(clocks.unseenInViewSeconds(1), 0.0) << "an ended region's clock is forgotten";
}

TEST(RegionClocks, APausedRecordingCountsAsASecondAndPersistCountsNothing)
{
	RegionClocks clocks;
	const std::vector<RegionInView> regions{{4, TBoundingBox({0.0, 0.0, 0.0}, {0.6, 0.6, 1.8})}};
	clocks.seen(4, 5.0, true);
	EXPECT_TRUE(clocks.age(5.0, false, regions, 10.0, always).empty());
	EXPECT_TRUE(clocks.age(8.0, false, regions, 10.0, always).empty());
	EXPECT_EQ(clocks.unseenInViewSeconds(4), 0.0) << "persist: regions never age";
	EXPECT_TRUE(clocks.age(30.0, true, regions, 10.0, always).empty());
	EXPECT_NEAR(clocks.unseenInViewSeconds(4), 1.0, 1e-12) << "22 s without images count as one";
	// A region of the same person made again starts afresh.
	clocks.seen(4, 2.0, true);
	EXPECT_TRUE(clocks.age(30.5, true, regions, 10.0, always).empty());
	EXPECT_NEAR(clocks.unseenInViewSeconds(4), 0.5, 1e-12);
}

TEST(RegionClocks, AClockAndTheImageTimeSurviveTheStream)
{
	RegionClocks original;
	const std::vector<RegionInView> regions{{2, TBoundingBox({0.0, 0.0, 0.0}, {0.6, 0.6, 1.8})}};
	original.seen(2, 1.0, true);
	original.age(1.0, true, regions, 5.0, always);
	original.age(1.4, true, regions, 5.0, always);
	mrpt::io::CMemoryStream buf;
	auto arch = mrpt::serialization::archiveFrom(buf);
	original.writeClock(arch, 2);
	original.writeImageTime(arch);
	buf.Seek(0);
	RegionClocks restored;
	restored.readClock(arch, 2);
	restored.readImageTime(arch);
	EXPECT_NEAR(restored.unseenInViewSeconds(2), 0.4, 1e-12);
	// Both go on the same: the image time and the last sighting came along.
	original.age(1.7, true, regions, 5.0, always);
	restored.age(1.7, true, regions, 5.0, always);
	EXPECT_EQ(restored.unseenInViewSeconds(2), original.unseenInViewSeconds(2));
	EXPECT_NEAR(restored.unseenInViewSeconds(2), 0.7, 1e-12);
}
