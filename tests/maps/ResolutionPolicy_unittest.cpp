// The resolution policy on small synthetic inputs: the region space as the
// union of the persons' voxels, the voxels that enter and leave it, persist
// and paper policy, and a restored policy going on as the original.
#include <gtest/gtest.h>
#include <mrpt/math/TBoundingBox.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <optional>
#include <set>
#include <vector>

#include "OcTreeKeys.h"
#include "ResolutionPolicy.h"
#include "SerializationCopy.h"

using namespace avm;
using namespace avm::detail;
using mrpt::math::TBoundingBox;

namespace
{
std::size_t voxels(const TBoundingBox& b, double res)
{
	std::size_t n = 1;
	for (int i = 0; i < 3; i++) n *= static_cast<std::size_t>(std::lround((b.max[i] - b.min[i]) / res));
	return n;
}
}  // namespace

TEST(ResolutionPolicy, RegionSpaceIsTheExactUnionOfEachPersonsVoxels)
{
	ResolutionPolicy policy(SwitchPolicy::Region, 0.2);
	// Two people 4 m apart, boxes off the grid: grown to whole low voxels.
	policy.placeRegion(1, TBoundingBox({0.05, 0.05, 0.0}, {0.55, 0.55, 1.7}), RegionLifetime::Follow, 0);
	policy.placeRegion(2, TBoundingBox({4.05, 0.05, 0.0}, {4.55, 0.55, 1.7}), RegionLifetime::Follow, 0);
	const TBoundingBox aligned1({0.0, 0.0, 0.0}, {0.6, 0.6, 1.8});
	auto change = policy.takeSpaceChange();
	EXPECT_EQ(change.entered.size(), 2 * voxels(aligned1, 0.2));
	EXPECT_TRUE(change.left.empty());
	EXPECT_TRUE(policy.inHighResolutionSpace({0.1, 0.1, 1.7}));
	EXPECT_FALSE(policy.inHighResolutionSpace({2.0, 0.3, 1.0})) << "the space between them";
	EXPECT_TRUE(std::is_sorted(change.entered.begin(), change.entered.end()));

	// Follow: person 1 steps 0.4 m along x: the space it left leaves, the
	// space it reaches enters, the overlap stays.
	policy.placeRegion(1, TBoundingBox({0.45, 0.05, 0.0}, {0.95, 0.55, 1.7}), RegionLifetime::Follow, 1);
	change = policy.takeSpaceChange();
	EXPECT_EQ(change.entered.size(), voxels(TBoundingBox({0.6, 0.0, 0.0}, {1.0, 0.6, 1.8}), 0.2));
	EXPECT_EQ(change.left.size(), voxels(TBoundingBox({0.0, 0.0, 0.0}, {0.4, 0.6, 1.8}), 0.2));
	EXPECT_EQ(policy.regions().size(), 2u);

	// Ending person 2 gives all of its space back; an unknown person nothing.
	EXPECT_TRUE(policy.endRegion(2));
	EXPECT_FALSE(policy.endRegion(2));
	EXPECT_FALSE(policy.endRegion(0)) << "fixed regions are not a person's";
	change = policy.takeSpaceChange();
	EXPECT_EQ(change.left.size(), voxels(aligned1, 0.2));
	EXPECT_TRUE(change.entered.empty());
}

namespace
{
/** The packed low keys of a grid-aligned box, counted by hand. */
std::set<std::uint64_t> lowKeysOf(const TBoundingBox& b, double res)
{
	std::set<std::uint64_t> keys;
	for (double x = b.min.x + res / 2; x < b.max.x; x += res)
		for (double y = b.min.y + res / 2; y < b.max.y; y += res)
			for (double z = b.min.z + res / 2; z < b.max.z; z += res)
			{
				std::uint64_t k = 0;
				EXPECT_TRUE(packedKeyOf(x, y, z, 1 / res, k));
				keys.insert(k);
			}
	return keys;
}
std::vector<std::uint64_t> minus(const std::set<std::uint64_t>& a, const std::set<std::uint64_t>& b)
{
	std::vector<std::uint64_t> out;
	std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
	return out;
}
std::set<std::uint64_t> joined(const std::set<std::uint64_t>& a, const std::set<std::uint64_t>& b)
{
	auto out = a;
	out.insert(b.begin(), b.end());
	return out;
}
}  // namespace

