#include "DnnGraph.h"

#include <opencv2/core.hpp>

#include <cstdint>
#include <algorithm>
#include <cstring>
#include <map>
#include <set>
#include <stdexcept>
#include <string_view>

#include "SwishLayer.h"

namespace avm::detection::detail
{
namespace
{
// --- protobuf's wire format, as much of it as an ONNX graph needs ---------
// A message is a list of fields viewing the file's bytes (a model's weights
// are most of them: nothing is copied but the graph written anew); a rewrite
// drops fields or writes new ones, and every field it does not touch is
// written back byte for byte.

struct WireError : std::runtime_error
{
	using std::runtime_error::runtime_error;
};

struct Field
{
	std::uint32_t number = 0;
	int wireType = 0;        //!< 0 varint, 1 fixed 64 bits, 2 length-delimited, 5 fixed 32 bits
	std::string_view value;  //!< a varint's bytes as encoded, a fixed field's bytes, or the payload
};
using Message = std::vector<Field>;

constexpr int kVarint = 0, kLengthDelimited = 2;

std::uint64_t readVarint(std::string_view bytes, std::size_t& at)
{
	std::uint64_t value = 0;
	for (int shift = 0; shift < 64; shift += 7)
	{
		if (at >= bytes.size()) throw WireError("truncated varint");
		const auto byte = static_cast<unsigned char>(bytes[at++]);
		value |= std::uint64_t(byte & 0x7f) << shift;
		if (byte < 0x80) return value;
	}
	throw WireError("varint longer than 64 bits");
}

void writeVarint(std::string& out, std::uint64_t value)
{
	for (; value >= 0x80; value >>= 7) out.push_back(char((value & 0x7f) | 0x80));
	out.push_back(char(value));
}

/** The fields of a message; they view `bytes`, which must outlive them. */
Message parse(std::string_view bytes)
{
	Message message;
	std::size_t at = 0;
	while (at < bytes.size())
	{
		const std::uint64_t tag = readVarint(bytes, at);
		Field f{std::uint32_t(tag >> 3), int(tag & 7), {}};
		std::size_t begin = at, length = 0;
		switch (f.wireType)
		{
			case kVarint:
				readVarint(bytes, at);
				length = at - begin;
				break;
			case 1:
				length = 8;
				break;
			case kLengthDelimited:
				length = readVarint(bytes, at);
				begin = at;
				break;
			case 5:
				length = 4;
				break;
			default:
				throw WireError("unsupported wire type");
		}
		if (length > bytes.size() - begin) throw WireError("truncated field");
		f.value = bytes.substr(begin, length);
		at = begin + length;
		message.push_back(f);
	}
	return message;
}

/** A field as written in a message. */
std::string encoded(const Field& f)
{
	std::string out;
	writeVarint(out, (std::uint64_t(f.number) << 3) | std::uint64_t(f.wireType));
	if (f.wireType == kLengthDelimited) writeVarint(out, f.value.size());
	out += f.value;
	return out;
}

std::string bytesField(std::uint32_t number, std::string_view payload)
{
	return encoded({number, kLengthDelimited, payload});
}

std::string varintField(std::uint32_t number, std::uint64_t value)
{
	std::string bytes;
	writeVarint(bytes, value);
	return encoded({number, kVarint, bytes});
}

std::int64_t varintOf(const Field& f)
{
	std::size_t at = 0;
	return static_cast<std::int64_t>(readVarint(f.value, at));
}

std::vector<std::string> stringsOf(const Message& m, std::uint32_t number)
{
	std::vector<std::string> out;
	for (const auto& f : m)
		if (f.number == number && f.wireType == kLengthDelimited) out.emplace_back(f.value);
	return out;
}

const Field* firstOf(const Message& m, std::uint32_t number)
{
	for (const auto& f : m)
		if (f.number == number) return &f;
	return nullptr;
}

// --- the ONNX messages (onnx.proto field numbers) -------------------------
namespace model
{
constexpr std::uint32_t graph = 7;
}
namespace graph
{
constexpr std::uint32_t node = 1, initializer = 5, input = 11, output = 12;
}
namespace node
{
constexpr std::uint32_t input = 1, output = 2, opType = 4, attribute = 5;
}
namespace attribute
{
constexpr std::uint32_t name = 1, i = 3, ints = 8;
}
namespace tensor
{
constexpr std::uint32_t dims = 1, dataType = 2, int64Data = 7, name = 8, rawData = 9;
constexpr std::int64_t int64Type = 7;
}  // namespace tensor
namespace value_info
{
constexpr std::uint32_t name = 1, type = 2;
}
namespace type_proto
{
constexpr std::uint32_t tensorType = 1, elemType = 1, shape = 2, dim = 1, dimValue = 1;
}

struct Node
{
	std::size_t field = 0;  //!< its index among the graph's fields
	Message message;
	std::vector<std::string> inputs, outputs;
	std::string opType;
};

struct Graph
{
	Message fields;
	std::vector<Node> nodes;
	std::map<std::string, Message> initializers;
	std::map<std::string, int> uses;              //!< consumers of a tensor, the graph's outputs among them
	std::map<std::string, std::size_t> producer;  //!< node (index in nodes) writing a tensor

