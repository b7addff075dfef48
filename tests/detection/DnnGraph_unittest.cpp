// The rewritten graph against the model as exported (YOLOX-Nano and a small
// graph with its patterns): the same network, without the layers the rewrite
// removes; a pattern that does not match exactly is left as it is.
#include <gtest/gtest.h>
#include <mrpt/io/vector_loadsave.h>

#include <opencv2/dnn.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cstdint>
#include <cstring>
#include <map>

#include "DnnGraph.h"
#include "SwishLayer.h"
#include "TestData.h"

using avm::detection::detail::rewriteForDnn;
using avm::detection::detail::SpaceToDepth;
using avm::detection::detail::swapLastAxes;

namespace
{
std::string yoloxBytes()
{
	return mrpt::io::file_get_contents(avm::test::sharedFile("models/yolox_nano.onnx").string());
}

cv::dnn::Net load(const std::string& onnx)
{
	cv::dnn::Net net = cv::dnn::readNetFromONNX(onnx.data(), onnx.size());
	net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
	net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
	return net;
}

/** A small ONNX model written field by field (onnx.proto's numbers), with
 *  the patterns of a YOLOX export: a 2x2 space-to-depth of a 1x3x4x4 input
 *  (four chains Slice(rows) -> Slice(columns), concatenated on the channels
 *  in `order`), then SiLU as Sigmoid and Mul. */
class TinyModel
{
   public:
	using Offset = std::pair<int, int>;                         // row, column in each 2x2 block
	std::vector<Offset> order{{0, 0}, {1, 0}, {0, 1}, {1, 1}};  // YOLOX's
	// A Sigmoid of the input is a second output.
	bool inputReadElsewhere = false;
	// The SiLU's sigmoid is an output too.
	bool sigmoidIsAnOutput = false;
	// The SiLU reshaped to 1x12x4 and transposed to 1x4x12 is the output.
	bool transposedOutput = false;

	std::string bytes() const
	{
		std::string nodes;
		std::vector<std::string> patches;
		for (const auto& [row, col] : order)
		{
			const std::string rows = "rows" + std::to_string(row) + std::to_string(col),
							  patch = "patch" + std::to_string(row) + std::to_string(col);
			nodes += field(1, node("Slice", {"images", row ? "one" : "zero", "end", "axis2", "two"}, rows));
			nodes += field(1, node("Slice", {rows, col ? "one" : "zero", "end", "axis3", "two"}, patch));
			patches.push_back(patch);
		}
		const std::string axis = field(1, "axis") + number(3, 1) + number(20, 2);  // INT attribute
		nodes += field(1, node("Concat", patches, "focus", field(5, axis)));
		nodes += field(1, node("Sigmoid", {"focus"}, "sigmoid"));
		nodes += field(1, node("Mul", {"focus", "sigmoid"}, "silu"));
		std::string outputs = field(12, valueInfo("silu", {1, 12, 2, 2}));
		if (transposedOutput)
		{
			nodes += field(1, node("Reshape", {"silu", "shape"}, "flat"));
			// An INTS attribute.
			const std::string perm = field(1, "perm") + number(8, 0) + number(8, 2) + number(8, 1) + number(20, 7);
			nodes += field(1, node("Transpose", {"flat"}, "out", field(5, perm)));
			outputs = field(12, valueInfo("out", {1, 4, 12}));
		}
		if (inputReadElsewhere)
		{
			nodes += field(1, node("Sigmoid", {"images"}, "inputSigmoid"));
			outputs += field(12, valueInfo("inputSigmoid", {1, 3, 4, 4}));
		}
		if (sigmoidIsAnOutput) outputs += field(12, valueInfo("sigmoid", {1, 12, 2, 2}));
		std::string initializers;
		for (const auto& [name, values] :
			std::vector<std::pair<std::string, std::vector<std::int64_t>>>{{"zero", {0}}, {"one", {1}},
				{"end", {INT64_MAX}}, {"two", {2}}, {"axis2", {2}}, {"axis3", {3}}, {"shape", {1, 12, 4}}})
		{
			std::string raw(values.size() * sizeof(std::int64_t), '\0');
			std::memcpy(raw.data(), values.data(), raw.size());
			initializers += field(5, number(1, values.size()) + number(2, 7) + field(8, name) + field(9, raw));
		}
		const std::string graph =
			nodes + field(2, "tiny") + initializers + field(11, valueInfo("images", {1, 3, 4, 4})) + outputs;
		return number(1, 8) + field(7, graph) + field(8, number(2, 13));  // IR 8, opset 13
	}

