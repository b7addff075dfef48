// avm::CAdaptiveOctoMap on real data: Bonn crowd frames with ground-truth
// poses. What each test compares is stated in it.
#include <gtest/gtest.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/math/CMatrixDynamic.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/TPixelLabelInfo.h>
#include <mrpt/opengl/COctoMapVoxels.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/serialization/CArchive.h>

#include <filesystem>
#include <map>

#include "BonnFrames.h"
#include "avm/maps/OcTreeKeyLayout.h"
#include "avm/maps/OccupiedKeys.h"
#include "avm/plugin/CAdaptiveOctoMap.h"

using avm::CAdaptiveOctoMap;
using avm::Resolution;
using avm::test::firstBonnFrames;
using avm::test::MapFrame;

namespace
{
void insertAll(CAdaptiveOctoMap& map, const std::vector<MapFrame>& fs)
{
	for (const auto& f : fs) ASSERT_TRUE(map.insertObservation(*f.obs, f.pose)) << "frame " << f.index;
}

/** A box around the surface seen at the centre of the first frame. */
mrpt::math::TBoundingBox boxAheadOfFirstFrame(double halfSize)
{
	const auto& f = firstBonnFrames().front();
	const auto& img = f.obs->rangeImage;
	const double d = img(img.rows() / 2, img.cols() / 2) * f.obs->rangeUnits;
	EXPECT_GT(d, 0.3) << "no depth at the centre pixel of frame " << f.index;
	const auto p = (f.pose + f.obs->sensorPose).composePoint(mrpt::math::TPoint3D(d, 0, 0));
	const mrpt::math::TPoint3D h(halfSize, halfSize, halfSize);
	return {p - h, p + h};
}

bool overlaps(const mrpt::math::TBoundingBox& a, const mrpt::math::TBoundingBox& b)
{
	const double eps = 1e-4;  // octomap coordinates are floats
	for (int i = 0; i < 3; i++)
		if (!(a.min[i] < b.max[i] - eps && b.min[i] < a.max[i] - eps)) return false;
	return true;
}

CAdaptiveOctoMap::TCreationOptions resolutions(double low, double high)
{
	CAdaptiveOctoMap::TCreationOptions c;
	c.low.resolution = low;
	c.high.resolution = high;
	return c;
}

/** Same leaves (key, depth) with the same log-odds in both trees. */
void expectSameTree(const octomap::OcTree* a, const octomap::OcTree* b)
{
	ASSERT_EQ(a == nullptr, b == nullptr);
	if (!a) return;
	ASSERT_EQ(a->size(), b->size());
	ASSERT_DOUBLE_EQ(a->getResolution(), b->getResolution());
	std::map<std::tuple<int, int, int, int>, float> leaves;
	for (auto it = a->begin_leafs(); it != a->end_leafs(); ++it)
		leaves[{it.getKey()[0], it.getKey()[1], it.getKey()[2], static_cast<int>(it.getDepth())}] = it->getLogOdds();
	std::size_t n = 0;
	for (auto it = b->begin_leafs(); it != b->end_leafs(); ++it, ++n)
	{
		const auto found =
			leaves.find({it.getKey()[0], it.getKey()[1], it.getKey()[2], static_cast<int>(it.getDepth())});
		ASSERT_NE(found, leaves.end());
		ASSERT_EQ(found->second, it->getLogOdds());
	}
	EXPECT_EQ(n, leaves.size());
}
}  // namespace

