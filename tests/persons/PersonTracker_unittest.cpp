// Person tracks on synthetic sequences: what the ids must do when people walk
// across the view, stand side by side, cross, leave and come back.
#include <gtest/gtest.h>

#include <set>

#include "SerializationCopy.h"
#include "avm/persons/PersonTracker.h"

using namespace avm::persons;

namespace
{
PersonSighting at(double x, double y, double z = 1.0)
{
	PersonSighting s;
	s.position = {x, y, z};
	s.box = mrpt::math::TBoundingBox({x - 0.25, y - 0.25, 0.0}, {x + 0.25, y + 0.25, 1.8});
	s.points = 1000;
	return s;
}

constexpr double kStep = 0.1;  // [s] a detection every third frame at 30 Hz

bool sameBox(const mrpt::math::TBoundingBox& a, const mrpt::math::TBoundingBox& b)
{
	return a.min == b.min && a.max == b.max;
}
}  // namespace

TEST(PersonTracker, APersonWalkingAcrossTheViewKeepsOneId)
{
	PersonTracker tracker;
	std::set<std::uint32_t> ids;
	for (int k = 0; k <= 30; k++)  // 1.4 m/s for 3 s
		ids.insert(tracker.update({at(-2.0 + 1.4 * kStep * k, 3.0)}, 3 * k, 100 + kStep * k).at(0));
	EXPECT_EQ(ids.size(), 1u);
	ASSERT_EQ(tracker.tracks().size(), 1u);
	const auto& t = tracker.tracks()[0];
	EXPECT_EQ(t.sightings, 31u);
	EXPECT_EQ(t.firstFrame, 0u);
	EXPECT_EQ(t.lastFrame, 90u);
	EXPECT_DOUBLE_EQ(t.firstTime, 100.0);
	EXPECT_NEAR(t.position.x, 2.2, 1e-9);
}

TEST(PersonTracker, ATrackIsAPersonOnceConfirmedBySightings)
{
	// A person walking by, and a detector's false box seen twice elsewhere:
	// both are tracks (each had its region), only the person is confirmed.
	TrackerOptions options;
	ASSERT_EQ(options.minSightings, 3u);
	PersonTracker tracker(options);
	for (int k = 0; k < 10; k++)
	{
		std::vector<PersonSighting> seen{at(1.4 * kStep * k, 3.0)};
		if (k == 4 || k == 5) seen.push_back(at(-3.0, 6.0));
		tracker.update(seen, 3 * k, kStep * k);
		const auto persons = confirmedTracks(tracker.tracks(), options.minSightings);
		ASSERT_EQ(persons.size(), k >= 2 ? 1u : 0u) << "after " << k + 1 << " sightings";
		if (!persons.empty())
		{
			EXPECT_EQ(persons[0].id, 1u);
		}
	}
	ASSERT_EQ(tracker.tracks().size(), 2u);
	EXPECT_EQ(tracker.tracks()[1].sightings, 2u);
	// Every track is a person when one sighting confirms it.
	EXPECT_EQ(confirmedTracks(tracker.tracks(), 1).size(), 2u);
}

TEST(PersonTracker, TwoPeopleSideBySideStayTwoTracks)
{
	PersonTracker tracker;
	for (int k = 0; k <= 30; k++)
	{
		const double x = 1.0 * kStep * k;
		// The order the detector lists them in changes from frame to frame.
		const bool swap = k % 2 == 1;
		const auto a = at(x, 2.0), b = at(x, 2.7);
		const auto ids = tracker.update(swap ? std::vector{b, a} : std::vector{a, b}, 3 * k, kStep * k);
		ASSERT_EQ(ids.size(), 2u);
		EXPECT_NE(ids[0], ids[1]);
		EXPECT_EQ(swap ? ids[1] : ids[0], 1u) << "step " << k;
		EXPECT_EQ(swap ? ids[0] : ids[1], 2u) << "step " << k;
	}
	EXPECT_EQ(tracker.tracks().size(), 2u);
}

TEST(PersonTracker, TwoPeopleCrossingStayTwoTracks)
{
	PersonTracker tracker;
	for (int k = 0; k <= 40; k++)
	{
		const double s = 1.2 * kStep * k;
		tracker.update({at(-2.4 + s, 3.0), at(2.4 - s, 3.4)}, 3 * k, kStep * k);
	}
	EXPECT_EQ(tracker.tracks().size(), 2u);
	for (const auto& t : tracker.tracks()) EXPECT_EQ(t.sightings, 41u);
}