// The voxels themselves, not only how many: overlapping boxes share voxels,
// which stay while either box holds them; changes that undo each other before
// the trees catch up, and sightings that move nothing, report nothing.
TEST(ResolutionPolicy, SpaceChangesNameTheVoxelsThatEnterAndLeave)
{
	ResolutionPolicy policy(SwitchPolicy::Region, 0.2);
	const TBoundingBox a({0.0, 0.0, 0.0}, {0.6, 0.6, 1.8}), b({0.4, 0.2, 0.0}, {1.0, 0.8, 1.8}),
		c({2.0, 0.0, 0.0}, {2.6, 0.6, 1.8});
	const auto ka = lowKeysOf(a, 0.2), kb = lowKeysOf(b, 0.2), kc = lowKeysOf(c, 0.2);
	ASSERT_LT(joined(ka, kb).size(), ka.size() + kb.size()) << "a and b must overlap";

	policy.placeRegion(1, a, RegionLifetime::Follow, 0);
	policy.placeRegion(2, b, RegionLifetime::Follow, 0);
	auto change = policy.takeSpaceChange();
	EXPECT_EQ(change.entered, minus(joined(ka, kb), {}));
	EXPECT_TRUE(change.left.empty());

	change = policy.takeSpaceChange();
	EXPECT_TRUE(change.entered.empty() && change.left.empty()) << "nothing changed";
	policy.placeRegion(1, a, RegionLifetime::Follow, 1);
	change = policy.takeSpaceChange();
	EXPECT_TRUE(change.entered.empty() && change.left.empty()) << "seen where it was";
	policy.placeRegion(1, c, RegionLifetime::Follow, 2);
	policy.placeRegion(1, a, RegionLifetime::Follow, 2);
	change = policy.takeSpaceChange();
	EXPECT_TRUE(change.entered.empty() && change.left.empty()) << "moved away and back before the trees caught up";

	// Person 1 moves from a to c: what b still holds of a stays.
	policy.placeRegion(1, c, RegionLifetime::Follow, 3);
	change = policy.takeSpaceChange();
	EXPECT_EQ(change.entered, minus(kc, {}));
	EXPECT_EQ(change.left, minus(ka, kb));

	EXPECT_TRUE(policy.endRegion(2));
	change = policy.takeSpaceChange();
	EXPECT_TRUE(change.entered.empty());
	EXPECT_EQ(change.left, minus(kb, {}));

	EXPECT_TRUE(policy.endRegion(1));
	change = policy.takeSpaceChange();
	EXPECT_EQ(change.left, minus(kc, {}));
	EXPECT_FALSE(policy.hasSwitched());
	EXPECT_FALSE(policy.boxes().covers(*kc.begin(), 1)) << "no space left";
}

// What the integrator asks of every key: whether its voxel lies in the
// space, for the low grid and for grids 3 and 4 times finer, against the
// boxes themselves.
TEST(ResolutionPolicy, AVoxelIsCoveredExactlyWhenItsCentreIsInABox)
{
	ResolutionPolicy policy(SwitchPolicy::Region, 0.2);
	const std::vector<TBoundingBox> boxes{TBoundingBox({-0.6, -0.4, 0.0}, {0.2, 0.4, 1.0}),
		TBoundingBox({0.0, 0.2, 0.4}, {0.8, 1.0, 1.2}), TBoundingBox({3.0, -1.0, -0.2}, {3.4, -0.6, 0.2})};
	for (std::uint32_t i = 0; i < boxes.size(); i++) policy.placeRegion(i + 1, boxes[i], RegionLifetime::Follow, 0);
	const auto& space = policy.boxes();
	for (const unsigned ratio : {1u, 3u, 4u})
	{
		const double res = 0.2 / ratio;
		std::size_t inside = 0;
		for (double x = -1.0 + res / 2; x < 4.0; x += res)
			for (double y = -1.4 + res / 2; y < 1.4; y += res)
				for (double z = -0.6 + res / 2; z < 1.6; z += res)
				{
					std::uint64_t k = 0;
					ASSERT_TRUE(packedKeyOf(x, y, z, 1 / res, k));
					const auto c = centreOf(k, res);
					const bool expected = std::any_of(boxes.begin(), boxes.end(),
						[&](const TBoundingBox& b) { return Region{b}.contains(c.x, c.y, c.z); });
					ASSERT_EQ(space.covers(k, ratio), expected)
						<< c.x << " " << c.y << " " << c.z << " ratio " << ratio;
					inside += expected;
				}
		EXPECT_GT(inside, 0u);
	}
}