// Algorithm 2: after the switch the high tree only takes points where the
// low tree has no node, so no occupied high leaf lies in low-tree space.
TEST(CAdaptiveOctoMapBonn, PaperPolicyKeepsHighLeavesOutOfLowSpace)
{
	CAdaptiveOctoMap::TInsertionOptions ins;
	ins.switchPolicy = avm::SwitchPolicy::Paper;
	ins.switchAtFraction = 0.5;
	CAdaptiveOctoMap map(resolutions(0.2, 0.05), ins, {});
	map.setExpectedFrameCount(firstBonnFrames().size());

	const std::size_t half = firstBonnFrames().size() / 2;
	std::string lowAtSwitch;
	for (std::size_t i = 0; i < firstBonnFrames().size(); i++)
	{
		if (i == half)
		{
			std::ostringstream s;
			map.tree(Resolution::Low)->writeBinaryConst(s);
			lowAtSwitch = s.str();
		}
		ASSERT_TRUE(map.insertObservation(*firstBonnFrames()[i].obs, firstBonnFrames()[i].pose));
	}
	ASSERT_EQ(map.switchInsertionIndex(), std::optional<std::size_t>(half));
	ASSERT_TRUE(map.hasSwitched());
	const auto* low = map.tree(Resolution::Low);
	const auto* high = map.tree(Resolution::High);
	ASSERT_TRUE(high);

	// Algorithm 1: the low tree does not change after the switch.
	std::ostringstream lowAtEnd;
	low->writeBinaryConst(lowAtEnd);
	EXPECT_EQ(lowAtEnd.str(), lowAtSwitch);

	std::size_t occupiedHigh = 0, inLowSpace = 0;
	for (auto it = high->begin_leafs(); it != high->end_leafs(); ++it)
	{
		if (!high->isNodeOccupied(*it)) continue;
		occupiedHigh++;
		if (low->search(it.getCoordinate())) inLowSpace++;
	}
	std::cout << "paper policy: " << occupiedHigh << " occupied high leaves, low tree " << low->size() << " nodes\n";
	EXPECT_GT(occupiedHigh, 0u) << "the second half of the run added nothing to the high tree";
	EXPECT_EQ(inLowSpace, 0u);
	// What the map shows agrees: every occupied high voxel it reports answers
	// as high.
	map.forEachLeaf(Resolution::High,
		[&](const avm::TLeafVoxel& v)
		{
			if (v.occupied)
			{
				EXPECT_EQ(map.query(v.center).tree, Resolution::High);
			}
		});
}

// Region policy: region space lives in the high tree only, the rest in the
// low tree only; inside the region the map matches a 0.05 m OctoMap, outside
// a 0.20 m OctoMap (both built by octomap's own insertPointCloud with
// discretize=true, the same maximum range, frames and poses).
TEST(CAdaptiveOctoMapBonn, RegionPolicyMatchesSingleResolutionOctoMapsInsideAndOutside)
{
	const double maxRange = 5.0;
	CAdaptiveOctoMap map(resolutions(0.2, 0.05), {}, {});
	map.addHighResolutionRegion(boxAheadOfFirstFrame(0.6));
	const auto region = map.highResolutionRegions().at(0).boxes.at(0);

	octomap::OcTree refHigh(0.05), refLow(0.2);
	for (const auto& f : firstBonnFrames())
	{
		ASSERT_TRUE(map.insertObservation(*f.obs, f.pose));
		avm::test::insertWithOctomap(refHigh, f, maxRange);
		avm::test::insertWithOctomap(refLow, f, maxRange);
	}

	// No space held twice: no leaf of the low tree (free or occupied, any
	// size) overlaps the region.
	const auto* low = map.tree(Resolution::Low);
	std::size_t lowInRegion = 0;
	for (auto it = low->begin_leafs(); it != low->end_leafs(); ++it)
	{
		const auto c = it.getCoordinate();
		const double h = 0.5 * it.getSize();
		if (overlaps({{c.x() - h, c.y() - h, c.z() - h}, {c.x() + h, c.y() + h, c.z() + h}}, region)) lowInRegion++;
	}
	EXPECT_EQ(lowInRegion, 0u);

	auto inRegion = [&](double x, double y, double z) { return region.containsPoint({x, y, z}); };
	auto outside = [&](double x, double y, double z) { return !region.containsPoint({x, y, z}); };
	const auto highMine = avm::occupiedFinestKeys(*map.tree(Resolution::High), inRegion);
	const auto highRef = avm::occupiedFinestKeys(refHigh, inRegion);
	const auto lowMine = avm::occupiedFinestKeys(*low, outside);
	const auto lowRef = avm::occupiedFinestKeys(refLow, outside);
	const double iouInside = avm::intersectionOverUnion(highMine, highRef);
	const double iouOutside = avm::intersectionOverUnion(lowMine, lowRef);
	std::cout << "inside the region: " << highMine.size() << " occupied 0.05 m voxels vs " << highRef.size()
			  << " in the reference, IoU " << iouInside << "\noutside: " << lowMine.size()
			  << " occupied 0.20 m voxels vs " << lowRef.size() << ", IoU " << iouOutside << "\n";
	EXPECT_GT(highRef.size(), 100u) << "the region holds too little surface for a meaningful comparison";
	EXPECT_GE(iouInside, 0.9);
	EXPECT_GE(iouOutside, 0.9);

	// Queries answer with the tree that owns the space.
	const auto centre = (region.min + region.max) * 0.5;
	EXPECT_EQ(map.query(centre).tree, Resolution::High);
	EXPECT_DOUBLE_EQ(map.query(centre).resolution, 0.05);
	EXPECT_EQ(map.query(region.max + mrpt::math::TPoint3D(0.5, 0.5, 0.5)).tree, Resolution::Low);
	const auto hs = map.highResolutionStats(), ls = map.lowResolutionStats();
	EXPECT_EQ(hs.occupiedLeaves + ls.occupiedLeaves, map.getAsSimplePointsMap()->size());
	EXPECT_GT(hs.memoryBytes, 0u);
	EXPECT_GT(ls.binaryBytes, 0u);
}