   private:
	static std::string varint(std::uint64_t v)
	{
		std::string out;
		for (; v >= 0x80; v >>= 7) out.push_back(char((v & 0x7f) | 0x80));
		out.push_back(char(v));
		return out;
	}
	static std::string number(std::uint32_t field, std::uint64_t v) { return varint(field << 3) + varint(v); }
	static std::string field(std::uint32_t field, const std::string& payload)
	{
		return varint((field << 3) | 2) + varint(payload.size()) + payload;
	}
	static std::string node(const std::string& op, const std::vector<std::string>& inputs, const std::string& output,
		const std::string& attributes = "")
	{
		std::string n;
		for (const auto& in : inputs) n += field(1, in);
		return n + field(2, output) + field(3, output + "_node") + field(4, op) + attributes;
	}
	static std::string valueInfo(const std::string& name, const std::vector<int>& dims)
	{
		std::string shape;
		for (const int d : dims) shape += field(1, number(1, std::uint64_t(d)));
		return field(1, name) + field(2, field(1, number(1, 1) + field(2, shape)));  // float tensor
	}
};

/** The model's outputs on a 1x3x4x4 ramp, through the rewrite when `rewritten`. */
std::vector<cv::Mat> outputsOf(const std::string& onnx, bool rewritten)
{
	const int shape[4] = {1, 3, 4, 4};
	cv::Mat input(4, shape, CV_32F);
	for (int i = 0; i < 48; ++i) input.ptr<float>()[i] = float(i) - 20.f;
	const auto graph = rewriteForDnn(onnx);
	cv::dnn::Net net = load(rewritten ? graph.onnx : onnx);
	net.setInput(rewritten && graph.inputSpaceToDepth ? graph.inputSpaceToDepth->apply(input) : input);
	std::vector<cv::Mat> outputs;
	net.forward(outputs, net.getUnconnectedOutLayersNames());
	if (rewritten && graph.outputTransposed)
		for (auto& out : outputs) out = swapLastAxes(out);
	return outputs;
}

/** Each output of the rewritten model is the model's as exported, and not zeros. */
void expectSameOutputs(const std::string& onnx)
{
	const auto expected = outputsOf(onnx, false), found = outputsOf(onnx, true);
	ASSERT_EQ(found.size(), expected.size());
	for (std::size_t i = 0; i < found.size(); ++i)
	{
		ASSERT_EQ(found[i].size, expected[i].size) << "output " << i;
		EXPECT_LT(cv::norm(found[i], expected[i], cv::NORM_INF), 1e-5) << "output " << i;
		EXPECT_GT(cv::norm(expected[i], cv::NORM_INF), 0.5) << "output " << i;
	}
}

/** Layers by type once the network has run (OpenCV fuses layers then). */
std::map<std::string, int> layerTypes(cv::dnn::Net& net)
{
	std::map<std::string, int> types;
	for (const auto& name : net.getLayerNames()) ++types[net.getLayer(name)->type];
	return types;
}
}  // namespace

