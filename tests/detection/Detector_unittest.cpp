// The detectors on the real test images, and a model that will not load.
#include <gtest/gtest.h>

#include <opencv2/dnn.hpp>
#include <opencv2/imgcodecs.hpp>

#include <fstream>
#include <future>

#include "DetectionTestSupport.h"
#include "avm/detection/Detector.h"
#include "avm/detection/OutputDecoders.h"

using namespace avm;
using namespace avm::detection;
namespace fs = std::filesystem;

namespace
{

cv::Mat image(const std::string& name)
{
	const cv::Mat img = cv::imread(test::sharedFile("images/" + name).string(), cv::IMREAD_COLOR);
	if (img.empty()) throw std::runtime_error("cannot read " + name);
	return img;
}

std::size_t countClass(const std::vector<Detection>& dets, const std::string& name)
{
	return static_cast<std::size_t>(
		std::count_if(dets.begin(), dets.end(), [&](const Detection& d) { return d.className == name; }));
}

void expectLoadErrorNaming(const fs::path& model, const std::string& alsoMentions)
{
	TDetectorOptions o;
	o.model = model.string();
	try
	{
		createDetector(o);
		ADD_FAILURE() << model << " loaded";
	}
	catch (const std::runtime_error& e)
	{
		const std::string what = e.what();
		EXPECT_NE(what.find(model.string()), std::string::npos) << what;
		EXPECT_NE(what.find(alsoMentions), std::string::npos) << what;
	}
}
}  // namespace

TEST(YoloxDetector, BusJpgHasAtLeastThreeUprightPersonsInsideTheImage)
{
	const cv::Mat bus = image("bus.jpg");
	const auto det = createDetector(test::yoloxOptions());
	const auto persons = det->detect(bus);
	EXPECT_GE(persons.size(), 3u);
	for (const auto& p : persons)
	{
		EXPECT_EQ(p.className, "person");
		EXPECT_GE(p.box.x, 0);
		EXPECT_GE(p.box.y, 0);
		EXPECT_LE(p.box.x + p.box.width, bus.cols);
		EXPECT_LE(p.box.y + p.box.height, bus.rows);
		EXPECT_GT(p.box.height, p.box.width) << "box " << p.box;
		EXPECT_GE(p.score, 0.3f);
		EXPECT_LE(p.score, 1.f);
	}
	EXPECT_NE(det->description().find("yolox"), std::string::npos) << det->description();
	EXPECT_NE(det->description().find("yolox_nano.onnx"), std::string::npos) << det->description();
}

TEST(YoloxDetector, PersonJpgHasExactlyOnePerson)
{
	const auto dets = createDetector(test::yoloxOptions())->detect(image("person.jpg"));
	ASSERT_EQ(dets.size(), 1u);
	EXPECT_EQ(dets[0].className, "person");
	// The person stands left of the centre, between the dog and the horse.
	const cv::Point2f c = (dets[0].box.tl() + dets[0].box.br()) * 0.5f;
	EXPECT_GT(c.x, 150);
	EXPECT_LT(c.x, 300);
}

TEST(YoloxDetector, WidenedClassFilterAlsoFindsTheDogAndTheHorse)
{
	auto o = test::yoloxOptions();
	o.classes = "person, dog, horse";
	const auto dets = createDetector(o)->detect(image("person.jpg"));
	EXPECT_EQ(countClass(dets, "person"), 1u);
	EXPECT_EQ(countClass(dets, "dog"), 1u);
	EXPECT_EQ(countClass(dets, "horse"), 1u);
	EXPECT_EQ(dets.size(), 3u);
}

// The decoder multiplies objectness and class score as given: this pins that
// the official YOLOX export applies the sigmoid inside the graph (scores are
// probabilities) while the box sizes stay raw logarithms.
TEST(YoloxDetector, ExportedScoresAreProbabilitiesAndSizesAreLogarithms)
{
	auto net = cv::dnn::readNetFromONNX(test::sharedFile("models/yolox_nano.onnx").string());
	Letterbox lb;
	net.setInput(makeInputBlob(image("bus.jpg"), OutputLayout::Yolox, {416, 416}, lb));
	const cv::Mat out = net.forward();
	ASSERT_EQ(out.dims, 3);
	ASSERT_EQ(out.size[1], 3549);
	ASSERT_EQ(out.size[2], 85);
	const cv::Mat m = out.reshape(1, 3549);
	double minScore, maxScore, minLogSize, maxLogSize;
	cv::minMaxLoc(m.colRange(4, 85), &minScore, &maxScore);
	cv::minMaxLoc(m.colRange(2, 4), &minLogSize, &maxLogSize);
	EXPECT_GE(minScore, 0.0);
	EXPECT_LE(maxScore, 1.0);
	EXPECT_GT(maxScore, 0.5);    // some cell is sure about a person
	EXPECT_LT(minLogSize, 0.0);  // exp() still to be applied
}

