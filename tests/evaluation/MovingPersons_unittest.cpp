// People are objects, not walls, on real data: Bonn crowd frames
// with ground-truth poses and YOLOX person boxes. A person walking through
// leaves (almost) no occupied voxels where a reference that never saw the
// people says the space is free; a person who stays still is mapped; the
// paper policy (Algorithm 1) still maps every point; the reference maps of
// avm-map treat the moving persons' pixels as the map did.
#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <array>
#include <map>

#include "BonnFrames.h"
#include "avm/detection/Detector.h"
#include "avm/detection/PersonLabels.h"
#include "avm/io/DepthCamera.h"
#include "avm/io/RgbdFrame.h"
#include "avm/persons/PersonBand.h"
#include "avm/persons/PersonLayer.h"
#include "avm/plugin/CAdaptiveOctoMap.h"
#include "avm/evaluation/ReferenceOctoMaps.h"
#include "avm/evaluation/TrailPixels.h"
#include "avm/evaluation/TrailShare.h"

using avm::CAdaptiveOctoMap;
using avm::test::MapFrame;

namespace
{
/** Every 2nd frame of 60..240, where people walk through the view: each
 *  frame with its detector boxes as person labels. */
struct LabelledFrame
{
	MapFrame frame;
	mrpt::obs::CObservation3DRangeScan::Ptr labelled;
};
const std::vector<LabelledFrame>& labelledFrames()
{
	static const auto frames = []
	{
		avm::detection::TDetectorOptions o;
		o.model = avm::test::sharedFile("models/yolox_nano.onnx").string();
		const auto detector = avm::detection::createDetector(o);
		std::vector<LabelledFrame> out;
		for (const auto& f : avm::test::bonnFrames(240, 2))
		{
			if (f.index < 60) continue;
			auto labelled = mrpt::obs::CObservation3DRangeScan::Create(*f.obs);
			avm::detection::writePersonLabels(
				*labelled, avm::detection::personsOnly(detector->detect(avm::io::colourImage(*f.obs))));
			out.push_back({f, labelled});
		}
		return out;
	}();
	return frames;
}

/** The trail (low + high) of a map built from the frames, labels on every
 *  3rd frame as avm-map detects, against references without the persons. */
avm::evaluation::TrailRow trailOf(const CAdaptiveOctoMap& map, const avm::evaluation::TrailReference& high,
	const avm::evaluation::TrailReference& low, const std::string& name)
{
	auto row = high.judge(*map.tree(avm::Resolution::High), name);
	row += low.judge(*map.tree(avm::Resolution::Low), name);
	return row;
}

/** The cuts of a labelled frame, the persons' depth band as a map of default
 *  options takes it. */
avm::evaluation::PersonCuts cutsOf(const LabelledFrame& lf)
{
	return avm::evaluation::personCuts(
		*lf.labelled, lf.frame.pose + lf.labelled->sensorPose, avm::evaluation::TrailOptions{});
}

/** The person labels of `obs` that hold pixels (avm-detect also names an
 *  empty plain "person" label). */
std::size_t labelledPersons(const mrpt::obs::CObservation3DRangeScan& obs)
{
	const auto labels = avm::persons::readPersonLabels(obs);
	return static_cast<std::size_t>(
		std::count_if(labels.begin(), labels.end(), [](const auto& l) { return !l.pixels.empty(); }));
}

std::size_t depthPixels(const mrpt::obs::CObservation3DRangeScan& obs, const std::vector<std::uint8_t>& cut)
{
	std::size_t n = 0;
	const auto cols = static_cast<std::size_t>(obs.rangeImage.cols());
	for (std::size_t i = 0; i < cut.size(); ++i) n += cut[i] && obs.rangeImage(i / cols, i % cols) != 0;
	return n;
}

CAdaptiveOctoMap regionMap(double stillAfter)
{
	avm::persons::TPersonLayerOptions people;
	people.tracking.stillAfter = stillAfter;
	return CAdaptiveOctoMap({}, {}, {}, people);
}

std::size_t occupiedIn(const CAdaptiveOctoMap& map, const mrpt::math::TBoundingBox& box)
{
	std::size_t n = 0;
	for (const auto which : {avm::Resolution::Low, avm::Resolution::High})
		map.forEachLeaf(which,
			[&](const avm::TLeafVoxel& v)
			{
				if (v.occupied && box.containsPoint(v.center)) ++n;
			});
	return n;
}
}  // namespace

