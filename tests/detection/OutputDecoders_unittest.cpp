// Each decoder on a hand-made output tensor whose boxes are known exactly.
#include <gtest/gtest.h>

#include <cmath>

#include "avm/detection/OutputDecoders.h"

using namespace avm::detection;

namespace
{
// A 64x64 input has 8x8 + 4x4 + 2x2 = 84 grid cells.
const cv::Size kInput(64, 64);
constexpr int kCells = 84;

cv::Mat zeros(std::vector<int> shape)
{
	return cv::Mat(static_cast<int>(shape.size()), shape.data(), CV_32F, cv::Scalar(0));
}

void expectBox(const Detection& d, float x, float y, float w, float h)
{
	EXPECT_NEAR(d.box.x, x, 1e-3);
	EXPECT_NEAR(d.box.y, y, 1e-3);
	EXPECT_NEAR(d.box.width, w, 1e-3);
	EXPECT_NEAR(d.box.height, h, 1e-3);
}

DecodeParams allClasses()
{
	DecodeParams p;
	p.scoreThreshold = 0.3f;
	p.nmsThreshold = 0.45f;
	return p;
}

/** Sets YOLOX row `row`: (x, y, log w, log h, obj, class scores). */
void setYolox(cv::Mat& out, int row, float x, float y, float w, float h, float obj, int cls, float clsScore)
{
	float* r = out.ptr<float>(0, row);
	r[0] = x, r[1] = y, r[2] = std::log(w), r[3] = std::log(h), r[4] = obj, r[5 + cls] = clsScore;
}
}  // namespace

TEST(OutputDecoders, YoloxGridCellDecodesToExactImageBox)
{
	cv::Mat out = zeros({1, kCells, 85});
	// Stride-16 grid (4x4) starts after the 64 stride-8 cells; cell (col 1, row 2).
	setYolox(out, 64 + 2 * 4 + 1, 0.5f, 0.25f, 2.f, 3.f, 0.9f, 0, 0.8f);
	// A 128x128 image is scaled by 0.5 into the top-left of the input.
	const auto lb = Letterbox::topLeft({128, 128}, kInput);
	const auto dets = decodeYolox(out, lb, allClasses());
	ASSERT_EQ(dets.size(), 1u);
	// centre ((0.5+1)*16, (0.25+2)*16) = (24, 36), size (2*16, 3*16) = (32, 48) in input px.
	expectBox(dets[0], (24 - 16) / 0.5f, (36 - 24) / 0.5f, 64, 96);
	EXPECT_EQ(dets[0].classId, 0);
	EXPECT_EQ(dets[0].className, "person");
	EXPECT_NEAR(dets[0].score, 0.72f, 1e-6);
}

TEST(OutputDecoders, YoloxScoreIsObjectnessTimesClassAndThresholded)
{
	cv::Mat out = zeros({1, kCells, 85});
	setYolox(out, 0, 0.5f, 0.5f, 1, 1, 0.5f, 0, 0.5f);    // 0.25 < 0.3
	setYolox(out, 10, 0.5f, 0.5f, 1, 1, 0.7f, 16, 0.5f);  // dog, 0.35
	const auto dets = decodeYolox(out, Letterbox::topLeft(kInput, kInput), allClasses());
	ASSERT_EQ(dets.size(), 1u);
	EXPECT_EQ(dets[0].className, "dog");
	EXPECT_NEAR(dets[0].score, 0.35f, 1e-6);
}

TEST(OutputDecoders, NmsDropsTheWeakerOverlappingBoxOfTheSameClassOnly)
{
	cv::Mat out = zeros({1, kCells, 85});
	// Two stride-8 cells side by side, boxes 32x32: IoU = 24/40 = 0.6 > 0.45.
	setYolox(out, 3 * 8 + 3, 0.f, 0.f, 4, 4, 0.9f, 0, 1.f);
	setYolox(out, 3 * 8 + 4, 0.f, 0.f, 4, 4, 0.8f, 0, 1.f);
	// The same place, another class: kept.
	setYolox(out, 3 * 8 + 5, -1.f, 0.f, 4, 4, 0.7f, 2, 1.f);
	// Far away, same class: kept.
	setYolox(out, 64 + 15, 0.5f, 0.5f, 1, 1, 0.6f, 0, 1.f);
	const auto lb = Letterbox::topLeft(kInput, kInput);
	auto dets = decodeYolox(out, lb, allClasses());
	ASSERT_EQ(dets.size(), 3u);
	EXPECT_NEAR(dets[0].score, 0.9f, 1e-6);
	expectBox(dets[0], 24 - 16, 24 - 16, 32, 32);
	EXPECT_EQ(dets[1].className, "car");
	EXPECT_NEAR(dets[2].score, 0.6f, 1e-6);

	DecodeParams personOnly = allClasses();
	personOnly.classIds = {0};
	dets = decodeYolox(out, lb, personOnly);
	ASSERT_EQ(dets.size(), 2u);
	for (const auto& d : dets) EXPECT_EQ(d.classId, 0);
}