// A person label on the observation defines the region: a rawlog labelled
// once drives the map in any app.
TEST(CAdaptiveOctoMapBonn, PersonPixelLabelsCreateARegionAroundThosePoints)
{
	auto f = firstBonnFrames().front();
	auto labelled = mrpt::obs::CObservation3DRangeScan::Create(*f.obs);
	auto labels = std::make_shared<mrpt::obs::TPixelLabelInfo<1>>();
	const int rows = labelled->rangeImage.rows(), cols = labelled->rangeImage.cols();
	labels->setSize(rows, cols);
	labels->setLabelName(0, "chair");
	labels->setLabelName(1, "person");
	// A 60 x 120 pixel patch at the image centre as the "person".
	for (int r = rows / 2 - 60; r < rows / 2 + 60; r++)
		for (int c = cols / 2 - 30; c < cols / 2 + 30; c++) labels->setLabel(r, c, 1);
	labelled->pixelLabels = labels;

	// Two separate blobs under the same label are two people, two regions.
	{
		auto twoPeople = mrpt::obs::CObservation3DRangeScan::Create(*labelled);
		auto two = std::make_shared<mrpt::obs::TPixelLabelInfo<1>>(*labels);
		for (int r = rows / 2 - 60; r < rows / 2 + 60; r++)
			for (int c = 20; c < 80; c++) two->setLabel(r, c, 1);
		twoPeople->pixelLabels = two;
		CAdaptiveOctoMap map2;
		ASSERT_TRUE(map2.insertObservation(*twoPeople, f.pose));
		EXPECT_EQ(map2.highResolutionRegions().size(), 2u);
		EXPECT_EQ(map2.personTracks().size(), 2u);
		// The space between the two people stays low resolution.
		const auto a = map2.highResolutionRegions()[0].boxes.at(0), b = map2.highResolutionRegions()[1].boxes.at(0);
		EXPECT_EQ(map2.query((a.min + a.max + b.min + b.max) * 0.25).tree, Resolution::Low);
	}
	// A label of its own per person ("person/<k>", as avm-detect writes): one
	// person even where its pixels form several blobs.
	{
		auto split = mrpt::obs::CObservation3DRangeScan::Create(*labelled);
		auto own = std::make_shared<mrpt::obs::TPixelLabelInfo<1>>();
		own->setSize(rows, cols);
		own->setLabelName(0, "person");
		own->setLabelName(2, "person/1");
		for (int r = rows / 2 - 60; r < rows / 2 + 60; r++)
			for (int c = cols / 2 - 30; c < cols / 2 + 30; c++)
				if (c != cols / 2) own->setLabel(r, c, 2);  // a gap splits it in two blobs
		split->pixelLabels = own;
		CAdaptiveOctoMap map3;
		ASSERT_TRUE(map3.insertObservation(*split, f.pose));
		EXPECT_EQ(map3.personTracks().size(), 1u);
	}

	CAdaptiveOctoMap map;
	ASSERT_TRUE(map.insertObservation(*labelled, f.pose));
	ASSERT_EQ(map.highResolutionRegions().size(), 1u);
	EXPECT_EQ(map.switchInsertionIndex(), std::optional<std::size_t>(0));
	ASSERT_EQ(map.personTracks().size(), 1u);
	EXPECT_EQ(map.highResolutionRegions()[0].regionId, map.personTracks()[0].id);
	const auto region = map.highResolutionRegions()[0].boxes.at(0);
	const double d = labelled->rangeImage(rows / 2, cols / 2) * labelled->rangeUnits;
	const auto centre = (f.pose + labelled->sensorPose).composePoint(mrpt::math::TPoint3D(d, 0, 0));
	EXPECT_TRUE(region.containsPoint(centre)) << region.asString() << " vs " << centre.asString();
	// Margin 0.3 m on a patch of about 0.2 x 0.45 m at 2-3 m: well under 2 m.
	const auto size = region.max - region.min;
	EXPECT_LT(size.norm(), 3.0) << region.asString();
	// The labelled frame itself was mapped with the region in place.
	EXPECT_GT(map.highResolutionStats().occupiedLeaves, 0u);

	// Labels of another name do nothing.
	CAdaptiveOctoMap other;
	other.personOptions.personLabel = "dog";
	ASSERT_TRUE(other.insertObservation(*labelled, f.pose));
	EXPECT_FALSE(other.hasSwitched());
}

