// The rewritten YOLOX-Nano graph against the model as exported: the same
// network (outputs on real images), without the layers the rewrite removes.
#include <gtest/gtest.h>
#include <mrpt/io/vector_loadsave.h>

#include <opencv2/dnn.hpp>
#include <opencv2/imgcodecs.hpp>

#include <map>

#include "DnnGraph.h"
#include "TestData.h"

using avm::detection::detail::rewriteForDnn;
using avm::detection::detail::SpaceToDepth;

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
		const cv::Mat out = after.forward();
		ASSERT_EQ(out.size, expectedOut.size);
		// Swish computes x / (1 + e^-x) where the export multiplies x by the
		// sigmoid: the last bits of the floats differ, nothing more.
		EXPECT_LT(cv::norm(out, expectedOut, cv::NORM_INF), 1e-3) << image;
		EXPECT_GT(cv::norm(expectedOut, cv::NORM_INF), 1.0) << image;  // a real output, not zeros
	}
	auto typesBefore = layerTypes(before), typesAfter = layerTypes(after);
	EXPECT_EQ(typesBefore["Slice"], 8);
	EXPECT_EQ(typesAfter["Slice"], 0);
	EXPECT_EQ(typesAfter["Swish"], graph.swishActivations);
	EXPECT_EQ(typesBefore["Sigmoid"] - typesAfter["Sigmoid"], graph.swishActivations);
	EXPECT_EQ(typesBefore["Convolution"], typesAfter["Convolution"]);
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
		EXPECT_EQ(graph.summary(), "");
	}
}