TEST(PersonTracker, APersonOutOfViewAndBackNearTheSamePlaceKeepsTheId)
{
	PersonTracker tracker;
	for (int k = 0; k < 10; k++) tracker.update({at(1.0, 2.0)}, 3 * k, kStep * k);
	// The camera looks elsewhere for 20 s; the person moved a little.
	EXPECT_EQ(tracker.update({at(1.4, 2.3)}, 600, 21.0).at(0), 1u);
	// Someone seen far from any track is somebody new.
	EXPECT_EQ(tracker.update({at(5.0, 2.0)}, 603, 21.1).at(0), 2u);
	// In the same instant, a sighting beyond the gate of a just-seen track is new too.
	EXPECT_EQ(tracker.update({at(1.4 + 0.9, 2.3)}, 606, 21.2).at(0), 3u);
	EXPECT_EQ(tracker.tracks().size(), 3u);
}

TEST(PersonTracker, TheSameSightingsGiveTheSameIdsAndSurviveSerialization)
{
	auto run = [](PersonTracker& t)
	{
		std::vector<std::uint32_t> all;
		for (int k = 0; k < 20; k++)
			for (auto id : t.update({at(0.1 * k, 1.0), at(3 - 0.1 * k, 1.5), at(1.5, 5.0)}, k, kStep * k))
				all.push_back(id);
		return all;
	};
	PersonTracker a, b;
	EXPECT_EQ(run(a), run(b));

	PersonTracker restored;
	avm::test::copyBySerialization(a, restored);
	ASSERT_EQ(restored.tracks().size(), a.tracks().size());
	for (std::size_t i = 0; i < a.tracks().size(); i++)
	{
		EXPECT_EQ(restored.tracks()[i].id, a.tracks()[i].id);
		EXPECT_EQ(restored.tracks()[i].sightings, a.tracks()[i].sightings);
		EXPECT_EQ(restored.tracks()[i].position, a.tracks()[i].position);
	}
	// And it goes on the same way.
	EXPECT_EQ(restored.update({at(2.0, 1.0)}, 50, 5.0), a.update({at(2.0, 1.0)}, 50, 5.0));
}

// A track keeps the shape of its person's last sighting, through serialization.
TEST(PersonTracker, ATrackKeepsItsLastSightingsShape)
{
	PersonTracker tracker;
	auto first = at(1.0, 1.0);
	first.shape = {{1.025f, 1.025f, 0.025f}, {1.025f, 1.025f, 0.075f}};
	auto second = at(1.1, 1.0);
	second.shape = {{1.125f, 1.025f, 0.025f}};
	tracker.update({first}, 0, 0.0);
	ASSERT_EQ(tracker.tracks().size(), 1u);
	EXPECT_EQ(tracker.tracks()[0].shape, first.shape);
	tracker.update({second}, 1, kStep);
	ASSERT_EQ(tracker.tracks().size(), 1u);
	EXPECT_EQ(tracker.tracks()[0].shape, second.shape) << "the last sighting's shape replaces the one before";
	tracker.update({}, 2, 2 * kStep);
	EXPECT_EQ(tracker.tracks()[0].shape, second.shape) << "unseen, the person keeps their last shape";

	PersonTracker restored;
	avm::test::copyBySerialization(tracker, restored);
	ASSERT_EQ(restored.tracks().size(), 1u);
	EXPECT_EQ(restored.tracks()[0].shape, second.shape);
}

// A track keeps the box of all its last sighting's points (what a moving
// person's free-only box is made of), through serialization; a stream from
// before band extents gives the track its box instead.
TEST(PersonTracker, ATrackKeepsItsLastSightingsBandExtent)
{
	PersonTracker tracker;
	auto s = at(1.0, 1.0);
	s.bandExtent = mrpt::math::TBoundingBox({0.6, 0.5, -0.1}, {1.4, 1.3, 1.9});
	tracker.update({s}, 0, 0.0);
	ASSERT_EQ(tracker.tracks().size(), 1u);
	EXPECT_TRUE(sameBox(tracker.tracks()[0].bandExtent, s.bandExtent));

	PersonTracker restored;
	avm::test::copyBySerialization(tracker, restored);
	ASSERT_EQ(restored.tracks().size(), 1u);
	EXPECT_TRUE(sameBox(restored.tracks()[0].bandExtent, s.bandExtent));

	// Version 3 of the map's stream: no band extent after the shape.
	mrpt::io::CMemoryStream buffer;
	auto out = mrpt::serialization::archiveFrom(buffer);
	tracker.serializeTo(out);
	buffer.Seek(0);
	auto in = mrpt::serialization::archiveFrom(buffer);
	PersonTracker old;
	old.serializeFrom(in, {true, true, false});
	ASSERT_EQ(old.tracks().size(), 1u);
	EXPECT_TRUE(sameBox(old.tracks()[0].bandExtent, s.box));
}