TEST(OutputDecoders, Yolov5DecodedBoxesWithCentredLetterbox)
{
	cv::Mat out = zeros({1, 3 * kCells, 85});
	auto set = [&](int row, float cx, float cy, float w, float h, float obj, int cls, float s)
	{
		float* r = out.ptr<float>(0, row);
		r[0] = cx, r[1] = cy, r[2] = w, r[3] = h, r[4] = obj, r[5 + cls] = s;
	};
	set(7, 32, 32, 20, 10, 0.8f, 0, 0.9f);
	set(8, 33, 32, 20, 10, 0.7f, 0, 0.9f);   // overlaps the first: suppressed
	set(200, 10, 40, 8, 8, 0.9f, 17, 0.5f);  // horse 0.45
	// 128x64 image: scale 0.5, 64x32 centred with 16 rows of padding above.
	const auto lb = Letterbox::centred({128, 64}, kInput);
	EXPECT_DOUBLE_EQ(lb.padY, 16);
	EXPECT_DOUBLE_EQ(lb.padX, 0);
	const auto dets = decodeYolov5(out, lb, allClasses());
	ASSERT_EQ(dets.size(), 2u);
	EXPECT_NEAR(dets[0].score, 0.72f, 1e-6);
	expectBox(dets[0], (32 - 10) / 0.5f, (32 - 5 - 16) / 0.5f, 40, 20);
	EXPECT_EQ(dets[1].className, "horse");
	expectBox(dets[1], (10 - 4) / 0.5f, (40 - 4 - 16) / 0.5f, 16, 16);
}

TEST(OutputDecoders, Yolov8ChannelsFirstNoObjectness)
{
	const int n = kCells;
	cv::Mat out = zeros({1, 84, n});
	auto set = [&](int i, float cx, float cy, float w, float h, int cls, float s)
	{
		float* m = out.ptr<float>(0);
		m[0 * n + i] = cx, m[1 * n + i] = cy, m[2 * n + i] = w, m[3 * n + i] = h, m[(4 + cls) * n + i] = s;
	};
	set(5, 20, 30, 10, 40, 0, 0.6f);
	set(6, 21, 30, 10, 40, 0, 0.5f);  // suppressed by the first
	set(50, 50, 50, 4, 4, 0, 0.2f);   // under the threshold
	const auto lb = Letterbox::centred({64, 64}, kInput);
	const auto dets = decodeYolov8(out, lb, allClasses());
	ASSERT_EQ(dets.size(), 1u);
	EXPECT_NEAR(dets[0].score, 0.6f, 1e-6);
	expectBox(dets[0], 15, 10, 10, 40);
}

TEST(OutputDecoders, BoxesAreClippedToTheImage)
{
	cv::Mat out = zeros({1, kCells, 85});
	setYolox(out, 0, 0.f, 0.f, 4, 4, 1.f, 0, 1.f);  // centre (0,0), 32x32: half outside
	const auto dets = decodeYolox(out, Letterbox::topLeft(kInput, kInput), allClasses());
	ASSERT_EQ(dets.size(), 1u);
	expectBox(dets[0], 0, 0, 16, 16);
}

TEST(OutputDecoders, LayoutRecognisedFromShapeAndInputSize)
{
	EXPECT_EQ(recogniseLayout({1, 3549, 85}, {416, 416}), OutputLayout::Yolox);
	EXPECT_EQ(recogniseLayout({1, 8400, 85}, {640, 640}), OutputLayout::Yolox);
	EXPECT_EQ(recogniseLayout({1, 25200, 85}, {640, 640}), OutputLayout::Yolov5);
	EXPECT_EQ(recogniseLayout({1, 84, 8400}, {640, 640}), OutputLayout::Yolov8);
	EXPECT_EQ(recogniseLayout({1, 3549, 85}, {640, 640}), std::nullopt);
	EXPECT_EQ(recogniseLayout({1, 1000, 6}, {416, 416}), std::nullopt);
	EXPECT_EQ(recogniseLayout({1, 3, 416, 416}, {416, 416}), std::nullopt);
}

TEST(OutputDecoders, WrongRowCountIsAnError)
{
	const cv::Mat out = zeros({1, kCells + 1, 85});
	EXPECT_THROW(decodeYolox(out, Letterbox::topLeft(kInput, kInput), allClasses()), std::invalid_argument);
}
