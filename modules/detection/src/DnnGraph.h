// A YOLO-family ONNX graph rewritten into the same network in a form
// cv::dnn 4.6 runs faster. Three patterns of these models cost far more there
// than their arithmetic:
// - the input space-to-depth ("Focus" of YOLOX and YOLOv5 v1-v5): eight
//   strided Slice layers and a Concat, which take OpenCV 4.6 far longer than
//   the copy they make, where a loop over the input blob does that copy;
// - SiLU exported as Sigmoid and Mul: two layers and two passes over memory
//   per activation, where a Swish layer (SwishLayer.h) computes
//   x / (1 + exp(-x)) inside the convolution before it (the float results
//   differ in the last bits only);
// - the output's last Transpose (YOLOX's 1x85xN to 1xNx85): OpenCV's Permute
//   layer, where cv::transpose makes the same copy in a fraction of the time.
#pragma once

#include <opencv2/core/mat.hpp>

#include <optional>
#include <string>
#include <vector>

namespace avm::detection::detail
{
/** Where each channel group of a space-to-depth takes its pixels from. */
struct SpaceToDepth
{
	struct Offset
	{
		int row = 0, col = 0;  //!< [px] 0 or 1 in each 2x2 block
	};
	std::vector<Offset> groups;  //!< in the model's concatenation order

	/** A 1xCxHxW CV_32F blob as 1x(4C)x(H/2)x(W/2): group g, channel c is
	 *  the input's channel c at rows 2y + groups[g].row, columns 2x + groups[g].col. */
	cv::Mat apply(const cv::Mat& blob) const;
};

struct DnnGraph
{
	std::string onnx;  //!< the model to load (the file's bytes when nothing was rewritten)
	/** Set when the graph now starts after its input's space-to-depth: the
	 *  caller applies it to the blob before setInput. */
	std::optional<SpaceToDepth> inputSpaceToDepth;
	int swishActivations = 0;  //!< Sigmoid and Mul pairs now one Swish layer (kSwishLayerType)
	/** Set when the graph now ends before its output's Transpose (perm 0, 2,
	 *  1): the caller applies swapLastAxes to what the network gives. */
	bool outputTransposed = false;

	/** What changed, for the detector's description ("" when nothing). */
	std::string summary() const;
};

/** A 3-d CV_32F blob A x B x C as A x C x B (the Transpose perm 0, 2, 1). */
cv::Mat swapLastAxes(const cv::Mat& output);

/** The rewritten graph of an ONNX file's bytes. Anything unexpected (a graph
 *  these patterns do not match exactly, bytes that are not a protobuf) leaves
 *  that part as it is, so that cv::dnn reports a broken file as it would.
 *  Registers the Swish layer with cv::dnn when the graph uses it. */
DnnGraph rewriteForDnn(std::string onnx);
}  // namespace avm::detection::detail