namespace
{
/** A 60 x 120 pixel "person" at the image centre. */
std::vector<avm::persons::PixelSet> personAtCentre(const MapFrame& f)
{
	const int rows = f.obs->rangeImage.rows(), cols = f.obs->rangeImage.cols();
	return {avm::persons::pixelsOfBox(cols / 2 - 30, rows / 2 - 60, cols / 2 + 30, rows / 2 + 60, cols, rows)};
}

}  // namespace

/** A map whose person regions have seen the first 6 frames, the person
 *  sighted in each. */
CAdaptiveOctoMap mapWithPersonRegions(
	const CAdaptiveOctoMap::TInsertionOptions& ins, const avm::persons::TPersonLayerOptions& people = {})
{
	CAdaptiveOctoMap map(resolutions(0.2, 0.05), ins, {}, people);
	for (std::size_t i = 0; i < 6; i++)
	{
		const auto& f = firstBonnFrames().at(i);
		const auto observed = map.observePersons(*f.obs, f.pose, personAtCentre(f), f.index);
		EXPECT_TRUE(observed.at(0).sighting) << observed.at(0).skipReason;
		EXPECT_TRUE(map.insertObservation(*f.obs, f.pose));
	}
	return map;
}

// A region that ends is folded into the low tree (each low voxel takes the
// largest log-odds of its known high voxels, as octomap merges children), so
// no occupied surface seen at high resolution vanishes, and the high tree
// gives the space up.
TEST(CAdaptiveOctoMapBonn, AnEndingRegionIsCoarsenedNeverDropped)
{
	auto map = mapWithPersonRegions({});
	ASSERT_FALSE(map.highResolutionRegions().empty());
	std::vector<std::pair<mrpt::math::TPoint3D, double>> high;
	map.forEachLeaf(Resolution::High, [&](const avm::TLeafVoxel& v) { high.push_back({v.center, v.probability}); });
	std::size_t occupiedHigh = 0;
	for (const auto& [c, p] : high) occupiedHigh += p >= 0.5;
	ASSERT_GT(occupiedHigh, 50u);

	const auto regions = map.highResolutionRegions();
	for (const auto& r : regions) EXPECT_TRUE(map.endRegion(r.regionId));
	EXPECT_FALSE(map.endRegion(regions.front().regionId)) << "ended already";
	EXPECT_FALSE(map.hasSwitched());
	EXPECT_EQ(map.highResolutionStats().occupiedLeaves + map.highResolutionStats().freeLeaves, 0u);
	std::size_t lost = 0, notHigher = 0;
	for (const auto& [c, p] : high)
	{
		const auto q = map.query(c);
		EXPECT_EQ(q.tree, Resolution::Low);
		if (p >= 0.5 && q.state != avm::OccupancyState::Occupied) ++lost;
		// The low voxel holds the largest of its high voxels' values.
		if (q.probability + 1e-6 < p) ++notHigher;
	}
	EXPECT_EQ(lost, 0u) << "of " << occupiedHigh << " occupied high voxels";
	EXPECT_EQ(notHigher, 0u);
	EXPECT_FALSE(map.personTracks().empty()) << "the person's track outlives the region";

	// The low voxels remember where their surface was: a region over the
	// same space gets the occupied high voxels back, not solid low blocks.
	for (const auto& r : regions) map.addHighResolutionRegion(r.boxes.at(0));
	std::size_t back = 0, occupiedNow = 0;
	map.forEachLeaf(Resolution::High, [&](const avm::TLeafVoxel& v) { occupiedNow += v.occupied; });
	for (const auto& [c, p] : high)
		if (p >= 0.5 && map.query(c).state == avm::OccupancyState::Occupied) ++back;
	EXPECT_EQ(back, occupiedHigh);
	EXPECT_LE(occupiedNow, occupiedHigh + occupiedHigh / 10) << "only where the surface was";
}

