#include "avm/viewer/MapSnapshot.h"

#include <octomap/OcTree.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "avm/io/Trajectory.h"
#include "avm/maps/CAdaptiveOctoMap.h"

namespace avm::viewer
{
namespace
{
SnapshotVoxel voxelOf(const mrpt::math::TPoint3D& c, double size)
{
	return {mrpt::math::TPoint3Df(static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z)),
		static_cast<float>(size)};
}

std::string readText(const std::filesystem::path& file)
{
	std::ifstream in(file);
	if (!in) throw std::runtime_error(file.string() + ": cannot read");
	std::stringstream s;
	s << in.rdbuf();
	return s.str();
}

/** persons.csv as avm-map writes it: id, first_frame, last_frame, first_time,
 *  last_time, x, y, z, box…, detections. */
std::vector<SnapshotPerson> readPersonsCsv(const std::filesystem::path& file)
{
	std::vector<SnapshotPerson> persons;
	std::istringstream text(readText(file));
	std::string line;
	std::size_t lineNo = 0;
	while (std::getline(text, line))
	{
		++lineNo;
		if (lineNo == 1 || line.empty()) continue;	// header
		std::vector<std::string> f;
		std::stringstream cells(line);
		for (std::string c; std::getline(cells, c, ',');) f.push_back(c);
		try
		{
			if (f.size() < 8) throw std::invalid_argument("too few columns");
			SnapshotPerson p;
			p.id = static_cast<std::uint32_t>(std::stoul(f[0]));
			p.lastFrame = std::stoul(f[2]);
			p.position = {std::stod(f[5]), std::stod(f[6]), std::stod(f[7])};
			persons.push_back(p);
		}
		catch (const std::exception&)
		{
			throw std::runtime_error(file.string() + ":" + std::to_string(lineNo) + ": not a persons.csv line");
		}
	}
	return persons;
}

/** The part of `json` between the '[' after "key": and its matching ']'. */
std::optional<std::string> jsonArray(const std::string& json, const std::string& key)
{
	const auto at = json.find("\"" + key + "\"");
	if (at == std::string::npos) return std::nullopt;
	const auto open = json.find('[', at);
	if (open == std::string::npos) return std::nullopt;
	int depth = 0;
	for (std::size_t i = open; i < json.size(); ++i)
	{
		if (json[i] == '[') ++depth;
		else if (json[i] == ']' && --depth == 0) return json.substr(open + 1, i - open - 1);
	}
	return std::nullopt;
}

/** "regions" of stats.json: [{"person": N, "boxes": [{"min": [x,y,z], "max": [x,y,z]}, …]}, …]. */
std::vector<SnapshotRegion> readRegions(const std::string& json)
{
	std::vector<SnapshotRegion> regions;
	const auto array = jsonArray(json, "regions");
	if (!array) return regions;
	const std::string num = R"(\s*(-?[0-9.eE+-]+)\s*)";
	const std::regex person(R"("person"\s*:\s*([0-9]+))");
	const std::regex box(R"("min"\s*:\s*\[)" + num + "," + num + "," + num + R"(\]\s*,\s*"max"\s*:\s*\[)" + num +
		"," + num + "," + num + R"(\])");
	std::vector<std::pair<std::size_t, std::uint32_t>> starts;
	for (std::sregex_iterator it(array->begin(), array->end(), person), end; it != end; ++it)
		starts.emplace_back(it->position(), static_cast<std::uint32_t>(std::stoul((*it)[1])));
	for (std::size_t i = 0; i < starts.size(); ++i)
	{
		const auto from = starts[i].first, to = i + 1 < starts.size() ? starts[i + 1].first : array->size();
		const std::string part = array->substr(from, to - from);
		SnapshotRegion r;
		r.personId = starts[i].second;
		for (std::sregex_iterator it(part.begin(), part.end(), box), end; it != end; ++it)
		{
			const auto& m = *it;
			r.boxes.emplace_back(mrpt::math::TPoint3D(std::stod(m[1]), std::stod(m[2]), std::stod(m[3])),
				mrpt::math::TPoint3D(std::stod(m[4]), std::stod(m[5]), std::stod(m[6])));
		}
		regions.push_back(std::move(r));
	}
	return regions;
}

std::optional<std::size_t> readSwitchFrame(const std::string& json)
{
	std::smatch m;
	if (std::regex_search(json, m, std::regex(R"("switch_frame"\s*:\s*([0-9]+))"))) return std::stoul(m[1]);
	return std::nullopt;
}
}  // namespace

