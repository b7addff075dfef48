#include "avm/detection/TDetectorOptions.h"

#include <mrpt/config/CConfigFileBase.h>

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "avm/detection/CocoClasses.h"

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

[[noreturn]] void badKey(const std::string& section, const std::string& key, const std::string& value, const std::string& why)
{
	throw std::invalid_argument("[" + section + "] " + key + " = " + value + ": " + why);
}

template <typename T>
std::string str(const T& v)
{
	std::ostringstream s;
	s << v;
	return s.str();
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
		badKey(s, "layout", layoutName, e.what());
	}
	classes = c.read_string(s, "classes", classes);
	score_threshold = c.read_double(s, "score_threshold", score_threshold);
	nms_threshold = c.read_double(s, "nms_threshold", nms_threshold);
	input_width = c.read_int(s, "input_width", input_width);
	input_height = c.read_int(s, "input_height", input_height);
	threads = c.read_int(s, "threads", threads);
	hog_hit_threshold = c.read_double(s, "hog_hit_threshold", hog_hit_threshold);
	region_margin = c.read_double(s, "region_margin", region_margin);
	person_depth_band = c.read_double(s, "person_depth_band", person_depth_band);
	min_valid_depth_fraction = c.read_double(s, "min_valid_depth_fraction", min_valid_depth_fraction);
	min_region_points = c.read_int(s, "min_region_points", min_region_points);
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
	c.write(s, "region_margin", region_margin);
	c.write(s, "person_depth_band", person_depth_band);
	c.write(s, "min_valid_depth_fraction", min_valid_depth_fraction);
	c.write(s, "min_region_points", min_region_points);
}

void TDetectorOptions::validate(const std::string& s) const
{
	auto inUnit = [&](const char* key, double v, bool open) {
		if (!std::isfinite(v) || v < 0 || v > 1 || (open && v == 0))
			badKey(s, key, str(v), open ? "must be in (0, 1]" : "must be in [0, 1]");
	};
	inUnit("score_threshold", score_threshold, false);
	inUnit("nms_threshold", nms_threshold, true);
	inUnit("min_valid_depth_fraction", min_valid_depth_fraction, false);
	// The YOLO grids have stride 32.
	if (input_width < 32 || input_width % 32) badKey(s, "input_width", str(input_width), "must be a positive multiple of 32");
	if (input_height < 32 || input_height % 32) badKey(s, "input_height", str(input_height), "must be a positive multiple of 32");
	if (threads < 0) badKey(s, "threads", str(threads), "must be >= 0 (0 = OpenCV default)");
	if (!std::isfinite(hog_hit_threshold)) badKey(s, "hog_hit_threshold", str(hog_hit_threshold), "must be finite");
	if (!std::isfinite(region_margin) || region_margin < 0) badKey(s, "region_margin", str(region_margin), "must be >= 0 [m]");
	if (!std::isfinite(person_depth_band) || person_depth_band <= 0)
		badKey(s, "person_depth_band", str(person_depth_band), "must be > 0 [m]");
	if (min_region_points < 1) badKey(s, "min_region_points", str(min_region_points), "must be >= 1");
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
		if (!id) badKey(s, "classes", classes, "'" + name + "' is not a COCO class name");
		ids.push_back(*id);
	}
	if (ids.empty()) badKey(s, "classes", classes, "needs at least one COCO class name (e.g. person)");
	return ids;
}

std::filesystem::path resolveModelPath(const std::string& model, const std::filesystem::path& root)
{
	if (model.empty()) return {};
	const std::filesystem::path p(model);
	return p.is_absolute() || root.empty() ? p : root / p;
}
}  // namespace avm::detection