// Follow lifetime: a region whose space the camera looks at for
// region_end_after_s with no sighting of its person ends; a region out of
// view (the camera turned away) stays.
TEST(CAdaptiveOctoMapBonn, AFollowRegionEndsOnlyWhileInViewAndUnseen)
{
	CAdaptiveOctoMap::TInsertionOptions ins;
	avm::persons::TPersonLayerOptions people;
	people.regionEndAfterSeconds = 0.3;  // firstBonnFrames() are 5 source frames (0.17 s) apart
	{
		auto map = mapWithPersonRegions(ins, people);
		ASSERT_FALSE(map.highResolutionRegions().empty());
		// Turned away: the same frames, the camera looking backwards.
		for (std::size_t i = 6; i < 12; i++)
		{
			const auto& f = firstBonnFrames().at(i);
			ASSERT_TRUE(map.insertObservation(*f.obs, f.pose + mrpt::poses::CPose3D(0, 0, 0, 0, M_PI, 0)));
		}
		EXPECT_FALSE(map.highResolutionRegions().empty()) << "a person out of view keeps the region";
	}
	auto map = mapWithPersonRegions(ins, people);
	const auto& f6 = firstBonnFrames().at(6);
	ASSERT_TRUE(map.insertObservation(*f6.obs, f6.pose));
	EXPECT_FALSE(map.highResolutionRegions().empty()) << "0.17 s unseen is not enough";
	const auto& f7 = firstBonnFrames().at(7);
	ASSERT_TRUE(map.insertObservation(*f7.obs, f7.pose));
	EXPECT_TRUE(map.highResolutionRegions().empty()) << "0.33 s in view and unseen";
	// Persist: the same run keeps every region.
	ins.regionLifetime = avm::RegionLifetime::Persist;
	auto kept = mapWithPersonRegions(ins, people);
	const auto before = kept.highResolutionRegions().size();
	for (std::size_t i = 6; i < 10; i++)
		ASSERT_TRUE(kept.insertObservation(*firstBonnFrames().at(i).obs, firstBonnFrames().at(i).pose));
	EXPECT_EQ(kept.highResolutionRegions().size(), before);
}

