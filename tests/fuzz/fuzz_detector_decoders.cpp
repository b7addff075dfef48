// Any bytes as a network output tensor (floats, NaN and infinities included)
// for each layout: decoded boxes lie inside the image; never a crash.
#include <cmath>
#include <cstring>
#include <opencv2/core.hpp>
#include <stdexcept>

#include "avm/detection/OutputDecoders.h"

using namespace avm::detection;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	if (size < 2) return 0;
	// First byte: which layout and a small input size; the rest: the tensor.
	const int selector = data[0];
	const cv::Size input(32 * (1 + (data[1] % 4)), 32 * (1 + (data[1] / 4 % 4)));
	const cv::Size image(input.width * 2 + 3, input.height + 7);
	const OutputLayout layouts[] = {OutputLayout::Yolox, OutputLayout::Yolov5, OutputLayout::Yolov8};
	const OutputLayout layout = layouts[selector % 3];
	// The tensor has the shape the layout has for this input; the fuzz bytes
	// fill it, repeated as needed, so every input reaches the decoder.
	int cells = 0;
	for (const int stride : {8, 16, 32}) cells += (input.width / stride) * (input.height / stride);
	const int width = layout == OutputLayout::Yolov8 ? 84 : 85;
	const int rows = layout == OutputLayout::Yolov5 ? 3 * cells : cells;
	cv::Mat output = layout == OutputLayout::Yolov8 ? cv::Mat(width, rows, CV_32F) : cv::Mat(rows, width, CV_32F);
	const std::size_t bytes = output.total() * sizeof(float), payload = size - 2;
	for (std::size_t i = 0; i < bytes; ++i) output.data[i] = data[2 + i % payload];
	const Letterbox lb =
		layout == OutputLayout::Yolox ? Letterbox::topLeft(image, input) : Letterbox::centred(image, input);
	DecodeParams params;
	params.classIds = selector & 8 ? std::vector<int>{} : std::vector<int>{0};
	try
	{
		for (const auto& d : decodeOutput(layout, output, lb, params))
			if (!(d.box.x >= 0 && d.box.y >= 0 && d.box.x + d.box.width <= image.width + 1e-3 &&
					d.box.y + d.box.height <= image.height + 1e-3 && std::isfinite(d.score)))
				__builtin_trap();  // a decoded box outside the image is a bug
	}
	catch (const std::invalid_argument&)
	{
	}
	return 0;
}
