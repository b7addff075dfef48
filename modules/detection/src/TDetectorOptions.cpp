#include "avm/detection/TDetectorOptions.h"

#include <mrpt/config/CConfigFileBase.h>

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "avm/detection/CocoClasses.h"
#include "avm/io/ErrorMessage.h"
#include "avm/io/IniOptions.h"

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

std::string toString(OutputLayout layout)
{
	switch (layout)
	{
		case OutputLayout::Auto: return "auto";
		case OutputLayout::Yolox: return "yolox";
		case OutputLayout::Yolov5: return "yolov5";
		case OutputLayout::Yolov8: return "yolov8";
	}
	return "auto";
}

OutputLayout parseOutputLayout(const std::string& name)
{
	for (auto l : {OutputLayout::Auto, OutputLayout::Yolox, OutputLayout::Yolov5, OutputLayout::Yolov8})
		if (toString(l) == trim(name)) return l;
	throw std::invalid_argument("unknown output layout '" + name + "' (auto, yolox, yolov5, yolov8)");
}

void TDetectorOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
	model = unquote(trim(c.read_string(s, "model", model)));
	const std::string layoutName = c.read_string(s, "layout", toString(layout));
	try
	{
		layout = parseOutputLayout(layoutName);
	}
	catch (const std::invalid_argument& e)
	{
		throw io::iniValueError(s, "layout", layoutName, e.what());
	}
	classes = c.read_string(s, "classes", classes);
	// io's readers: "abc" is "not a number", not a 0 that validate() reports.
	const auto read = [&](const char* key, auto def) { return io::readIniValue(c, s, key, def); };
	score_threshold = read("score_threshold", score_threshold);
	nms_threshold = read("nms_threshold", nms_threshold);
	input_width = read("input_width", input_width);
	input_height = read("input_height", input_height);
	threads = read("threads", threads);
	hog_hit_threshold = read("hog_hit_threshold", hog_hit_threshold);
	validate(s);
}

void TDetectorOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
	c.write(s, "model", model);
	c.write(s, "layout", toString(layout));
	c.write(s, "classes", classes);
	c.write(s, "score_threshold", score_threshold);
	c.write(s, "nms_threshold", nms_threshold);
	c.write(s, "input_width", input_width);
	c.write(s, "input_height", input_height);
	c.write(s, "threads", threads);
	c.write(s, "hog_hit_threshold", hog_hit_threshold);
}

void TDetectorOptions::validate(const std::string& s) const
{
	auto inUnit = [&](const char* key, double v, bool open) {
		if (!std::isfinite(v) || v < 0 || v > 1 || (open && v == 0))
			throw io::iniValueError(s, key, v, open ? "must be in (0, 1]" : "must be in [0, 1]");
	};
	inUnit("score_threshold", score_threshold, false);
	inUnit("nms_threshold", nms_threshold, true);
	// The YOLO grids have stride 32.
	if (input_width < 32 || input_width % 32) throw io::iniValueError(s, "input_width", input_width, "must be a positive multiple of 32");
	if (input_height < 32 || input_height % 32) throw io::iniValueError(s, "input_height", input_height, "must be a positive multiple of 32");
	if (threads < 0) throw io::iniValueError(s, "threads", threads, "must be >= 0 (0 = OpenCV default)");
	if (!std::isfinite(hog_hit_threshold)) throw io::iniValueError(s, "hog_hit_threshold", hog_hit_threshold, "must be finite");
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