TEST(MovingPersons, AMovingPersonLeavesNoTrail)
{
	avm::evaluation::TrailReference high(0.05, 5.0), low(0.20, 5.0);
	// Every person is still at once: the map as it was before moving persons
	// were told apart (all their pixels are walls).
	auto objects = regionMap(2.0), walls = regionMap(0.0);
	std::size_t i = 0;
	for (const auto& lf : labelledFrames())
	{
		const auto cuts = cutsOf(lf);
		high.insert(*lf.frame.obs, lf.frame.pose, cuts);
		low.insert(*lf.frame.obs, lf.frame.pose, cuts);
		const auto& input = i++ % 3 == 0 ? *lf.labelled : *lf.frame.obs;
		ASSERT_TRUE(objects.insertObservation(input, lf.frame.pose));
		ASSERT_TRUE(walls.insertObservation(input, lf.frame.pose));
	}
	ASSERT_GE(objects.personTracks().size(), 1u);
	const auto o = trailOf(objects, high, low, "objects"), w = trailOf(walls, high, low, "walls");
	const auto single = high.judge(high.single(), "single 0.05 m");
	for (const auto y : {avm::evaluation::Yardstick::PersonMask, avm::evaluation::Yardstick::Boxes})
	{
		std::cout << "trail share without " << avm::evaluation::describe(y) << ": persons as objects " << o.share(y)
				  << " (" << o.trail(y) << " m3), as walls " << w.share(y) << " (" << w.trail(y)
				  << " m3), single 0.05 m OctoMap " << single.share(y) << "\n";
		EXPECT_LT(o.trail(y), 0.5 * w.trail(y));
		EXPECT_LT(o.share(y), single.share(y));
	}
	// What the boxes' reference never saw behind the persons and the map
	// rightly mapped is no trail against the person mask.
	EXPECT_LT(o.trail(avm::evaluation::Yardstick::PersonMask), o.trail(avm::evaluation::Yardstick::Boxes));
	// The rest of the scene is still mapped: most of the walls' occupied volume.
	EXPECT_GT(o.occupiedM3, 0.8 * w.occupiedM3);
}

TEST(MovingPersons, ThePersonMaskCutsThePersonsOwnPixelsAndNoMore)
{
	// Every pixel the sighting counts as the person's is cut, and the part of
	// the boxes left in the reference is the scene behind the persons.
	const avm::persons::SightingOptions sighting;
	std::size_t maskPixels = 0, boxPixels = 0, behind = 0, keptInBoxes = 0, onePersonFrames = 0;
	for (const auto& lf : labelledFrames())
	{
		const auto& obs = *lf.labelled;
		const auto cuts = cutsOf(lf);
		ASSERT_EQ(cuts.personMask.size(), cuts.boxes.size());
		for (std::size_t i = 0; i < cuts.boxes.size(); ++i) ASSERT_LE(cuts.personMask[i], cuts.boxes[i]) << i;
		maskPixels += depthPixels(obs, cuts.personMask);
		boxPixels += depthPixels(obs, cuts.boxes);
		const auto persons = avm::persons::personPixelsFromLabels(obs, "person", sighting.minPixels);
		const auto cols = static_cast<std::size_t>(obs.rangeImage.cols());
		for (const auto& pixels : persons)
		{
			const auto s =
				avm::persons::estimateSighting(obs, lf.frame.pose + obs.sensorPose, pixels, sighting).sighting;
			if (!s) continue;
			std::size_t cutWithDepth = 0;
			for (const auto i : pixels)
			{
				const auto raw = obs.rangeImage(i / cols, i % cols);
				if (raw == 0) continue;
				cutWithDepth += cuts.personMask[i];
				if (cuts.personMask[i]) continue;
				++keptInBoxes;
				behind += raw * obs.rangeUnits > s->depth;
			}
			// Another person's band may hold more of these pixels: only alone
			// are they exactly the person's.
			EXPECT_GE(cutWithDepth, s->points);
			if (persons.size() == 1 && labelledPersons(obs) == 1)
			{
				EXPECT_EQ(cutWithDepth, s->points) << "frame " << lf.frame.index;
				++onePersonFrames;
			}
		}
	}
	std::cout << "depth pixels cut: person mask " << maskPixels << ", boxes " << boxPixels << "; of the boxes' pixels "
			  << "kept, " << behind << " of " << keptInBoxes << " behind the person; " << onePersonFrames
			  << " one-person frames\n";
	EXPECT_GT(onePersonFrames, 0u);
	EXPECT_GT(maskPixels, 0u);
	EXPECT_LT(maskPixels, boxPixels);
	EXPECT_GT(behind, keptInBoxes / 2);
}

