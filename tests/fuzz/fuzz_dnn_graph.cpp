// Any bytes as an ONNX model file for the detector's graph rewrite: the
// rewritten graph, or the bytes back as they are; never a crash. The seed
// (corpus/dnn_graph/focus_silu.seed) is a small graph with two of its patterns: a
// 2x2 space-to-depth of the input followed by SiLU as Sigmoid and Mul.
#include <cstdint>
#include <set>
#include <string>

#include "DnnGraph.h"

using avm::detection::detail::rewriteForDnn;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	const std::string bytes(reinterpret_cast<const char*>(data), size);
	const auto graph = rewriteForDnn(bytes);
	const bool rewritten = graph.inputSpaceToDepth || graph.swishActivations > 0 || graph.outputTransposed;
	if (!rewritten && graph.onnx != bytes) __builtin_trap();  // changed without a rewrite
	if (rewritten == graph.summary().empty()) __builtin_trap();
	if (graph.inputSpaceToDepth)
	{
		// Four groups, each 2x2 block offset once.
		std::set<std::pair<int, int>> offsets;
		for (const auto& g : graph.inputSpaceToDepth->groups)
		{
			if (g.row < 0 || g.row > 1 || g.col < 0 || g.col > 1) __builtin_trap();
			offsets.insert({g.row, g.col});
		}
		if (graph.inputSpaceToDepth->groups.size() != 4 || offsets.size() != 4) __builtin_trap();
	}
	if (rewriteForDnn(bytes).onnx != graph.onnx) __builtin_trap();  // the same bytes give the same graph
	return 0;
}