MapSnapshot snapshotOf(const CAdaptiveOctoMap& map, const SnapshotOptions& options)
{
	MapSnapshot s;
	s.lowResolution = map.creationOptions().low.resolution;
	s.highResolution = map.creationOptions().high.resolution;
	s.hasFreeSpace = options.freeSpace;
	const auto take = [&](Resolution which, std::vector<SnapshotVoxel>& occupied, std::vector<SnapshotVoxel>& free) {
		map.forEachLeaf(which, [&](const TLeafVoxel& v) {
			if (v.occupied) occupied.push_back(voxelOf(v.center, v.size));
			else if (options.freeSpace) free.push_back(voxelOf(v.center, v.size));
		});
	};
	take(Resolution::Low, s.lowOccupied, s.lowFree);
	take(Resolution::High, s.highOccupied, s.highFree);
	for (const auto& r : map.highResolutionRegions()) s.regions.push_back({r.personId, r.boxes});
	for (const auto& t : map.personTracks()) s.persons.push_back({t.id, t.position, t.lastFrame});
	for (const auto which : {Resolution::Low, Resolution::High})
		if (const auto* t = map.tree(which)) s.mapMemoryBytes += t->memoryUsage();
	if (const auto i = map.switchInsertionIndex()) s.status.switchFrame = *i;
	return s;
}

MapSnapshot snapshotOfTrees(const octomap::OcTree& low, const octomap::OcTree* high, const SnapshotOptions& options)
{
	MapSnapshot s;
	s.lowResolution = low.getResolution();
	s.highResolution = high ? high->getResolution() : 0;
	s.hasFreeSpace = options.freeSpace;
	const auto take = [&](const octomap::OcTree& t, bool isHigh, std::vector<SnapshotVoxel>& occupied,
						  std::vector<SnapshotVoxel>& free) {
		if (t.size() == 0) return;
		for (auto it = t.begin_leafs(), end = t.end_leafs(); it != end; ++it)
		{
			const auto c = it.getCoordinate();
			if (isHigh && low.search(c) != nullptr) continue;  // the overlap filter
			const bool occ = t.isNodeOccupied(*it);
			if (occ) occupied.push_back(voxelOf({c.x(), c.y(), c.z()}, it.getSize()));
			else if (options.freeSpace) free.push_back(voxelOf({c.x(), c.y(), c.z()}, it.getSize()));
		}
	};
	take(low, false, s.lowOccupied, s.lowFree);
	if (high) take(*high, true, s.highOccupied, s.highFree);
	s.mapMemoryBytes = low.memoryUsage() + (high ? high->memoryUsage() : 0);
	return s;
}

MapSnapshot snapshotOfRun(const std::filesystem::path& outDir, const SnapshotOptions& options)
{
	const auto lowFile = outDir / "map_low.bt", highFile = outDir / "map_high.bt";
	if (!std::filesystem::exists(lowFile))
		throw std::runtime_error(lowFile.string() + ": not found (not an avm-map output folder?)");
	const auto load = [](const std::filesystem::path& f) {
		auto t = std::make_unique<octomap::OcTree>(0.1);
		if (!t->readBinary(f.string())) throw std::runtime_error(f.string() + ": not an octomap .bt file");
		return t;
	};
	const auto low = load(lowFile);
	std::unique_ptr<octomap::OcTree> high;
	if (std::filesystem::exists(highFile)) high = load(highFile);
	MapSnapshot s = snapshotOfTrees(*low, high.get(), options);

	if (const auto f = outDir / "trajectory.txt"; std::filesystem::exists(f))
	{
		for (const auto& p : io::readTumTrajectory(f)) s.trajectory.push_back(p.pose);
		if (!s.trajectory.empty()) s.camera = s.trajectory.back();
		s.status.frame = s.trajectory.empty() ? std::nullopt : std::optional<std::size_t>(s.trajectory.size() - 1);
		s.status.frames = s.trajectory.size();
	}
	if (const auto f = outDir / "persons.csv"; std::filesystem::exists(f)) s.persons = readPersonsCsv(f);
	if (const auto f = outDir / "stats.json"; std::filesystem::exists(f))
	{
		const auto json = readText(f);
		s.regions = readRegions(json);
		s.status.switchFrame = readSwitchFrame(json);
	}
	s.status.note = outDir.filename().string();
	return s;
}

std::string statusLine(const MapSnapshot& s)
{
	const auto lines = statusLines(s);
	return lines[0].empty() ? lines[1] : lines[0] + "  " + lines[1];
}

std::array<std::string, 2> statusLines(const MapSnapshot& s)
{
	std::ostringstream t;
	t.setf(std::ios::fixed);
	t.precision(1);
	const auto& st = s.status;
	if (st.frame)
	{
		t << "frame " << *st.frame;
		if (st.frames) t << "/" << st.frames;
	}
	if (st.fps > 0) t << "  " << st.fps << " fps";
	for (const auto& [name, ms] : st.stageMs) t << "  " << name << " " << ms << " ms";
	std::array<std::string, 2> lines{t.str(), {}};
	t.str("");
	t << "switch " << (st.switchFrame ? "at " + std::to_string(*st.switchFrame) : std::string("not yet"));
	t << "  persons " << s.persons.size() << "  regions " << s.regions.size();
	t.precision(2);
	t << "  map " << double(s.mapMemoryBytes) / (1024.0 * 1024.0) << " MB";
	t << "  voxels " << s.lowOccupied.size() << " low " << s.highOccupied.size() << " high";
	if (!st.note.empty()) lines[0] += "  " + st.note;
	lines[1] = t.str();
	const auto trim = [](std::string& x) { x.erase(0, x.find_first_not_of(' ')); };
	trim(lines[0]);
	return lines;
}
}  // namespace avm::viewer