	explicit Graph(std::string_view bytes) : fields(parse(bytes))
	{
		for (std::size_t i = 0; i < fields.size(); ++i)
		{
			const Field& f = fields[i];
			if (f.wireType != kLengthDelimited) continue;
			if (f.number == graph::node)
			{
				Node n{i, parse(f.value), {}, {}, {}};
				n.inputs = stringsOf(n.message, node::input);
				n.outputs = stringsOf(n.message, node::output);
				const auto op = stringsOf(n.message, node::opType);
				n.opType = op.empty() ? "" : op.front();
				for (const auto& in : n.inputs) ++uses[in];
				for (const auto& out : n.outputs) producer[out] = nodes.size();
				nodes.push_back(std::move(n));
			}
			else if (f.number == graph::initializer)
			{
				Message t = parse(f.value);
				const auto name = stringsOf(t, tensor::name);
				if (!name.empty()) initializers[name.front()] = std::move(t);
			}
			else if (f.number == graph::output)
				for (const auto& name : stringsOf(parse(f.value), value_info::name)) ++uses[name];
		}
	}

	int usesOf(const std::string& tensor) const
	{
		const auto it = uses.find(tensor);
		return it == uses.end() ? 0 : it->second;
	}

	/** The single value of a one-element INT64 initializer. */
	std::optional<std::int64_t> scalarInt64(const std::string& name) const
	{
		const auto it = initializers.find(name);
		if (it == initializers.end()) return std::nullopt;
		const Message& t = it->second;
		const Field* type = firstOf(t, tensor::dataType);
		if (!type || varintOf(*type) != tensor::int64Type) return std::nullopt;
		for (const auto& f : t)
			if (f.number == tensor::dims && varintOf(f) != 1) return std::nullopt;
		if (const Field* raw = firstOf(t, tensor::rawData))
		{
			if (raw->value.size() != sizeof(std::int64_t)) return std::nullopt;
			std::int64_t v = 0;  // ONNX stores raw data little-endian, as this CPU does
			std::memcpy(&v, raw->value.data(), sizeof v);
			return v;
		}
		if (const Field* data = firstOf(t, tensor::int64Data))
		{
			if (data->wireType == kVarint) return varintOf(*data);
			std::size_t at = 0;
			const auto v = static_cast<std::int64_t>(readVarint(data->value, at));
			if (at != data->value.size()) return std::nullopt;
			return v;
		}
		return std::nullopt;
	}

	/** The nodes reading `tensor`. */
	std::vector<std::size_t> consumers(const std::string& tensor) const
	{
		std::vector<std::size_t> out;
		for (std::size_t i = 0; i < nodes.size(); ++i)
			for (const auto& in : nodes[i].inputs)
				if (in == tensor)
				{
					out.push_back(i);
					break;
				}
		return out;
	}
};

/** A Slice of every second row (axis 2) or column (axis 3) from 0 or 1 to
 *  the end of a 4-d tensor. */
struct StrideTwoSlice
{
	int axis = 0;
	int start = 0;
};

std::optional<StrideTwoSlice> strideTwoSlice(const Graph& g, const Node& n)
{
	// Slice(data, starts, ends, axes, steps), opset 10 and later.
	if (n.opType != "Slice" || n.inputs.size() != 5 || n.outputs.size() != 1) return std::nullopt;
	const auto start = g.scalarInt64(n.inputs[1]), end = g.scalarInt64(n.inputs[2]);
	const auto axis = g.scalarInt64(n.inputs[3]), step = g.scalarInt64(n.inputs[4]);
	if (!start || !end || !axis || !step || *step != 2 || (*start != 0 && *start != 1) || *end < (1LL << 30))
		return std::nullopt;
	const std::int64_t a = *axis < 0 ? *axis + 4 : *axis;
	if (a != 2 && a != 3) return std::nullopt;
	return StrideTwoSlice{int(a), int(*start)};
}

/** A tensor's value info: its element type and its dimensions, all known. */
struct TensorInfo
{
	std::string elemType;  //!< the field as encoded
	std::vector<std::int64_t> dims;

