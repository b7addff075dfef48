#include "avm/io/TumDataset.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "TextLines.h"
#include "avm/io/Trajectory.h"

namespace avm::io
{
namespace fs = std::filesystem;

namespace
{
bool readEntry(std::istream& ss, TumListEntry& e)
{
	return static_cast<bool>(ss >> e.timestamp >> e.file) && std::isfinite(e.timestamp);
}
}  // namespace

std::vector<TumListEntry> readTumFileList(const fs::path& file)
{
	std::vector<TumListEntry> out;
	detail::forEachDataLine(file,
		[&](std::istream& ss, std::size_t line)
		{
			TumListEntry e;
			if (!readEntry(ss, e)) detail::failAt(file, line, "expected 'timestamp filename'");
			if (!out.empty() && e.timestamp <= out.back().timestamp)
				detail::failAt(file, line, "timestamps out of order");
			out.push_back(std::move(e));
		});
	return out;
}

std::vector<RgbdPair> readAssociations(const fs::path& file)
{
	std::vector<RgbdPair> out;
	detail::forEachDataLine(file,
		[&](std::istream& ss, std::size_t line)
		{
			RgbdPair p;
			if (!readEntry(ss, p.rgb) || !readEntry(ss, p.depth))
				detail::failAt(file, line, "expected 't_rgb rgb_file t_depth depth_file'");
			if (!out.empty() && p.rgb.timestamp <= out.back().rgb.timestamp)
				detail::failAt(file, line, "timestamps out of order");
			out.push_back(std::move(p));
		});
	return out;
}

Association associateNearest(
	const std::vector<TumListEntry>& rgb, const std::vector<TumListEntry>& depth, double maxDifference)
{
	Association out;
	std::size_t next = 0;  // first depth entry not used yet; both lists are time-ordered
	for (const auto& c : rgb)
	{
		while (next + 1 < depth.size() &&
			   std::abs(depth[next + 1].timestamp - c.timestamp) <= std::abs(depth[next].timestamp - c.timestamp))
			++next;
		if (next >= depth.size() || std::abs(depth[next].timestamp - c.timestamp) > maxDifference)
		{
			std::ostringstream why;
			why << c.file << ": no unused depth frame within " << maxDifference << " s";
			out.skipped.push_back(why.str());
			continue;
		}
		out.pairs.push_back({c, depth[next]});
		++next;
	}
	return out;
}

std::vector<std::string> cameraPresetNames() { return {"bonn", "tum-fr1", "tum-fr2", "tum-fr3"}; }

RgbdCameraModel cameraPreset(const std::string& name)
{
	struct Preset
	{
		const char* name;
		double fx, fy, cx, cy;
		double dist[5];
	};
	// Published calibrations: Bonn RGB-D Dynamic; TUM RGB-D "Freiburg 1/2/3".
	static const Preset presets[] = {
		{"bonn", 542.822841, 542.576870, 315.593520, 237.756098, {0, 0, 0, 0, 0}},
		{"tum-fr1", 517.3, 516.5, 318.6, 255.3, {0.2624, -0.9531, -0.0054, 0.0026, 1.1633}},
		{"tum-fr2", 520.9, 521.0, 325.1, 249.7, {0.2312, -0.7849, -0.0033, -0.0001, 0.9172}},
		{"tum-fr3", 535.4, 539.2, 320.1, 247.6, {0, 0, 0, 0, 0}},
	};
	for (const auto& p : presets)
	{
		if (name != p.name) continue;
		RgbdCameraModel m;
		m.intrinsics.ncols = 640;
		m.intrinsics.nrows = 480;
		m.intrinsics.setIntrinsicParamsFromValues(p.fx, p.fy, p.cx, p.cy);
		for (int k = 0; k < 5; ++k) m.intrinsics.dist[k] = p.dist[k];
		m.depthFactor = 5000;
		return m;
	}
	std::string names;
	for (const auto& n : cameraPresetNames()) names += (names.empty() ? "" : ", ") + n;
	throw std::runtime_error("unknown camera preset '" + name + "' (known: " + names + ")");
}

mrpt::poses::CPose3D groundTruthBodyToCamera(const std::string& presetOrFile)
{
	if (presetOrFile == "none") return {};
	if (presetOrFile == "bonn")
	{
		// T_ros * T_m from the Bonn RGB-D Dynamic dataset page.
		static const double T_ros_T_m[16] = {-1.0157, -0.1828, 0.2389, -0.0113,  //
			-0.3009, 0.6147, -0.8085, 0.0111,                                    //
			0.0009, -0.8431, -0.6413, -0.0098,                                   //
			0, 0, 0, 1};
		return rigidTransformFromMatrix(T_ros_T_m);
	}
	if (!fs::exists(presetOrFile))
		throw std::runtime_error(
			"ground-truth body transform '" + presetOrFile + "' is neither a preset (bonn, none) nor an existing file");
	return readRigidTransformFile(presetOrFile);
}
}  // namespace avm::io
