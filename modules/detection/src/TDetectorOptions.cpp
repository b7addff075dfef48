#include "avm/detection/TDetectorOptions.h"

#include <mrpt/config/CConfigFileBase.h>

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "avm/detection/CocoClasses.h"
#include "avm/io/EnumNames.h"
#include "avm/io/ErrorMessage.h"
#include "avm/io/IniKeys.h"

namespace avm::detection
{
namespace
{
std::string trim(const std::string& s)
{
	const auto b = s.find_first_not_of(" \t\r\n");
	if (b == std::string::npos) return {};
	const auto e = s.find_last_not_of(" \t\r\n");
	return s.substr(b, e - b + 1);
}

/** `"x"` -> `x`, so that `model = ""` can say "no model". */
std::string unquote(const std::string& s)
{
	return s.size() >= 2 && s.front() == '"' && s.back() == '"' ? s.substr(1, s.size() - 2) : s;
}
}  // namespace

namespace
{
const io::EnumNames<OutputLayout>& outputLayoutNames()
{
	static const io::EnumNames<OutputLayout> names(
		"output layout", {{OutputLayout::Auto, "auto"}, {OutputLayout::Yolox, "yolox"},
							 {OutputLayout::Yolov5, "yolov5"}, {OutputLayout::Yolov8, "yolov8"}});
	return names;
}
}  // namespace

std::string toString(OutputLayout layout) { return outputLayoutNames().name(layout); }

OutputLayout parseOutputLayout(const std::string& name) { return outputLayoutNames().parse(trim(name)); }

io::IniKeys<TDetectorOptions> TDetectorOptions::iniKeys()
{
	using O = TDetectorOptions;
	const auto inUnit = [](bool open)
	{
		return io::IniRule<double>{[open](double v) { return v >= 0 && v <= 1 && (!open || v > 0); },
			open ? "must be in (0, 1]" : "must be in [0, 1]"};
	};
	// The YOLO grids have stride 32.
	const io::IniRule<int> stride32{[](int v) { return v >= 32 && v % 32 == 0; }, "must be a positive multiple of 32"};
	io::IniKeys<O> keys;
	keys.text("model", &O::model, "ONNX model file, relative to the project root; \"\" = OpenCV's HOG people detector",
			{}, [](const std::string& v) { return unquote(trim(v)); })
		.choice(
			"layout", &O::layout, parseOutputLayout, [](OutputLayout l) { return toString(l); },
			"auto | yolox (1xNx85 raw grid) | yolov5 (1xNx85) | yolov8 (1x84xN)")
		.text("classes", &O::classes, "COCO class names to keep, comma separated")
		.number(
			"score_threshold", &O::score_threshold, "0..1", "minimum score (YOLOX: objectness x class)", inUnit(false))
		.number("nms_threshold", &O::nms_threshold, "0..1", "IoU above which the weaker box of a class is dropped",
			inUnit(true))
		.number("input_width", &O::input_width, "px", "network input, a multiple of 32", stride32)
		.number("input_height", &O::input_height, "px", "network input, a multiple of 32", stride32)
		.number("threads", &O::threads, "", "OpenCV threads for the whole run; 0 = OpenCV default",
			{[](int v) { return v >= 0; }, "must be >= 0 (0 = OpenCV default)"})
		.number("hog_hit_threshold", &O::hog_hit_threshold, "", "HOG only: SVM margin a window needs",
			{[](double v) { return std::isfinite(v); }, "must be finite"})
		.number("simplify_graph", &O::simplify_graph, "",
			"run the model's input space-to-depth (Focus) on the input blob and its Sigmoid-Mul pairs as Swish "
			"layers: the same network, faster in cv::dnn");
	return keys;
}

void TDetectorOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
	iniKeys().load(*this, c, s);
	classIds(s);
}

void TDetectorOptions::validate(const std::string& s) const
{
	iniKeys().validate(*this, s);
	classIds(s);
}

std::vector<int> TDetectorOptions::classIds(const std::string& s) const
{
	std::vector<int> ids;
	std::istringstream list(classes);
	for (std::string name; std::getline(list, name, ',');)
	{
		name = trim(name);
		if (name.empty()) continue;
		const auto id = cocoClassId(name);
		if (!id) throw io::iniValueError(s, "classes", classes, "'" + name + "' is not a COCO class name");
		ids.push_back(*id);
	}
	if (ids.empty()) throw io::iniValueError(s, "classes", classes, "needs at least one COCO class name (e.g. person)");
	return ids;
}

std::filesystem::path resolveModelPath(const std::string& model, const std::filesystem::path& root)
{
	if (model.empty()) return {};
	const std::filesystem::path p(model);
	return p.is_absolute() || root.empty() ? p : root / p;
}
}  // namespace avm::detection

template struct avm::io::CIniKeyOptions<avm::detection::TDetectorOptions>;