TEST(MovingPersons, AMovingPersonsFreeOnlyBoxHoldsEveryPixelOfTheirBand)
{
	// On a frame with their sighting, every pixel the person layer counts as
	// a moving person's (their depth band) lies in a free-only box: a pixel
	// outside would be mapped as a wall. The region box, the sighting's
	// percentile box grown by the margin, misses some of them: the ends of
	// the band and the limbs.
	const avm::persons::SightingOptions sighting;  // the built-in defaults, ini/default.ini's
	const double margin = avm::persons::TPersonLayerOptions().regionMargin;
	std::size_t bandPixels = 0, outsideFreeOnly = 0, outsideRegion = 0;
	for (const auto& lf : labelledFrames())
	{
		const auto& obs = *lf.labelled;
		const auto pose = lf.frame.pose + obs.sensorPose;
		const auto persons = avm::persons::personPixelsFromLabels(obs, "person", sighting.minPixels);
		avm::persons::PersonLayer layer;
		const auto seen = layer.observe(obs, pose, persons, lf.frame.index, sighting, margin, 0.05);
		// No margin: the box itself must hold them.
		const auto freeOnly = layer.movingPersonBoxes(obs, 1.5, 0.0);
		const auto camera = avm::io::DepthCamera::of(obs);
		const auto cols = static_cast<std::uint32_t>(camera.width);
		for (std::size_t p = 0; p < persons.size(); ++p)
		{
			if (!seen[p].sighting) continue;
			for (const auto i : avm::persons::personBandPixels(obs, persons[p], *seen[p].sighting, sighting))
			{
				const auto metres = static_cast<float>(obs.rangeImage(i / cols, i % cols) * obs.rangeUnits);
				const auto point = pose.composePoint(camera.unproject(i % cols, i / cols, metres));
				++bandPixels;
				outsideRegion += !seen[p].regionBox->containsPoint(point);
				outsideFreeOnly += std::none_of(freeOnly.begin(), freeOnly.end(),
					[&](const mrpt::math::TBoundingBox& b) { return b.containsPoint(point); });
			}
		}
	}
	std::cout << "band pixels of the persons seen: " << bandPixels << ", outside their region box " << outsideRegion
			  << ", outside every free-only box " << outsideFreeOnly << "\n";
	ASSERT_GT(bandPixels, 0u);
	EXPECT_EQ(outsideFreeOnly, 0u);
	EXPECT_GT(outsideRegion, 0u);
}