TEST(ResolutionPolicy, PersistKeepsEveryPlaceAndMergesExactly)
{
	ResolutionPolicy policy(SwitchPolicy::Region, 0.2);
	policy.placeRegion(1, TBoundingBox({0.0, 0.0, 0.0}, {0.6, 0.6, 1.8}), RegionLifetime::Persist, 0);
	policy.placeRegion(1, TBoundingBox({0.1, 0.1, 0.1}, {0.5, 0.5, 1.7}), RegionLifetime::Persist, 1);
	EXPECT_EQ(policy.regions().at(0).boxes.size(), 1u) << "a box already covered adds nothing";
	policy.placeRegion(1, TBoundingBox({0.6, 0.0, 0.0}, {1.2, 0.6, 1.8}), RegionLifetime::Persist, 2);
	ASSERT_EQ(policy.regions().at(0).boxes.size(), 1u) << "boxes that extend each other exactly merge";
	EXPECT_NEAR(policy.regions().at(0).boxes[0].max.x, 1.2, 1e-9);
	policy.placeRegion(1, TBoundingBox({3.0, 3.0, 0.0}, {3.6, 3.6, 1.8}), RegionLifetime::Persist, 3);
	EXPECT_EQ(policy.regions().at(0).boxes.size(), 2u) << "a far box is a box of its own, not a bounding box";
	EXPECT_FALSE(policy.inHighResolutionSpace({2.0, 2.0, 1.0}));
}

TEST(ResolutionPolicy, PaperPolicySwitchesAtTheFirstPersonAndSerializes)
{
	ResolutionPolicy paper(SwitchPolicy::Paper, 1.5);
	EXPECT_FALSE(paper.hasSwitched());
	paper.placeRegion(3, TBoundingBox({0, 0, 0}, {1, 1, 1}), RegionLifetime::Follow, 7);
	EXPECT_TRUE(paper.hasSwitched());
	EXPECT_EQ(paper.switchIndex(), std::optional<std::size_t>(7));
	EXPECT_TRUE(paper.regions().empty());
	EXPECT_THROW(ResolutionPolicy(SwitchPolicy::Region, 0.2).switchToHighResolution(0), std::logic_error);
	EXPECT_THROW(paper.addFixedRegion(TBoundingBox({0, 0, 0}, {0, 1, 1}), 0), std::invalid_argument);

	ResolutionPolicy region(SwitchPolicy::Region, 0.2);
	region.placeRegion(1, TBoundingBox({0, 0, 0}, {0.6, 0.6, 1.8}), RegionLifetime::Persist, 0);
	region.placeRegion(1, TBoundingBox({3, 3, 0}, {3.6, 3.6, 1.8}), RegionLifetime::Persist, 1);
	ResolutionPolicy restored(SwitchPolicy::Region, 0.2);
	test::copyBySerialization(region, restored);
	ASSERT_EQ(restored.regions().size(), 1u);
	EXPECT_EQ(restored.regions()[0].boxes.size(), 2u);
	EXPECT_TRUE(restored.takeSpaceChange().entered.empty()) << "the serialized trees already hold it";
}

// A checkpoint's policy goes on as the original: the next change reports the
// same space entering and leaving (what the trees must refine and coarsen).
// Read back with nothing marked as applied, it would report all of its space
// as entering and none as leaving: the space a region leaves would then stay
// in the high tree for good.
TEST(ResolutionPolicy, ARestoredPolicyReportsTheSameSpaceChangesAsTheOriginal)
{
	ResolutionPolicy original(SwitchPolicy::Region, 0.2);
	original.placeRegion(1, TBoundingBox({0.05, 0.05, 0.0}, {0.55, 0.55, 1.7}), RegionLifetime::Follow, 0);
	original.placeRegion(2, TBoundingBox({2.05, 0.05, 0.0}, {2.55, 0.55, 1.7}), RegionLifetime::Follow, 0);
	original.takeSpaceChange();  // the trees caught up, as after every insertion
	ResolutionPolicy restored(SwitchPolicy::Region, 0.2);
	test::copyBySerialization(original, restored);

	// Person 1 steps 0.4 m along x, person 2 leaves.
	for (auto* p : {&original, &restored})
	{
		p->placeRegion(1, TBoundingBox({0.45, 0.05, 0.0}, {0.95, 0.55, 1.7}), RegionLifetime::Follow, 1);
		EXPECT_TRUE(p->endRegion(2));
	}
	const auto expected = original.takeSpaceChange(), got = restored.takeSpaceChange();
	EXPECT_FALSE(expected.entered.empty());
	EXPECT_FALSE(expected.left.empty());
	EXPECT_EQ(got.entered, expected.entered);
	EXPECT_EQ(got.left, expected.left);
}
