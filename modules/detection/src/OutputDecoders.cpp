#include "avm/detection/OutputDecoders.h"

#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>

#include "avm/detection/CocoClasses.h"

namespace avm::detection
{
namespace
{
constexpr int kStrides[] = {8, 16, 32};
constexpr float kPad = 114.f;

int gridCells(cv::Size input)
{
	int n = 0;
	for (int s : kStrides) n += (input.width / s) * (input.height / s);
	return n;
}

/** The output as a 2-D CV_32F matrix of rows x cols, whatever its leading 1s. */
cv::Mat asMatrix(const cv::Mat& output, int expectedCols, const char* layout)
{
	if (output.type() != CV_32F) throw std::invalid_argument(std::string(layout) + " output is not CV_32F");
	if (output.total() % static_cast<std::size_t>(expectedCols) != 0 || output.total() == 0)
		throw std::invalid_argument(
			std::string(layout) + " output size is not a multiple of " + std::to_string(expectedCols));
	cv::Mat m = output.isContinuous() ? output : output.clone();
	return m.reshape(1, static_cast<int>(m.total() / static_cast<std::size_t>(expectedCols)));
}

bool wanted(const DecodeParams& p, int classId)
{
	return p.classIds.empty() || std::find(p.classIds.begin(), p.classIds.end(), classId) != p.classIds.end();
}

/** Best wanted class of one candidate given its class scores (times a common factor). */
void addCandidate(std::vector<Detection>& out, const float* classScores, int numClasses, int classStep, float factor,
	float cx, float cy, float w, float h, const Letterbox& lb, const DecodeParams& p)
{
	int best = -1;
	float bestScore = 0;
	for (int c = 0; c < numClasses; ++c)
	{
		const float s = classScores[c * classStep] * factor;
		if (s > bestScore && wanted(p, c)) best = c, bestScore = s;
	}
	if (best < 0 || bestScore < p.scoreThreshold) return;
	// A broken model can output NaN or infinities; such a box has no place in
	// the image (found by fuzzing: NaN passed std::clamp into the boxes).
	if (!std::isfinite(bestScore) || !std::isfinite(cx) || !std::isfinite(cy) || !std::isfinite(w) || !std::isfinite(h))
		return;
	const cv::Rect2f box = lb.toImage(cx, cy, w, h);
	if (box.width <= 0 || box.height <= 0) return;
	out.push_back({box, best, cocoClassName(best), bestScore});
}
}  // namespace

Letterbox Letterbox::topLeft(cv::Size image, cv::Size input)
{
	Letterbox lb = centred(image, input);
	lb.padX = lb.padY = 0;
	return lb;
}

Letterbox Letterbox::centred(cv::Size image, cv::Size input)
{
	if (image.empty() || input.empty()) throw std::invalid_argument("letterbox of an empty image or input");
	Letterbox lb;
	lb.image = image;
	lb.input = input;
	lb.scale = std::min(double(input.width) / image.width, double(input.height) / image.height);
	lb.padX = (input.width - std::round(image.width * lb.scale)) / 2.0;
	lb.padY = (input.height - std::round(image.height * lb.scale)) / 2.0;
	return lb;
}

cv::Rect2f Letterbox::toImage(float cx, float cy, float w, float h) const
{
	const auto clampX = [&](double x) { return static_cast<float>(std::clamp(x, 0.0, double(image.width))); };
	const auto clampY = [&](double y) { return static_cast<float>(std::clamp(y, 0.0, double(image.height))); };
	const float x0 = clampX((cx - w / 2 - padX) / scale), x1 = clampX((cx + w / 2 - padX) / scale);
	const float y0 = clampY((cy - h / 2 - padY) / scale), y1 = clampY((cy + h / 2 - padY) / scale);
	return {x0, y0, x1 - x0, y1 - y0};
}

Letterbox letterboxFor(OutputLayout layout, cv::Size image, cv::Size input)
{
	return layout == OutputLayout::Yolox ? Letterbox::topLeft(image, input) : Letterbox::centred(image, input);
}

cv::Mat makeInputBlob(const cv::Mat& bgr, OutputLayout layout, cv::Size input, Letterbox& lb)
{
	if (bgr.empty() || bgr.type() != CV_8UC3)
		throw std::invalid_argument("detector input must be a non-empty BGR CV_8UC3 image");
	lb = letterboxFor(layout, bgr.size(), input);
	const cv::Size scaled(
		static_cast<int>(std::round(bgr.cols * lb.scale)), static_cast<int>(std::round(bgr.rows * lb.scale)));
	cv::Mat canvas(input, CV_8UC3, cv::Scalar::all(kPad));
	cv::Mat resized;
	cv::resize(bgr, resized, scaled, 0, 0, cv::INTER_LINEAR);
	resized.copyTo(canvas(cv::Rect(static_cast<int>(lb.padX), static_cast<int>(lb.padY), scaled.width, scaled.height)));
	const bool yolox = layout == OutputLayout::Yolox;
	return cv::dnn::blobFromImage(canvas, yolox ? 1.0 : 1.0 / 255.0, cv::Size(), cv::Scalar(), !yolox, false, CV_32F);
}

std::optional<OutputLayout> recogniseLayout(const std::vector<int>& shape, cv::Size input)
{
	std::vector<int> s;
	for (int d : shape)
		if (d != 1 || !s.empty()) s.push_back(d);  // drop the leading batch dimension(s)
	if (s.size() != 2) return std::nullopt;
	const int cells = gridCells(input);
	if (s[1] == 85 && s[0] == cells) return OutputLayout::Yolox;
	if (s[1] == 85 && s[0] == 3 * cells) return OutputLayout::Yolov5;
	if (s[0] == 84 && s[1] > 84) return OutputLayout::Yolov8;
	return std::nullopt;
}

std::string expectedShape(OutputLayout layout, cv::Size input)
{
	const int cells = gridCells(input);
	switch (layout)
	{
		case OutputLayout::Yolox:
			return "1x" + std::to_string(cells) + "x85";
		case OutputLayout::Yolov5:
			return "1x" + std::to_string(3 * cells) + "x85";
		case OutputLayout::Yolov8:
			return "1x84x" + std::to_string(cells);
		case OutputLayout::Auto:
			break;
	}
	return "1x" + std::to_string(cells) + "x85 (yolox), 1x" + std::to_string(3 * cells) +
		   "x85 (yolov5) or 1x84xN (yolov8)";
}

std::vector<Detection> decodeYolox(const cv::Mat& output, const Letterbox& lb, const DecodeParams& p)
{
	const cv::Mat m = asMatrix(output, 85, "YOLOX");
	if (m.rows != gridCells(lb.input))
		throw std::invalid_argument("YOLOX output has " + std::to_string(m.rows) + " rows, the " +
									std::to_string(lb.input.width) + "x" + std::to_string(lb.input.height) +
									" grids have " + std::to_string(gridCells(lb.input)));
	std::vector<Detection> candidates;
	int row = 0;
	for (int stride : kStrides)
	{
		const int cols = lb.input.width / stride, rows = lb.input.height / stride;
		for (int gy = 0; gy < rows; ++gy)
			for (int gx = 0; gx < cols; ++gx, ++row)
			{
				const float* r = m.ptr<float>(row);
				const float objectness = r[4];
				if (objectness < p.scoreThreshold) continue;  // score = obj * cls <= obj
				const float cx = (r[0] + gx) * stride, cy = (r[1] + gy) * stride;
				const float w = std::exp(r[2]) * stride, h = std::exp(r[3]) * stride;
				addCandidate(candidates, r + 5, 80, 1, objectness, cx, cy, w, h, lb, p);
			}
	}
	return nonMaximumSuppression(candidates, p.nmsThreshold);
}

std::vector<Detection> decodeYolov5(const cv::Mat& output, const Letterbox& lb, const DecodeParams& p)
{
	const cv::Mat m = asMatrix(output, 85, "YOLOv5");
	std::vector<Detection> candidates;
	for (int i = 0; i < m.rows; ++i)
	{
		const float* r = m.ptr<float>(i);
		if (r[4] < p.scoreThreshold) continue;
		addCandidate(candidates, r + 5, 80, 1, r[4], r[0], r[1], r[2], r[3], lb, p);
	}
	return nonMaximumSuppression(candidates, p.nmsThreshold);
}

std::vector<Detection> decodeYolov8(const cv::Mat& output, const Letterbox& lb, const DecodeParams& p)
{
	const int n = static_cast<int>(output.total() / 84);
	const cv::Mat m = asMatrix(output, n, "YOLOv8");  // 84 rows (attributes) x n columns (candidates)
	if (m.rows != 84) throw std::invalid_argument("YOLOv8 output must have 84 rows (4 box + 80 classes)");
	std::vector<Detection> candidates;
	for (int i = 0; i < n; ++i)
	{
		const float* col = m.ptr<float>(0) + i;
		addCandidate(candidates, col + 4 * n, 80, n, 1.f, col[0], col[n], col[2 * n], col[3 * n], lb, p);
	}
	return nonMaximumSuppression(candidates, p.nmsThreshold);
}

std::vector<Detection> decodeOutput(
	OutputLayout layout, const cv::Mat& output, const Letterbox& lb, const DecodeParams& p)
{
	switch (layout)
	{
		case OutputLayout::Yolox:
			return decodeYolox(output, lb, p);
		case OutputLayout::Yolov5:
			return decodeYolov5(output, lb, p);
		case OutputLayout::Yolov8:
			return decodeYolov8(output, lb, p);
		case OutputLayout::Auto:
			break;
	}
	throw std::logic_error("decodeOutput needs a resolved layout");
}

std::vector<Detection> nonMaximumSuppression(const std::vector<Detection>& candidates, float iouThreshold)
{
	std::map<int, std::vector<std::size_t>> byClass;
	for (std::size_t i = 0; i < candidates.size(); ++i) byClass[candidates[i].classId].push_back(i);
	std::vector<Detection> kept;
	for (const auto& [cls, members] : byClass)
	{
		std::vector<cv::Rect2d> boxes;
		std::vector<float> scores;
		for (auto i : members) boxes.emplace_back(candidates[i].box), scores.push_back(candidates[i].score);
		std::vector<int> keep;
		cv::dnn::NMSBoxes(boxes, scores, 0.f, iouThreshold, keep);
		for (int k : keep) kept.push_back(candidates[members[static_cast<std::size_t>(k)]]);
	}
	std::stable_sort(
		kept.begin(), kept.end(), [](const Detection& a, const Detection& b) { return a.score > b.score; });
	return kept;
}
}  // namespace avm::detection