// Space that enters a region takes what the low tree knew there: a free low
// voxel gives free high voxels (but for surfaces its sketch kept), an occupied
// one occupied high voxels where its sketch saw the surface (and none
// elsewhere), an unknown one nothing; the low tree no longer holds that space.
TEST(CAdaptiveOctoMapBonn, SpaceEnteringARegionKeepsWhatTheLowTreeKnew)
{
	CAdaptiveOctoMap map(resolutions(0.2, 0.05), {}, {});
	insertAll(map, std::vector<MapFrame>(firstBonnFrames().begin(), firstBonnFrames().begin() + 3));
	const auto box = boxAheadOfFirstFrame(0.4);
	// The low voxels around the box and what the map said of each.
	std::vector<std::pair<mrpt::math::TPoint3D, avm::OccupancyState>> before;
	for (double x = box.min.x - 0.2; x < box.max.x + 0.2; x += 0.2)
		for (double y = box.min.y - 0.2; y < box.max.y + 0.2; y += 0.2)
			for (double z = box.min.z - 0.2; z < box.max.z + 0.2; z += 0.2)
			{
				const auto centre = [](double v) { return avm::keyCentre(avm::keyOf(v, 1 / 0.2), 0.2); };
				const mrpt::math::TPoint3D c(centre(x), centre(y), centre(z));
				before.push_back({c, map.query(c).state});
			}

	map.addHighResolutionRegion(box);
	std::size_t inRegion = 0, occupiedLow = 0, occupiedHigh = 0, wrong = 0;
	for (const auto& [c, state] : before)
	{
		if (map.query(c).tree != Resolution::High) continue;
		++inRegion;
		std::size_t occupied = 0, free = 0;
		for (double dx = -0.075; dx < 0.1; dx += 0.05)
			for (double dy = -0.075; dy < 0.1; dy += 0.05)
				for (double dz = -0.075; dz < 0.1; dz += 0.05)
				{
					const auto q = map.query(c + mrpt::math::TPoint3D(dx, dy, dz)).state;
					occupied += q == avm::OccupancyState::Occupied;
					free += q == avm::OccupancyState::Free;
				}
		if (state == avm::OccupancyState::Occupied)
		{
			++occupiedLow;
			occupiedHigh += occupied;
		}
		const bool kept = state == avm::OccupancyState::Free       ? occupied + free == 64 && free > occupied
						  : state == avm::OccupancyState::Occupied ? free == 0
																   : occupied + free == 0;
		if (!kept) ++wrong;
	}
	EXPECT_GT(inRegion, 30u);
	EXPECT_GT(occupiedLow, 0u);
	EXPECT_GE(occupiedHigh, occupiedLow) << "the surfaces of the occupied low voxels come back";
	EXPECT_EQ(wrong, 0u);
	// No space held twice: the low tree has nothing inside the region.
	const auto region = map.highResolutionRegions().at(0).boxes.at(0);
	const auto* low = map.tree(Resolution::Low);
	for (auto it = low->begin_leafs(); it != low->end_leafs(); ++it)
	{
		const auto c = it.getCoordinate();
		const double h = 0.5 * it.getSize();
		ASSERT_FALSE(overlaps({{c.x() - h, c.y() - h, c.z() - h}, {c.x() + h, c.y() + h, c.z() + h}}, region));
	}
	EXPECT_GT(map.highResolutionStats().occupiedLeaves, 0u);
}

TEST(CAdaptiveOctoMapBonn, SerializationCopyAndCloneAreExact)
{
	CAdaptiveOctoMap map(resolutions(0.2, 0.05), {}, {});
	map.addHighResolutionRegion(boxAheadOfFirstFrame(0.5));
	insertAll(map, std::vector<MapFrame>(firstBonnFrames().begin(), firstBonnFrames().begin() + 6));

	mrpt::io::CMemoryStream buf;
	auto arch = mrpt::serialization::archiveFrom(buf);
	arch << map;
	buf.Seek(0);
	auto obj = arch.ReadObject();
	auto restored = std::dynamic_pointer_cast<CAdaptiveOctoMap>(obj);
	ASSERT_TRUE(restored);
	expectSameTree(map.tree(Resolution::Low), restored->tree(Resolution::Low));
	expectSameTree(map.tree(Resolution::High), restored->tree(Resolution::High));
	EXPECT_EQ(restored->highResolutionRegions().size(), map.highResolutionRegions().size());
	EXPECT_EQ(restored->switchInsertionIndex(), map.switchInsertionIndex());
	EXPECT_EQ(restored->insertionCount(), map.insertionCount());
	EXPECT_EQ(restored->serializedBytes(), map.serializedBytes());

	CAdaptiveOctoMap copy(map);
	expectSameTree(map.tree(Resolution::High), copy.tree(Resolution::High));
	std::unique_ptr<mrpt::rtti::CObject> cloned(map.clone());
	auto* clone = dynamic_cast<CAdaptiveOctoMap*>(cloned.get());
	ASSERT_TRUE(clone);
	expectSameTree(map.tree(Resolution::Low), clone->tree(Resolution::Low));

	// Deep: inserting into the copy leaves the original alone.
	const auto before = map.tree(Resolution::Low)->size();
	ASSERT_TRUE(copy.insertObservation(*firstBonnFrames().back().obs, firstBonnFrames().back().pose));
	EXPECT_EQ(map.tree(Resolution::Low)->size(), before);
	EXPECT_NE(copy.tree(Resolution::Low)->size(), before);
}