TEST(MovingPersons, APersonWhoStaysStillIsMappedAndPaperMapsEveryPoint)
{
	// The first frame with a person, seen again and again 0.1 s apart: a
	// person who does not move.
	const LabelledFrame* seen = nullptr;
	for (const auto& lf : labelledFrames())
		if (!avm::evaluation::personPixelMask(*lf.labelled, "person").empty() &&
			avm::persons::personPixelsFromLabels(*lf.labelled, "person", 200).size() == 1)
		{
			seen = &lf;
			break;
		}
	ASSERT_NE(seen, nullptr);
	auto map = regionMap(2.0);
	const auto t0 = seen->labelled->timestamp;
	std::map<int, std::size_t> occupiedAfter;
	mrpt::math::TBoundingBox person;
	for (int k = 0; k <= 30; k++)
	{
		auto again = mrpt::obs::CObservation3DRangeScan::Create(*seen->labelled);
		again->timestamp = t0 + std::chrono::milliseconds(100 * k);
		ASSERT_TRUE(map.insertObservation(*again, seen->frame.pose));
		ASSERT_EQ(map.personTracks().size(), 1u);
		person = map.personTracks()[0].box;
		occupiedAfter[k] = occupiedIn(map, person);
		if (k < 19 || k > 21)
		{
			EXPECT_EQ(map.personTracks()[0].still, k > 20) << "after " << k * 0.1 << " s";
		}
	}
	std::cout << "occupied voxels in the person's box: after 1 s " << occupiedAfter[10] << ", after 3 s "
			  << occupiedAfter[30] << "\n";
	EXPECT_GT(occupiedAfter[30], 10 * std::max<std::size_t>(1, occupiedAfter[10]));

	// Paper policy: Algorithm 1 as written, every point of the person mapped.
	avm::CDualOctoMap::TInsertionOptions paper;
	paper.switchPolicy = avm::SwitchPolicy::Paper;
	CAdaptiveOctoMap paperMap({}, paper, {});
	ASSERT_TRUE(paperMap.insertObservation(*seen->labelled, seen->frame.pose));
	EXPECT_GT(occupiedIn(paperMap, person), occupiedAfter[30] / 4);
}

TEST(MovingPersons, TheFreeOnlyReferenceTreatsTheMovingPersonsAsTheMapDid)
{
	// The map's free-only boxes, frame by frame, into the reference as
	// avm-map does: inside the regions at the end, the single 0.05 m OctoMap
	// whose moving-person pixels are free-only holds fewer occupied voxels
	// than the one of all pixels, and the map agrees with it better.
	auto map = regionMap(2.0);
	const auto& c = map.creationOptions();
	avm::evaluation::ReferenceOctoMaps reference(c.high.resolution, c.low.resolution, c.high.maxRange, c.low.maxRange);
	std::size_t i = 0, framesWithFreeOnly = 0;
	for (const auto& lf : labelledFrames())
	{
		ASSERT_TRUE(map.insertObservation(i++ % 3 == 0 ? *lf.labelled : *lf.frame.obs, lf.frame.pose));
		framesWithFreeOnly += !map.lastFreeOnlyBoxes().empty();
		reference.insert(*lf.frame.obs, lf.frame.pose, map.lastFreeOnlyBoxes());
	}
	ASSERT_GT(framesWithFreeOnly, 0u);
	ASSERT_FALSE(map.highResolutionRegions().empty());
	const auto r = reference.compare(map);
	std::cout << "inside the regions: adaptive " << r.insideAdaptive << ", all pixels " << r.insideReference << " (IoU "
			  << r.insideIoU << "), moving persons free-only " << r.insideFreeOnlyReference << " (IoU "
			  << r.insideFreeOnlyIoU << "); frames with free-only boxes " << framesWithFreeOnly << "\n";
	EXPECT_LT(r.insideFreeOnlyReference, r.insideReference);
	EXPECT_GT(r.insideFreeOnlyIoU, r.insideIoU);
}

