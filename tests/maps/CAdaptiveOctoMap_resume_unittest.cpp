// Checkpoints (`avm-map --resume`): a map serialized mid-run and read
// back must go on exactly as the map that was never interrupted. Real Bonn
// frames, persons observed on some of them so that regions start, move, end
// and coarsen on both sides of the checkpoint; after the checkpoint both maps
// take the same frames and sightings, and must serialize to the same bytes
// after every frame.
#include <gtest/gtest.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>
#include <octomap/OcTree.h>

#include <cstdint>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "BonnFrames.h"
#include "avm/plugin/CAdaptiveOctoMap.h"

using avm::CAdaptiveOctoMap;
using avm::Resolution;
using avm::test::MapFrame;

namespace
{
/** The checkpoint: after frames 0..kCheckpoint. A second one (of the resumed
 *  map, read into a map that already holds other data) after
 *  kSecondCheckpoint. */
constexpr std::size_t kCheckpoint = 10, kSecondCheckpoint = 20;

/** Two "persons" as pixel boxes: A at the image centre on frames 3..9, B left
 *  of it on frames 5..12 and again on 20..22. With region_end_after_s 1.5 s
 *  (9 frames) A's region ends after the checkpoint, B's too, and B's comes
 *  back after the second checkpoint. */
std::vector<avm::persons::PixelSet> personsOn(std::size_t i)
{
	const auto& obs = *avm::test::firstBonnFrames().at(i).obs;
	const int rows = obs.rangeImage.rows(), cols = obs.rangeImage.cols();
	std::vector<avm::persons::PixelSet> out;
	if (i >= 3 && i <= 9)
		out.push_back(
			avm::persons::pixelsOfBox(cols / 2 - 30, rows / 2 - 60, cols / 2 + 30, rows / 2 + 60, cols, rows));
	if ((i >= 5 && i <= 12) || (i >= 20 && i <= 22))
		out.push_back(
			avm::persons::pixelsOfBox(cols / 2 - 200, rows / 2 - 60, cols / 2 - 140, rows / 2 + 60, cols, rows));
	return out;
}

/** Frame i as the pipeline gives it: its persons, then the frame. */
void step(CAdaptiveOctoMap& map, std::size_t i)
{
	const auto& f = avm::test::firstBonnFrames().at(i);
	const auto persons = personsOn(i);
	if (!persons.empty()) map.observePersons(*f.obs, f.pose, persons, f.index);
	ASSERT_TRUE(map.insertObservation(*f.obs, f.pose)) << "frame " << f.index;
}

std::string bytesOf(const CAdaptiveOctoMap& map)
{
	mrpt::io::CMemoryStream buf;
	auto arch = mrpt::serialization::archiveFrom(buf);
	arch << map;
	return std::string(static_cast<const char*>(buf.getRawBufferData()), buf.getTotalBytesCount());
}

/** What a checkpoint file would hold, read back as a new object. */
std::shared_ptr<CAdaptiveOctoMap> restoredAsNewObject(const CAdaptiveOctoMap& map)
{
	mrpt::io::CMemoryStream buf;
	auto arch = mrpt::serialization::archiveFrom(buf);
	arch << map;
	buf.Seek(0);
	return std::dynamic_pointer_cast<CAdaptiveOctoMap>(arch.ReadObject());
}

/** The same, read into an existing map (whatever it held before). */
void restoreInto(const CAdaptiveOctoMap& map, CAdaptiveOctoMap& into)
{
	mrpt::io::CMemoryStream buf;
	auto arch = mrpt::serialization::archiveFrom(buf);
	arch << map;
	buf.Seek(0);
	arch >> into;
}

std::size_t leaves(const CAdaptiveOctoMap& map, Resolution which)
{
	const auto* t = map.tree(which);
	return t ? t->getNumLeafNodes() : 0;
}

/** Everything observable of the two maps, then their bytes. */
void expectSameMap(const CAdaptiveOctoMap& a, const CAdaptiveOctoMap& b, const std::string& where)
{
	SCOPED_TRACE(where);
	EXPECT_EQ(a.insertionCount(), b.insertionCount());
	EXPECT_EQ(a.switchInsertionIndex(), b.switchInsertionIndex());
	ASSERT_EQ(a.highResolutionRegions().size(), b.highResolutionRegions().size());
	for (std::size_t r = 0; r < a.highResolutionRegions().size(); r++)
	{
		const auto &ra = a.highResolutionRegions()[r], &rb = b.highResolutionRegions()[r];
		EXPECT_EQ(ra.regionId, rb.regionId);
		EXPECT_EQ(a.regionClocks().unseenInViewSeconds(ra.regionId), b.regionClocks().unseenInViewSeconds(rb.regionId))
			<< "person " << ra.regionId;
		ASSERT_EQ(ra.boxes.size(), rb.boxes.size());
		for (std::size_t k = 0; k < ra.boxes.size(); k++) EXPECT_EQ(ra.boxes[k].asString(), rb.boxes[k].asString());
	}
	ASSERT_EQ(a.personTracks().size(), b.personTracks().size());
	for (std::size_t t = 0; t < a.personTracks().size(); t++)
	{
		const auto &ta = a.personTracks()[t], &tb = b.personTracks()[t];
		EXPECT_EQ(ta.id, tb.id);
		EXPECT_EQ(ta.lastFrame, tb.lastFrame);
		EXPECT_EQ(ta.lastTime, tb.lastTime);
		EXPECT_EQ(ta.sightings, tb.sightings);
		EXPECT_EQ(ta.position.asString(), tb.position.asString());
	}
	for (const auto which : {Resolution::Low, Resolution::High})
	{
		SCOPED_TRACE(which == Resolution::Low ? "low tree" : "high tree");
		ASSERT_EQ(a.tree(which) == nullptr, b.tree(which) == nullptr);
		EXPECT_EQ(leaves(a, which), leaves(b, which));
		if (a.tree(which))
		{
			EXPECT_EQ(a.tree(which)->size(), b.tree(which)->size());
		}
		// What a run reports of the map (run summary): the same too.
		const auto sa = which == Resolution::Low ? a.lowResolutionStats() : a.highResolutionStats();
		const auto sb = which == Resolution::Low ? b.lowResolutionStats() : b.highResolutionStats();
		EXPECT_EQ(sa.occupiedLeaves, sb.occupiedLeaves);
		EXPECT_EQ(sa.freeLeaves, sb.freeLeaves);
		EXPECT_EQ(sa.memoryBytes, sb.memoryBytes);
		EXPECT_EQ(sa.binaryBytes, sb.binaryBytes);
	}
	const auto bytesA = bytesOf(a), bytesB = bytesOf(b);
	if (bytesA != bytesB)
	{
		std::size_t at = 0;
		while (at < bytesA.size() && at < bytesB.size() && bytesA[at] == bytesB[at]) at++;
		ADD_FAILURE() << "serialized maps differ: " << bytesA.size() << " vs " << bytesB.size()
					  << " bytes, first difference at byte " << at;
	}
}

struct RunFacts
{
	std::size_t regionsEndedAfterCheckpoint = 0, regionsStartedAfterCheckpoint = 0;
	std::size_t regionsAtCheckpoint = 0;
};

std::set<std::uint32_t> regionIds(const CAdaptiveOctoMap& map)
{
	std::set<std::uint32_t> ids;
	for (const auto& r : map.highResolutionRegions()) ids.insert(r.regionId);
	return ids;
}

/** Runs every frame through `original`. After each, the map must read back
 *  as itself (a checkpoint may come after any frame). From kCheckpoint on, a
 *  map restored there (a new object) takes the same frames and is compared
 *  with the original after every frame; at kSecondCheckpoint it is
 *  checkpointed again, read into `reused`, which goes on in its place. */
RunFacts runAndResume(CAdaptiveOctoMap& original, CAdaptiveOctoMap& reused)
{
	RunFacts facts;
	const std::size_t end = avm::test::firstBonnFrames().size();
	EXPECT_GT(end, kSecondCheckpoint + 5);
	std::shared_ptr<CAdaptiveOctoMap> resumed;
	CAdaptiveOctoMap* current = nullptr;
	for (std::size_t i = 0; i < end; i++)
	{
		const std::string where =
			"frame " + std::to_string(avm::test::firstBonnFrames().at(i).index) + " (index " + std::to_string(i) + ")";
		const auto before = regionIds(original);
		step(original, i);
		if (current) step(*current, i);
		if (i > kCheckpoint)
		{
			const auto after = regionIds(original);
			for (const auto id : before) facts.regionsEndedAfterCheckpoint += !after.count(id);
			for (const auto id : after) facts.regionsStartedAfterCheckpoint += !before.count(id);
		}
		const auto restored = restoredAsNewObject(original);
		EXPECT_TRUE(restored);
		if (!restored) return facts;
		expectSameMap(original, *restored, "restored after " + where);
		if (current)
			expectSameMap(original, *current, "resumed at index " + std::to_string(kCheckpoint) + ", after " + where);
		if (::testing::Test::HasFailure()) return facts;  // the first frame that differs says most
		if (i == kCheckpoint)
		{
			facts.regionsAtCheckpoint = original.highResolutionRegions().size();
			resumed = restored;
			current = resumed.get();
		}
		if (i == kSecondCheckpoint)
		{
			restoreInto(*current, reused);
			current = &reused;
			expectSameMap(original, reused, "restored into a used map after " + where);
		}
	}
	return facts;
}

/** A map that already holds other frames, a fixed region and other options:
 *  reading a checkpoint into it must leave nothing of that. */
CAdaptiveOctoMap usedMap()
{
	CAdaptiveOctoMap::TInsertionOptions other;
	other.regionLifetime = avm::RegionLifetime::Persist;
	avm::persons::TPersonLayerOptions people;
	people.regionMargin = 0.4;
	people.tracking.gate = 0.3;
	CAdaptiveOctoMap map({}, other, {}, people);
	const auto& f = avm::test::firstBonnFrames().back();
	map.addHighResolutionRegion(
		{f.pose.translation() - mrpt::math::TPoint3D(1, 1, 1), f.pose.translation() + mrpt::math::TPoint3D(1, 1, 1)});
	map.observePersons(*f.obs, f.pose, personsOn(7), f.index);
	for (std::size_t i = avm::test::firstBonnFrames().size() - 3; i < avm::test::firstBonnFrames().size(); i++)
		EXPECT_TRUE(map.insertObservation(*avm::test::firstBonnFrames()[i].obs, avm::test::firstBonnFrames()[i].pose));
	return map;
}
}  // namespace