TEST(CAdaptiveOctoMapBonn, FilesLikelihoodRayCastAndEmptiness)
{
	CAdaptiveOctoMap map(resolutions(0.2, 0.05), {}, {});
	EXPECT_TRUE(map.isEmpty());
	map.addHighResolutionRegion(boxAheadOfFirstFrame(0.5));
	insertAll(map, std::vector<MapFrame>(firstBonnFrames().begin(), firstBonnFrames().begin() + 10));
	EXPECT_FALSE(map.isEmpty());

	const auto dir = avm::test::scratchDir("map-files");
	const auto prefix = (dir / "bonn").string();
	map.saveMetricMapRepresentationToFile(prefix);
	for (const auto* suffix : {"_low.bt", "_high.bt", ".3Dscene"})
		ASSERT_TRUE(std::filesystem::exists(prefix + suffix)) << prefix + suffix;
	octomap::OcTree lowBack(0.1), highBack(0.1);
	ASSERT_TRUE(lowBack.readBinary(prefix + "_low.bt"));
	ASSERT_TRUE(highBack.readBinary(prefix + "_high.bt"));
	EXPECT_DOUBLE_EQ(lowBack.getResolution(), 0.2);
	EXPECT_DOUBLE_EQ(highBack.getResolution(), 0.05);
	EXPECT_GT(highBack.getNumLeafNodes(), 0u);
	mrpt::opengl::COpenGLScene scene;
	ASSERT_TRUE(scene.loadFromFile(prefix + ".3Dscene"));
	// The scene holds both trees' occupied voxels, in stock MRPT classes.
	auto voxels = scene.getByClass<mrpt::opengl::COctoMapVoxels>();
	ASSERT_TRUE(voxels);
	EXPECT_EQ(voxels->getVoxelCount(0), map.lowResolutionStats().occupiedLeaves);
	EXPECT_EQ(voxels->getVoxelCount(1), map.highResolutionStats().occupiedLeaves);
	EXPECT_GT(voxels->getVoxelCount(1), 0u);

	// The first frame is explained better at its true pose than 0.5 m off.
	const auto& f = firstBonnFrames().front();
	const double atTruth = map.computeObservationLikelihood(*f.obs, f.pose);
	const double shifted = map.computeObservationLikelihood(*f.obs, f.pose + mrpt::poses::CPose3D(0, 0, 0.5, 0, 0, 0));
	EXPECT_GT(atTruth, shifted);
	// The map's own occupied voxels match it fully where they are, far less
	// once moved by 0.7 m along each axis and turned by 30 degrees.
	const auto* pts = map.getAsSimplePointsMap();
	EXPECT_FLOAT_EQ(map.compute3DMatchingRatio(&map, mrpt::poses::CPose3D(), {}), 1.0f);
	EXPECT_LT(map.compute3DMatchingRatio(&map, mrpt::poses::CPose3D(0.7, 0.7, 0.7, mrpt::DEG2RAD(30), 0, 0), {}), 0.5f);
	EXPECT_GT(pts->size(), 0u);

	// A ray along the optical axis of the first frame stops near the depth
	// measured at the centre pixel.
	const auto& img = f.obs->rangeImage;
	const double d = img(img.rows() / 2, img.cols() / 2) * f.obs->rangeUnits;
	const auto sensor = f.pose + f.obs->sensorPose;
	const auto hit = map.castRay(sensor.translation(), sensor.rotateVector({1, 0, 0}), 6.0);
	ASSERT_TRUE(hit);
	EXPECT_NEAR((hit->point - sensor.translation()).norm(), d, 0.3);
	EXPECT_EQ(hit->tree, Resolution::High);  // the box around that surface
	const auto box = map.knownSpaceBoundingBox();
	ASSERT_TRUE(box);
	EXPECT_TRUE(box->containsPoint(hit->point));

	map.clear();
	EXPECT_TRUE(map.isEmpty());
	EXPECT_FALSE(map.hasSwitched());
}

