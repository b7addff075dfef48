// The default detector and the persons' world sightings (the estimator the
// map uses on detector boxes) on the real Bonn sequence.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "DetectionTestSupport.h"
#include "avm/detection/Detector.h"
#include "avm/detection/PersonLabels.h"
#include "avm/io/RawlogFrameReader.h"
#include "avm/persons/PersonSighting.h"

using namespace avm;
using namespace avm::detection;

namespace
{
io::RgbdFrame bonnFrame(std::size_t index)
{
	io::RawlogFrameReader reader(test::bonnRawlog());
	while (auto f = reader.next())
		if (f->index == index) return *f;
	throw std::runtime_error("no frame " + std::to_string(index));
}

std::vector<Detection> personsIn(const io::RgbdFrame& f)
{
	return personsOnly(createDetector(test::yoloxOptions())->detect(io::colourImage(*f.observation)));
}

persons::SightingEstimate sightingOf(
	const Detection& p, const io::RgbdFrame& f, const mrpt::obs::CObservation3DRangeScan& obs)
{
	const cv::Size size(static_cast<int>(obs.rangeImage.cols()), static_cast<int>(obs.rangeImage.rows()));
	return persons::estimateSighting(obs, *f.groundTruth + obs.sensorPose, personPixels(p, size), {});
}

/** The 8 corners of a world box in the camera optical frame. */
std::vector<mrpt::math::TPoint3D> cornersInCamera(const mrpt::math::TBoundingBox& b, const mrpt::poses::CPose3D& cam)
{
	std::vector<mrpt::math::TPoint3D> out;
	for (int i = 0; i < 8; ++i)
	{
		const mrpt::math::TPoint3D w(i & 1 ? b.max.x : b.min.x, i & 2 ? b.max.y : b.min.y, i & 4 ? b.max.z : b.min.z);
		mrpt::math::TPoint3D c;
		cam.inverseComposePoint(w, c);
		out.push_back(c);
	}
	return out;
}
}  // namespace

TEST(BonnPersons, NoPersonInTheFirstFrame) { EXPECT_TRUE(personsIn(bonnFrame(0)).empty()); }

// Frame 150 shows two people from head to (cut-off) feet: one in a grey
// sweater in the middle, one in blue on the right, and the blurred arm and
// side of a third passing the right edge. Their boxes, drawn by eye on the
// colour image [px]: each is found, where it stands.
TEST(BonnPersons, TheTwoPeopleInFrame150AreFoundWhereTheyStand)
{
	const std::vector<std::pair<const char*, cv::Rect2d>> people = {
		{"grey sweater", cv::Rect2d(cv::Point2d(267, 32), cv::Point2d(397, 480))},
		{"blue", cv::Rect2d(cv::Point2d(460, 2), cv::Point2d(627, 480))}};
	const auto found = personsIn(bonnFrame(150));
	const auto iou = [](const cv::Rect2d& a, const cv::Rect2d& b) { return (a & b).area() / (a | b).area(); };
	for (const auto& [who, box] : people)
	{
		double best = 0;
		for (const auto& d : found) best = std::max(best, iou(box, d.box));
		EXPECT_GE(best, 0.6) << "the person in " << who << " at " << box << ": best box overlap " << best;
	}
	// Nothing else, bar the third person at the right edge.
	for (const auto& d : found)
	{
		const bool someone =
			std::any_of(people.begin(), people.end(), [&](const auto& p) { return iou(p.second, d.box) >= 0.3; });
		EXPECT_TRUE(someone || d.box.x > 560) << "a box on no one: " << d.box << " (score " << d.score << ")";
	}
	EXPECT_LE(found.size(), 3u);
}

// "In front" is along the optical axis (camera z), "tall" along the camera's
// -y axis: the Bonn motion-capture world need not have z up.
TEST(BonnPersons, SightingOfAPersonInFrame150IsInFrontAndPersonSized)
{
	const auto frame = bonnFrame(150);
	ASSERT_TRUE(frame.groundTruth);
	const auto persons = personsIn(frame);
	ASSERT_FALSE(persons.empty());
	std::size_t sightings = 0;
	for (const auto& p : persons)
	{
		const auto est = sightingOf(p, frame, *frame.observation);
		if (!est.sighting)
		{
			std::cout << "person at " << p.box << " skipped: " << est.skipReason << "\n";
			continue;
		}
		++sightings;
		const auto& s = *est.sighting;
		EXPECT_GE(s.depth, 0.5f);
		EXPECT_LE(s.depth, 5.f);
		EXPECT_TRUE(s.box.containsPoint(s.position));
		double minY = 1e9, maxY = -1e9, minZ = 1e9, maxZ = -1e9;
		for (const auto& c : cornersInCamera(s.box, *frame.groundTruth))
		{
			minY = std::min(minY, c.y), maxY = std::max(maxY, c.y);
			minZ = std::min(minZ, c.z), maxZ = std::max(maxZ, c.z);
		}
		std::cout << "person " << p.box << ": depth " << s.depth << " m, camera z " << minZ << ".." << maxZ
				  << ", height " << maxY - minY << " m, " << s.points << " points\n";
		EXPECT_GT(minZ, 0.0) << "part of the person is behind the camera";
		EXPECT_GE(0.5 * (minZ + maxZ), 0.5);
		EXPECT_LE(0.5 * (minZ + maxZ), 5.0);
		EXPECT_LE(maxY - minY, 2.2);
		EXPECT_GT(maxY - minY, 0.5);  // a person, not a speck
		// The box is the person's depth band, not the background behind it.
		EXPECT_LE(maxZ - minZ, 2 * persons::SightingOptions().depthBand + 1e-6);
	}
	EXPECT_GE(sightings, 1u);
}

TEST(BonnPersons, BoxWithoutDepthGivesNoSightingAndSaysWhy)
{
	const auto frame = bonnFrame(150);
	const auto persons = personsIn(frame);
	ASSERT_FALSE(persons.empty());
	auto obs = *frame.observation;
	const cv::Size size(static_cast<int>(obs.rangeImage.cols()), static_cast<int>(obs.rangeImage.rows()));
	for (const auto i : personPixels(persons[0], size)) obs.rangeImage(i / size.width, i % size.width) = 0;
	const auto est = sightingOf(persons[0], frame, obs);
	EXPECT_FALSE(est.sighting);
	EXPECT_NE(est.skipReason.find("depth"), std::string::npos) << est.skipReason;
}