// Region policy, follow lifetime (the default): regions move with their
// person and end once in view and unseen for region_end_after_s, on both
// sides of the checkpoint.
TEST(CAdaptiveOctoMapResume, FollowRegionsContinueExactlyAfterACheckpoint)
{
	CAdaptiveOctoMap original;
	ASSERT_EQ(original.insertionOptions.switchPolicy, avm::SwitchPolicy::Region);
	ASSERT_EQ(original.insertionOptions.regionLifetime, avm::RegionLifetime::Follow);
	auto reused = usedMap();
	const auto facts = runAndResume(original, reused);
	std::cout << "follow: " << facts.regionsAtCheckpoint << " regions at the checkpoint, "
			  << facts.regionsEndedAfterCheckpoint << " ended and " << facts.regionsStartedAfterCheckpoint
			  << " started after it; " << original.personTracks().size() << " person tracks\n";
	EXPECT_GE(facts.regionsAtCheckpoint, 2u);
	EXPECT_GE(facts.regionsEndedAfterCheckpoint, 1u) << "the test should see a region end after the checkpoint";
	EXPECT_GE(facts.regionsStartedAfterCheckpoint, 1u);
}

// Region policy, persist lifetime: every place a person has been stays high
// resolution; boxes are joined as the persons move.
TEST(CAdaptiveOctoMapResume, PersistRegionsContinueExactlyAfterACheckpoint)
{
	CAdaptiveOctoMap::TInsertionOptions ins;
	ins.regionLifetime = avm::RegionLifetime::Persist;
	CAdaptiveOctoMap original({}, ins, {});
	auto reused = usedMap();
	const auto facts = runAndResume(original, reused);
	std::size_t boxes = 0;
	for (const auto& r : original.highResolutionRegions()) boxes += r.boxes.size();
	std::cout << "persist: " << original.highResolutionRegions().size() << " regions, " << boxes << " boxes\n";
	EXPECT_GE(facts.regionsAtCheckpoint, 2u);
	EXPECT_EQ(facts.regionsEndedAfterCheckpoint, 0u);
}

// Paper policy: the first sighting (frame 3) switches the whole map to the high
// tree, filtered by Algorithm 2 against the frozen low tree.
TEST(CAdaptiveOctoMapResume, PaperPolicyContinuesExactlyAfterACheckpoint)
{
	CAdaptiveOctoMap::TInsertionOptions ins;
	ins.switchPolicy = avm::SwitchPolicy::Paper;
	CAdaptiveOctoMap original({}, ins, {});
	auto reused = usedMap();
	runAndResume(original, reused);
	EXPECT_EQ(original.switchInsertionIndex(), std::optional<std::size_t>(3));
	EXPECT_GT(leaves(original, Resolution::High), 0u);
}