	static std::optional<TensorInfo> of(std::string_view valueInfo)
	{
		const Message info = parse(valueInfo);
		const Field* type = firstOf(info, value_info::type);
		if (!type) return std::nullopt;
		const Message typeProto = parse(type->value);
		const Field* tensorType = firstOf(typeProto, type_proto::tensorType);
		if (!tensorType) return std::nullopt;
		const Message tt = parse(tensorType->value);
		const Field* elemType = firstOf(tt, type_proto::elemType);
		const Field* shape = firstOf(tt, type_proto::shape);
		if (!elemType || !shape) return std::nullopt;
		TensorInfo out{encoded(*elemType), {}};
		for (const auto& d : parse(shape->value))
		{
			if (d.number != type_proto::dim) continue;
			const Message dim = parse(d.value);
			const Field* value = firstOf(dim, type_proto::dimValue);
			if (!value) return std::nullopt;  // a named (dynamic) dimension: left as it is
			out.dims.push_back(varintOf(*value));
		}
		return out;
	}

	/** The value info of a tensor `name` of this type. */
	std::string valueInfo(const std::string& name) const
	{
		std::string shapeBytes;
		for (const auto d : dims)
			shapeBytes += bytesField(type_proto::dim, varintField(type_proto::dimValue, std::uint64_t(d)));
		const std::string tensorTypeBytes = elemType + bytesField(type_proto::shape, shapeBytes);
		return bytesField(value_info::name, name) +
			   bytesField(value_info::type, bytesField(type_proto::tensorType, tensorTypeBytes));
	}
};

/** Nodes to drop, nodes and fields to replace: the rewrite of one graph. */
struct Edits
{
	std::set<std::size_t> droppedNodes;
	std::map<std::size_t, std::string> replacedFields;  //!< graph field index -> new payload
};

/** The input's Focus: four chains Slice(rows) -> Slice(columns) (either
 *  order) from the graph's only input, concatenated on the channels, and
 *  the input read by nothing else. */
std::optional<SpaceToDepth> foldInputSpaceToDepth(const Graph& g, Edits& edits)
{
	std::optional<std::size_t> inputField;
	std::string input;
	for (std::size_t i = 0; i < g.fields.size(); ++i)
	{
		if (g.fields[i].number != graph::input || g.fields[i].wireType != kLengthDelimited) continue;
		const auto name = stringsOf(parse(g.fields[i].value), value_info::name);
		if (name.empty() || g.initializers.count(name.front())) continue;  // old exports list weights as inputs
		if (inputField) return std::nullopt;                               // more than one input
		inputField = i;
		input = name.front();
	}
	if (!inputField) return std::nullopt;
	const auto first = g.consumers(input);
	if (first.size() != 4 || g.usesOf(input) != 4) return std::nullopt;

	SpaceToDepth s;
	std::set<std::pair<int, int>> offsets;
	std::optional<std::size_t> concat;
	std::vector<std::string> chainOutputs;
	std::set<std::size_t> chainNodes;
	for (const auto i : first)
	{
		const Node& a = g.nodes[i];
		const auto sa = strideTwoSlice(g, a);
		if (!sa || a.inputs[0] != input || g.usesOf(a.outputs[0]) != 1) return std::nullopt;
		const auto next = g.consumers(a.outputs[0]);
		if (next.size() != 1) return std::nullopt;
		const Node& b = g.nodes[next[0]];
		const auto sb = strideTwoSlice(g, b);
		if (!sb || sb->axis == sa->axis || b.inputs[0] != a.outputs[0] || g.usesOf(b.outputs[0]) != 1)
			return std::nullopt;
		const auto join = g.consumers(b.outputs[0]);
		if (join.size() != 1 || (concat && *concat != join[0])) return std::nullopt;
		concat = join[0];
		const int row = sa->axis == 2 ? sa->start : sb->start, col = sa->axis == 3 ? sa->start : sb->start;
		offsets.insert({row, col});
		chainNodes.insert({i, next[0]});
		chainOutputs.push_back(b.outputs[0]);
	}
	if (offsets.size() != 4) return std::nullopt;
	const Node& c = g.nodes[*concat];
	if (c.opType != "Concat" || c.inputs.size() != 4 || c.outputs.size() != 1) return std::nullopt;
	std::optional<std::int64_t> axis;
	for (const auto& f : c.message)
		if (f.number == node::attribute)
		{
			const Message attr = parse(f.value);
			const auto name = stringsOf(attr, attribute::name);
			const Field* i = firstOf(attr, attribute::i);
			if (!name.empty() && name.front() == "axis" && i) axis = varintOf(*i);
		}
	if (axis != 1 && axis != -3) return std::nullopt;
	for (const auto& in : c.inputs)
	{
		if (std::find(chainOutputs.begin(), chainOutputs.end(), in) == chainOutputs.end()) return std::nullopt;
		const Node& b = g.nodes[g.producer.at(in)];
		const Node& a = g.nodes[g.producer.at(b.inputs[0])];
		const auto sa = strideTwoSlice(g, a), sb = strideTwoSlice(g, b);
		s.groups.push_back({sa->axis == 2 ? sa->start : sb->start, sa->axis == 3 ? sa->start : sb->start});
	}
	// The graph's input is now the Concat's output: N x 4C x H/2 x W/2.
	auto info = TensorInfo::of(g.fields[*inputField].value);
	if (!info || info->dims.size() != 4 || info->dims[2] % 2 != 0 || info->dims[3] % 2 != 0) return std::nullopt;
	auto& d = info->dims;
	d = {d[0], 4 * d[1], d[2] / 2, d[3] / 2};
	edits.replacedFields[*inputField] = info->valueInfo(c.outputs[0]);
	for (const auto i : chainNodes) edits.droppedNodes.insert(i);
	edits.droppedNodes.insert(*concat);
	return s;
}

/** The integers of a node's attribute `name` (an INTS attribute). */
std::optional<std::vector<std::int64_t>> intsAttribute(const Node& n, const std::string& name)
{
	for (const auto& f : n.message)
	{
		if (f.number != node::attribute) continue;
		const Message attr = parse(f.value);
		const auto names = stringsOf(attr, attribute::name);
		if (names.empty() || names.front() != name) continue;
		std::vector<std::int64_t> values;
		for (const auto& v : attr)
		{
			if (v.number != attribute::ints) continue;
			if (v.wireType == kVarint)
				values.push_back(varintOf(v));
			else  // packed
				for (std::size_t at = 0; at < v.value.size();)
					values.push_back(static_cast<std::int64_t>(readVarint(v.value, at)));
		}
		return values;
	}
	return std::nullopt;
}

/** The graph's only output made by Transpose(x, perm = [0, 2, 1]) that
 *  nothing else reads: the graph ends at x instead. */
bool dropOutputTranspose(const Graph& g, Edits& edits)
{
	std::optional<std::size_t> outputField;
	for (std::size_t i = 0; i < g.fields.size(); ++i)
		if (g.fields[i].number == graph::output && g.fields[i].wireType == kLengthDelimited)
		{
			if (outputField) return false;  // more than one output
			outputField = i;
		}
	if (!outputField) return false;
	const auto name = stringsOf(parse(g.fields[*outputField].value), value_info::name);
	if (name.size() != 1 || g.usesOf(name.front()) != 1) return false;
	const auto p = g.producer.find(name.front());
	if (p == g.producer.end()) return false;
	const Node& t = g.nodes[p->second];
	if (t.opType != "Transpose" || t.inputs.size() != 1 || t.outputs.size() != 1 || g.usesOf(t.inputs[0]) != 1 ||
		!g.producer.count(t.inputs[0]))
		return false;
	if (intsAttribute(t, "perm") != std::vector<std::int64_t>{0, 2, 1}) return false;
	auto info = TensorInfo::of(g.fields[*outputField].value);
	if (!info || info->dims.size() != 3) return false;
	std::swap(info->dims[1], info->dims[2]);
	edits.replacedFields[*outputField] = info->valueInfo(t.inputs[0]);
	edits.droppedNodes.insert(p->second);
	return true;
}

/** Each Mul(x, Sigmoid(x)) whose sigmoid nothing else reads, as our Swish(x) layer. */
int fuseSwish(const Graph& g, Edits& edits)
{
	int fused = 0;
	for (const Node& mul : g.nodes)
	{
		if (mul.opType != "Mul" || mul.inputs.size() != 2) continue;
		for (const auto& [x, s] : {std::pair(mul.inputs[0], mul.inputs[1]), std::pair(mul.inputs[1], mul.inputs[0])})
		{
			const auto p = g.producer.find(s);
			if (p == g.producer.end() || g.usesOf(s) != 1) continue;
			const Node& sigmoid = g.nodes[p->second];
			if (sigmoid.opType != "Sigmoid" || sigmoid.inputs.size() != 1 || sigmoid.inputs[0] != x) continue;
			std::string swish = bytesField(node::input, x);
			for (const auto& f : mul.message)
				if (f.number == node::opType)
					swish += bytesField(node::opType, kSwishLayerType);
				else if (f.number != node::input)
					swish += encoded(f);
			edits.replacedFields[mul.field] = swish;
			edits.droppedNodes.insert(p->second);
			++fused;
			break;
		}
	}
	return fused;
}
}  // namespace

cv::Mat SpaceToDepth::apply(const cv::Mat& blob) const
{
	CV_Assert(blob.dims == 4 && blob.type() == CV_32F && blob.size[0] == 1 && blob.isContinuous());
	const int channels = blob.size[1], rows = blob.size[2], cols = blob.size[3];
	CV_Assert(rows % 2 == 0 && cols % 2 == 0);
	const int shape[4] = {1, int(groups.size()) * channels, rows / 2, cols / 2};
	cv::Mat out(4, shape, CV_32F);
	float* dst = out.ptr<float>();
	for (const auto& g : groups)
		for (int c = 0; c < channels; ++c)
		{
			const float* plane = blob.ptr<float>(0, c);
			for (int y = 0; y < rows / 2; ++y)
			{
				const float* src = plane + std::size_t(2 * y + g.row) * cols + g.col;
				for (int x = 0; x < cols / 2; ++x) *dst++ = src[2 * x];
			}
		}
	return out;
}

cv::Mat swapLastAxes(const cv::Mat& output)
{
	CV_Assert(output.dims == 3 && output.type() == CV_32F && output.isContinuous());
	const int planes = output.size[0], rows = output.size[1], cols = output.size[2];
	const int shape[3] = {planes, cols, rows};
	cv::Mat out(3, shape, CV_32F);
	for (int p = 0; p < planes; ++p)
	{
		const cv::Mat from(rows, cols, CV_32F, const_cast<float*>(output.ptr<float>(p)));
		cv::Mat to(cols, rows, CV_32F, out.ptr<float>(p));
		cv::transpose(from, to);
	}
	return out;
}

std::string DnnGraph::summary() const
{
	std::vector<std::string> parts;
	if (inputSpaceToDepth) parts.push_back("input space-to-depth before the network");
	if (swishActivations > 0)
		parts.push_back(std::to_string(swishActivations) +
						(swishActivations == 1 ? " Sigmoid-Mul pair" : " Sigmoid-Mul pairs") + " as Swish");
	if (outputTransposed) parts.push_back("output transposed after it");
	std::string s;
	for (const auto& part : parts) s += (s.empty() ? "" : ", ") + part;
	return s;
}

DnnGraph rewriteForDnn(std::string onnx)
{
	DnnGraph out;
	try
	{
		Message modelFields = parse(onnx);
		std::optional<std::size_t> graphField;
		for (std::size_t i = 0; i < modelFields.size(); ++i)
			if (modelFields[i].number == model::graph && modelFields[i].wireType == kLengthDelimited)
			{
				if (graphField) throw WireError("two graphs");
				graphField = i;
			}
		if (!graphField) throw WireError("no graph");
		const Graph g(modelFields[*graphField].value);
		Edits edits;
		out.inputSpaceToDepth = foldInputSpaceToDepth(g, edits);
		out.swishActivations = fuseSwish(g, edits);
		if (out.swishActivations > 0) registerSwishLayer();
		out.outputTransposed = dropOutputTranspose(g, edits);
		if (edits.replacedFields.empty() && edits.droppedNodes.empty())
		{
			out.onnx = std::move(onnx);
			return out;
		}
		std::set<std::size_t> droppedFields;
		for (const auto i : edits.droppedNodes) droppedFields.insert(g.nodes[i].field);
		std::string graphBytes;
		for (std::size_t i = 0; i < g.fields.size(); ++i)
		{
			if (droppedFields.count(i)) continue;
			const auto replaced = edits.replacedFields.find(i);
			graphBytes += replaced == edits.replacedFields.end() ? encoded(g.fields[i])
																 : bytesField(g.fields[i].number, replaced->second);
		}
		std::string rewritten;
		for (std::size_t i = 0; i < modelFields.size(); ++i)
			rewritten += i == *graphField ? bytesField(model::graph, graphBytes) : encoded(modelFields[i]);
		out.onnx = std::move(rewritten);
	}
	catch (const WireError&)
	{
		out = DnnGraph{};
		out.onnx = std::move(onnx);
	}
	return out;
}
}  // namespace avm::detection::detail