TEST(HogDetector, FallbackWithoutModelFindsAPersonInPersonJpg)
{
	TDetectorOptions o;
	o.model = "";
	const auto det = createDetector(o);
	EXPECT_NE(det->description().find("HOG"), std::string::npos) << det->description();
	const auto dets = det->detect(image("person.jpg"));
	ASSERT_FALSE(dets.empty());
	// The best window overlaps the person's YOLOX box (x 189..277, y 97..374).
	const cv::Rect2f person(189, 97, 88, 277);
	const cv::Rect2f overlap = dets[0].box & person;
	EXPECT_GT(overlap.area(), 0.5 * person.area()) << dets[0].box;
	for (const auto& d : dets) EXPECT_EQ(d.className, "person");
}

TEST(HogDetector, RefusesClassesWithoutPerson)
{
	TDetectorOptions o;
	o.model = "";
	o.classes = "dog";
	EXPECT_THROW(createDetector(o), std::invalid_argument);
}

TEST(DetectorErrors, MissingModelNamesTheFileAndGetData)
{
	expectLoadErrorNaming(test::scratchDir("det-missing") / "nope.onnx", "scripts/get-data.sh");
}

TEST(DetectorErrors, TruncatedModelNamesTheFile)
{
	const auto dir = test::scratchDir("det-truncated");
	const auto cut = dir / "half.onnx";
	{
		const std::string bytes = mrpt::io::file_get_contents(test::sharedFile("models/yolox_nano.onnx").string());
		std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
	}
	expectLoadErrorNaming(cut, "ONNX");
}

TEST(DetectorErrors, TextFileIsNotAnOnnxModel)
{
	const auto file = test::scratchDir("det-text") / "readme.onnx";
	std::ofstream(file) << "This is not a neural network.\n";
	expectLoadErrorNaming(file, "ONNX");
}

TEST(DetectorErrors, LayoutThatDoesNotFitTheOutputNamesFileAndShape)
{
	auto o = test::yoloxOptions();
	o.layout = OutputLayout::Yolov8;
	try
	{
		createDetector(o);
		FAIL() << "a YOLOX model accepted as yolov8";
	}
	catch (const std::runtime_error& e)
	{
		const std::string what = e.what();
		EXPECT_NE(what.find("yolox_nano.onnx"), std::string::npos) << what;
		// YOLOX's grid at the default 256x192 input: 32x24 + 16x12 + 8x6 cells.
		EXPECT_NE(what.find("1x1008x85"), std::string::npos) << what;
	}
}

// Instances share nothing: two on two threads give what one gives alone.
TEST(YoloxDetector, InstancesOnTwoThreadsMatchSerialResults)
{
	const cv::Mat bus = image("bus.jpg"), person = image("person.jpg");
	const auto expectedBus = createDetector(test::yoloxOptions())->detect(bus);
	const auto expectedPerson = createDetector(test::yoloxOptions())->detect(person);
	auto run = [](cv::Mat img)
	{
		auto det = createDetector(test::yoloxOptions());
		std::vector<Detection> last;
		for (int i = 0; i < 5; ++i) last = det->detect(img);
		return last;
	};
	auto a = std::async(std::launch::async, run, bus);
	auto b = std::async(std::launch::async, run, person);
	const auto gotBus = a.get(), gotPerson = b.get();
	ASSERT_EQ(gotBus.size(), expectedBus.size());
	ASSERT_EQ(gotPerson.size(), expectedPerson.size());
	for (std::size_t i = 0; i < gotBus.size(); ++i) EXPECT_EQ(gotBus[i].box, expectedBus[i].box);
	for (std::size_t i = 0; i < gotPerson.size(); ++i) EXPECT_EQ(gotPerson[i].box, expectedPerson[i].box);
}

TEST(Detector, TheSimplifiedGraphFindsTheSameObjects)
{
	auto simplified = test::yoloxOptions(), asExported = test::yoloxOptions();
	simplified.classes = asExported.classes = "person, bus";
	asExported.simplify_graph = false;
	const auto a = createDetector(simplified), b = createDetector(asExported);
	EXPECT_NE(a->description().find("space-to-depth"), std::string::npos) << a->description();
	EXPECT_EQ(b->description().find("space-to-depth"), std::string::npos) << b->description();
	for (const char* name : {"person.jpg", "bus.jpg"})
	{
		const auto found = a->detect(image(name)), expected = b->detect(image(name));
		ASSERT_EQ(found.size(), expected.size()) << name;
		ASSERT_FALSE(found.empty()) << name;
		for (std::size_t i = 0; i < found.size(); ++i)
		{
			EXPECT_EQ(found[i].className, expected[i].className) << name;
			EXPECT_NEAR(found[i].score, expected[i].score, 1e-4) << name;
			EXPECT_NEAR(found[i].box.x, expected[i].box.x, 0.01) << name;
			EXPECT_NEAR(found[i].box.y, expected[i].box.y, 0.01) << name;
			EXPECT_NEAR(found[i].box.width, expected[i].box.width, 0.01) << name;
			EXPECT_NEAR(found[i].box.height, expected[i].box.height, 0.01) << name;
		}
	}
}