TEST(DnnGraph, YoloxNanoGivesTheSameOutputsWithoutItsFocusSlicesAndSigmoidMulPairs)
{
	const std::string original = yoloxBytes();
	ASSERT_FALSE(original.empty());
	const auto graph = rewriteForDnn(original);
	ASSERT_TRUE(graph.inputSpaceToDepth);
	// YOLOX's Focus: top-left, bottom-left, top-right, bottom-right.
	const std::vector<std::pair<int, int>> expected{{0, 0}, {1, 0}, {0, 1}, {1, 1}};
	std::vector<std::pair<int, int>> groups;
	for (const auto& g : graph.inputSpaceToDepth->groups) groups.emplace_back(g.row, g.col);
	EXPECT_EQ(groups, expected);
	EXPECT_GT(graph.swishActivations, 0);
	EXPECT_TRUE(graph.outputTransposed);
	EXPECT_LT(graph.onnx.size(), original.size());

	cv::dnn::Net before = load(original), after = load(graph.onnx);
	for (const char* image : {"images/person.jpg", "images/bus.jpg"})
	{
		const cv::Mat bgr = cv::imread(avm::test::sharedFile(image).string());
		ASSERT_FALSE(bgr.empty()) << image;
		const cv::Mat blob = cv::dnn::blobFromImage(bgr, 1.0, cv::Size(256, 192), cv::Scalar(), false, false);
		before.setInput(blob);
		const cv::Mat expectedOut = before.forward().clone();
		after.setInput(graph.inputSpaceToDepth->apply(blob));
		const cv::Mat out = swapLastAxes(after.forward());
		ASSERT_EQ(out.size, expectedOut.size);
		// Swish computes x / (1 + e^-x) where the export multiplies x by the
		// sigmoid: the last bits of the floats differ, nothing more.
		EXPECT_LT(cv::norm(out, expectedOut, cv::NORM_INF), 1e-3) << image;
		EXPECT_GT(cv::norm(expectedOut, cv::NORM_INF), 1.0) << image;  // a real output, not zeros
	}
	auto typesBefore = layerTypes(before), typesAfter = layerTypes(after);
	EXPECT_EQ(typesBefore["Slice"], 8);
	EXPECT_EQ(typesAfter["Slice"], 0);
	EXPECT_EQ(typesAfter[avm::detection::detail::kSwishLayerType], graph.swishActivations);
	EXPECT_EQ(typesBefore["Sigmoid"] - typesAfter["Sigmoid"], graph.swishActivations);
	EXPECT_EQ(typesBefore["Convolution"], typesAfter["Convolution"]);
	EXPECT_EQ(typesBefore["Permute"], 1);
	EXPECT_EQ(typesAfter["Permute"], 0);
}

TEST(DnnGraph, SpaceToDepthTakesEachGroupsPixels)
{
	const int shape[4] = {1, 2, 4, 6};
	cv::Mat blob(4, shape, CV_32F);
	for (int c = 0; c < 2; ++c)
		for (int y = 0; y < 4; ++y)
			for (int x = 0; x < 6; ++x) blob.ptr<float>(0, c, y)[x] = float(100 * c + 10 * y + x);
	const SpaceToDepth s{{{0, 0}, {1, 0}, {0, 1}, {1, 1}}};
	const cv::Mat out = s.apply(blob);
	ASSERT_EQ(out.dims, 4);
	EXPECT_EQ(out.size[1], 8);
	EXPECT_EQ(out.size[2], 2);
	EXPECT_EQ(out.size[3], 3);
	for (int g = 0; g < 4; ++g)
		for (int c = 0; c < 2; ++c)
			for (int y = 0; y < 2; ++y)
				for (int x = 0; x < 3; ++x)
				{
					const auto& o = s.groups[std::size_t(g)];
					EXPECT_EQ(out.ptr<float>(0, 2 * g + c, y)[x], blob.ptr<float>(0, c, 2 * y + o.row)[2 * x + o.col]);
				}
}