// The same frames given as a CObservationPointCloud (sensor frame) and as a
// world-frame points map with its sensor origin map the same occupied voxels
// as the depth images the map unprojects itself.
TEST(CAdaptiveOctoMapBonn, PointCloudInputsMapLikeDepthImages)
{
	const std::vector<MapFrame> some(firstBonnFrames().begin(), firstBonnFrames().begin() + 5);
	CAdaptiveOctoMap fromDepth, fromCloud, fromWorld;
	for (auto* m : {&fromDepth, &fromCloud, &fromWorld}) m->addHighResolutionRegion(boxAheadOfFirstFrame(0.5));
	for (const auto& f : some)
	{
		ASSERT_TRUE(fromDepth.insertObservation(*f.obs, f.pose));
		auto sensorPts = mrpt::maps::CSimplePointsMap::Create();
		f.obs->unprojectInto(*sensorPts);  // sensor frame
		mrpt::obs::CObservationPointCloud cloud;
		cloud.pointcloud = sensorPts;
		cloud.sensorPose = f.obs->sensorPose;
		ASSERT_TRUE(fromCloud.insertObservation(cloud, f.pose));
		mrpt::maps::CSimplePointsMap world;
		mrpt::obs::T3DPointsProjectionParams pp;
		pp.takeIntoAccountSensorPoseOnRobot = true;
		pp.robotPoseInTheWorld = f.pose;
		f.obs->unprojectInto(world, pp);
		ASSERT_TRUE(fromWorld.insertPointCloud(world, (f.pose + f.obs->sensorPose).translation()));
	}
	auto all = [](double, double, double) { return true; };
	for (const auto which : {Resolution::Low, Resolution::High})
	{
		const auto ref = avm::occupiedFinestKeys(*fromDepth.tree(which), all);
		const double iouCloud = avm::intersectionOverUnion(avm::occupiedFinestKeys(*fromCloud.tree(which), all), ref);
		const double iouWorld = avm::intersectionOverUnion(avm::occupiedFinestKeys(*fromWorld.tree(which), all), ref);
		std::cout << (which == Resolution::Low ? "low" : "high") << " tree: IoU cloud " << iouCloud << ", world points "
				  << iouWorld << " (" << ref.size() << " occupied voxels from depth)\n";
		EXPECT_GT(ref.size(), 100u);
		EXPECT_GE(iouCloud, 0.95);
		EXPECT_GE(iouWorld, 0.95);
	}
}

// Two threads for the depth-image pass build exactly the map one thread does.
TEST(CAdaptiveOctoMapBonn, TwoInsertionThreadsGiveTheSameMap)
{
	CAdaptiveOctoMap::TInsertionOptions two;
	two.insertionThreads = 2;
	CAdaptiveOctoMap single(resolutions(0.2, 0.05), {}, {}), dual(resolutions(0.2, 0.05), two, {});
	for (auto* m : {&single, &dual}) m->addHighResolutionRegion(boxAheadOfFirstFrame(0.6));
	for (std::size_t i = 0; i < 8; i++)
	{
		ASSERT_TRUE(single.insertObservation(*firstBonnFrames()[i].obs, firstBonnFrames()[i].pose));
		ASSERT_TRUE(dual.insertObservation(*firstBonnFrames()[i].obs, firstBonnFrames()[i].pose));
	}
	expectSameTree(single.tree(Resolution::Low), dual.tree(Resolution::Low));
	expectSameTree(single.tree(Resolution::High), dual.tree(Resolution::High));
	EXPECT_GT(dual.highResolutionStats().occupiedLeaves, 0u);
}
