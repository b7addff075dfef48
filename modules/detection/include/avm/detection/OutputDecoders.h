// From a YOLO-family output tensor to detections in image pixels. Each layout
// comes with its own input preparation (letterbox side, channel order, scale),
// because the networks were trained that way.
#pragma once

#include <opencv2/core/mat.hpp>

#include <optional>
#include <vector>

#include "avm/detection/Detection.h"
#include "avm/detection/TDetectorOptions.h"

namespace avm::detection
{
/** How an image was scaled and padded into the network input. */
struct Letterbox
{
	double scale = 1;           //!< input pixels per image pixel
	double padX = 0, padY = 0;  //!< [input px] offset of the image in the input
	cv::Size image, input;

	/** YOLOX: image at the top-left corner. */
	static Letterbox topLeft(cv::Size image, cv::Size input);
	/** YOLOv5/v8: image centred. */
	static Letterbox centred(cv::Size image, cv::Size input);
	/** A box in input pixels (centre, size) to image pixels, clipped to the image. */
	cv::Rect2f toImage(float cx, float cy, float w, float h) const;
};

/** The letterbox a layout is trained with. */
Letterbox letterboxFor(OutputLayout layout, cv::Size image, cv::Size input);

/** The network input blob (1x3xHxW, CV_32F) for a BGR image: YOLOX takes BGR
 *  0..255 padded 114 at the top-left; YOLOv5/v8 take RGB 0..1 padded 114/255,
 *  centred. */
cv::Mat makeInputBlob(const cv::Mat& bgr, OutputLayout layout, cv::Size input, Letterbox& letterbox);

struct DecodeParams
{
	std::vector<int> classIds;  //!< classes kept; empty = all
	float scoreThreshold = 0.3f;
	float nmsThreshold = 0.45f;
};

/** The layout an output of this shape has for this input size, if any:
 *  1x84xN (N > 84) is YOLOv8; 1xNx85 is YOLOX when N is the number of stride
 *  8/16/32 grid cells, YOLOv5 when it is three times that (three anchors). */
std::optional<OutputLayout> recogniseLayout(const std::vector<int>& outputShape, cv::Size input);
/** The shape an output of `layout` has for this input size, e.g. "1x3549x85". */
std::string expectedShape(OutputLayout layout, cv::Size input);

/** YOLOX raw grid output, 1xNx85 (or Nx85): per cell of the stride 8, 16, 32
 *  grids in row-major order, (x, y, log w, log h, objectness, 80 class scores)
 *  with x = (x + col) * stride, w = exp(log w) * stride, score = obj * class. */
std::vector<Detection> decodeYolox(const cv::Mat& output, const Letterbox& lb, const DecodeParams& p);
/** YOLOv5 output, 1xNx85: (cx, cy, w, h) in input pixels, objectness, classes. */
std::vector<Detection> decodeYolov5(const cv::Mat& output, const Letterbox& lb, const DecodeParams& p);
/** YOLOv8/YOLO11 output, 1x84xN: rows cx, cy, w, h, then 80 class scores. */
std::vector<Detection> decodeYolov8(const cv::Mat& output, const Letterbox& lb, const DecodeParams& p);
/** Dispatches on a resolved layout (not Auto). */
std::vector<Detection> decodeOutput(
	OutputLayout layout, const cv::Mat& output, const Letterbox& lb, const DecodeParams& p);

/** Per-class non-maximum suppression; result sorted by score, best first. */
std::vector<Detection> nonMaximumSuppression(const std::vector<Detection>& candidates, float iouThreshold);
}  // namespace avm::detection