TEST(DnnGraph, BytesThatAreNoModelComeBackAsTheyAre)
{
	const std::string original = yoloxBytes();
	for (const std::string& bytes :
		{std::string("not an onnx model\n"), original.substr(0, original.size() / 2), std::string()})
	{
		const auto graph = rewriteForDnn(bytes);
		EXPECT_EQ(graph.onnx, bytes);
		EXPECT_FALSE(graph.inputSpaceToDepth);
		EXPECT_EQ(graph.swishActivations, 0);
		EXPECT_FALSE(graph.outputTransposed);
		EXPECT_EQ(graph.summary(), "");
	}
}

TEST(DnnGraph, ASmallExportsPatternsAreRewrittenInItsOwnGroupOrder)
{
	for (const auto& order : {std::vector<TinyModel::Offset>{{0, 0}, {1, 0}, {0, 1}, {1, 1}},
			 std::vector<TinyModel::Offset>{{1, 1}, {0, 0}, {0, 1}, {1, 0}}})
	{
		TinyModel model;
		model.order = order;
		const std::string onnx = model.bytes();
		const auto graph = rewriteForDnn(onnx);
		ASSERT_TRUE(graph.inputSpaceToDepth);
		std::vector<TinyModel::Offset> groups;
		for (const auto& g : graph.inputSpaceToDepth->groups) groups.emplace_back(g.row, g.col);
		EXPECT_EQ(groups, order);
		EXPECT_EQ(graph.swishActivations, 1);
		EXPECT_FALSE(graph.outputTransposed);
		expectSameOutputs(onnx);
	}
	TinyModel transposed;
	transposed.transposedOutput = true;
	const auto graph = rewriteForDnn(transposed.bytes());
	EXPECT_TRUE(graph.inputSpaceToDepth);
	EXPECT_EQ(graph.swishActivations, 1);
	EXPECT_TRUE(graph.outputTransposed);
	expectSameOutputs(transposed.bytes());
}

TEST(DnnGraph, SwapLastAxesIsATransposeOfEachPlane)
{
	const int shape[3] = {2, 3, 5};
	cv::Mat blob(3, shape, CV_32F);
	for (int i = 0; i < 30; ++i) blob.ptr<float>()[i] = float(i);
	const cv::Mat out = swapLastAxes(blob);
	ASSERT_EQ(out.dims, 3);
	EXPECT_EQ(out.size[0], 2);
	EXPECT_EQ(out.size[1], 5);
	EXPECT_EQ(out.size[2], 3);
	for (int p = 0; p < 2; ++p)
		for (int r = 0; r < 3; ++r)
			for (int c = 0; c < 5; ++c) EXPECT_EQ(out.ptr<float>(p, c)[r], blob.ptr<float>(p, r)[c]);
}

TEST(DnnGraph, APatternThatDoesNotMatchExactlyIsLeftAsItIs)
{
	// The input is read by another layer too: its space-to-depth stays in the graph.
	TinyModel inputShared;
	inputShared.inputReadElsewhere = true;
	auto graph = rewriteForDnn(inputShared.bytes());
	EXPECT_FALSE(graph.inputSpaceToDepth);
	EXPECT_EQ(graph.swishActivations, 1);
	expectSameOutputs(inputShared.bytes());

	// The sigmoid is also an output of the graph: the Mul cannot take it over.
	TinyModel sigmoidOut;
	sigmoidOut.sigmoidIsAnOutput = true;
	graph = rewriteForDnn(sigmoidOut.bytes());
	EXPECT_TRUE(graph.inputSpaceToDepth);
	EXPECT_EQ(graph.swishActivations, 0);
	expectSameOutputs(sigmoidOut.bytes());

	// Both: nothing to rewrite, the bytes come back as they are.
	TinyModel neither;
	neither.inputReadElsewhere = neither.sigmoidIsAnOutput = true;
	graph = rewriteForDnn(neither.bytes());
	EXPECT_EQ(graph.onnx, neither.bytes());
	EXPECT_FALSE(graph.inputSpaceToDepth);
	EXPECT_EQ(graph.swishActivations, 0);
}