TEST(MovingPersons, TheSurfaceInABoxBesideAMovingPersonIsBackgroundNotTheirSilhouette)
{
	// The box yardstick counts as trail what the map inserts of a detector's
	// box: the pixels outside every free-only box. Were these mostly mixed
	// pixels on the silhouette (a depth edge next to the person's band, their
	// depth between the person and the background), they would move with the
	// person, a real trail. They are mostly the background behind the band.
	const avm::evaluation::TrailOptions options;  // the person keys at their built-in defaults, ini/default.ini's
	// region_margin; the odometry's depth_edge_ratio
	const double margin = avm::persons::TPersonLayerOptions().regionMargin, edgeRatio = 0.05;
	constexpr auto kClasses = static_cast<std::size_t>(avm::evaluation::TrailPixelClass::Count);
	std::array<std::size_t, kClasses> inBoxes{}, surface{};
	for (const auto& lf : labelledFrames())
	{
		const auto& obs = *lf.labelled;
		const auto pose = lf.frame.pose + obs.sensorPose;
		const auto cuts = avm::evaluation::personCuts(obs, pose, options);
		std::vector<float> personDepth;
		const auto cls = avm::evaluation::trailPixelClasses(obs, pose, options, cuts.boxes, edgeRatio, personDepth);
		avm::persons::PersonLayer layer;
		layer.observe(obs, pose, avm::persons::personPixelsFromLabels(obs, "person", options.sighting.minPixels),
			lf.frame.index, options.sighting, margin, 0.05);
		const auto freeOnly = layer.movingPersonBoxes(obs, 1.5, margin);
		const auto camera = avm::io::DepthCamera::of(obs);
		for (int v = 0; v < camera.height; v++)
			for (int u = 0; u < camera.width; u++)
			{
				const auto c = cls[static_cast<std::size_t>(v) * camera.width + u];
				const auto raw = obs.rangeImage(v, u);
				if (raw == 0 || c == static_cast<std::uint8_t>(avm::evaluation::TrailPixelClass::Other)) continue;
				++inBoxes[c];
				const auto point = pose.composePoint(camera.unproject(u, v, raw * obs.rangeUnits));
				surface[c] += std::none_of(freeOnly.begin(), freeOnly.end(),
					[&](const mrpt::math::TBoundingBox& b) { return b.containsPoint(point); });
			}
	}
	std::cout << "box pixels with depth, of them mapped as surface (outside every free-only box):\n";
	for (std::size_t c = 0; c < kClasses; ++c)
		std::cout << "  " << avm::evaluation::describe(static_cast<avm::evaluation::TrailPixelClass>(c)) << ": "
				  << inBoxes[c] << ", " << surface[c] << "\n";
	const auto of = [](const auto& counts, avm::evaluation::TrailPixelClass c)
	{ return counts[static_cast<std::size_t>(c)]; };
	using C = avm::evaluation::TrailPixelClass;
	EXPECT_GT(of(inBoxes, C::Mixed), 0u);
	EXPECT_EQ(of(surface, C::Band), 0u);  // the free-only box holds the band (test above)
	EXPECT_LT(10 * of(surface, C::Mixed), of(surface, C::Behind));
}

TEST(MovingPersons, ALowVoxelTheFineReferenceHoldsSurfaceInIsNoTrailOfThatReading)
{
	// A 0.20 m reference frees a voxel that rays pass through beside a
	// surface; the 0.05 m reference of the same frames still holds that
	// surface, and octomap's own coarse view of it (an inner node is occupied
	// if a child is) calls the 0.20 m voxel occupied. The reading that asks
	// the finer reference too counts less trail, never more.
	avm::evaluation::TrailReference high(0.05, 5.0), low(0.20, 5.0);
	for (const auto& lf : labelledFrames())
	{
		const auto cuts = cutsOf(lf);
		high.insert(*lf.frame.obs, lf.frame.pose, cuts);
		low.insert(*lf.frame.obs, lf.frame.pose, cuts);
	}
	using avm::evaluation::Yardstick;
	const auto single = low.judge(low.single(), "single 0.20 m", &high);
	const auto masked = low.judge(low.reference(Yardstick::PersonMask), "without the persons' own pixels", &high);
	const auto unread = low.judge(low.single(), "single 0.20 m");
	for (const auto y : {Yardstick::PersonMask, Yardstick::Boxes})
	{
		std::cout << "0.20 m trail without " << avm::evaluation::describe(y) << ": single " << single.trail(y) << " -> "
				  << single.trailNoFineSurface(y) << " m3, without the persons' own pixels " << masked.trail(y)
				  << " -> " << masked.trailNoFineSurface(y) << " m3\n";
		EXPECT_LE(single.trailNoFineSurface(y), single.trail(y));
		EXPECT_LE(masked.trailNoFineSurface(y), masked.trail(y));
		// Without a finer reference the reading is the plain one.
		EXPECT_EQ(unread.trailNoFineSurface(y), unread.trail(y));
	}
	EXPECT_EQ(masked.trail(Yardstick::PersonMask), 0.0);
	// The boxes' references never see the background behind the persons:
	// the 0.20 m one frees voxels whose surface the 0.05 m one keeps.
	EXPECT_LT(single.trailNoFineSurface(Yardstick::Boxes), single.trail(Yardstick::Boxes));
	EXPECT_LT(masked.trailNoFineSurface(Yardstick::Boxes), masked.trail(Yardstick::Boxes));
}
