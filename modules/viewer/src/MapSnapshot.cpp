#include "avm/viewer/MapSnapshot.h"

#include <mrpt/containers/yaml.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <array>
#include <sstream>
#include <stdexcept>

#include "avm/io/RunFolder.h"
#include "avm/io/Trajectory.h"
#include "avm/plugin/CAdaptiveOctoMap.h"
#include "avm/maps/OcTreeFile.h"
#include "avm/maps/VisibleLeaves.h"
#include "avm/persons/PersonShapesPly.h"
#include "avm/persons/PersonsCsv.h"

namespace avm::viewer
{
namespace
{
SnapshotVoxel voxelOf(const mrpt::math::TPoint3D& c, double size)
{
	return {mrpt::math::TPoint3Df(static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z)),
		static_cast<float>(size)};
}

/** A leaf visitor that keeps the occupied leaves, and the free ones if `freeSpace`. */
std::function<void(const TLeafVoxel&)> collector(
	std::vector<SnapshotVoxel>& occupied, std::vector<SnapshotVoxel>& free, bool freeSpace)
{
	return [&occupied, &free, freeSpace](const TLeafVoxel& v)
	{
		if (v.occupied)
			occupied.push_back(voxelOf(v.center, v.size));
		else if (freeSpace)
			free.push_back(voxelOf(v.center, v.size));
	};
}

mrpt::math::TPoint3D pointOf(const mrpt::containers::yaml& xyz)
{
	return {xyz(0).as<double>(), xyz(1).as<double>(), xyz(2).as<double>()};
}

/** "regions" of stats.json: [{"person": N, "boxes": [{"min": [x,y,z], "max": [x,y,z]}, …]}, …]. */
std::vector<SnapshotRegion> readRegions(const mrpt::containers::yaml& stats)
{
	std::vector<SnapshotRegion> regions;
	if (!stats.has("regions")) return regions;
	const auto& array = stats["regions"];
	for (std::size_t i = 0; i < array.size(); ++i)
	{
		const auto& region = array(i);
		SnapshotRegion r;
		r.personId = region["person"].as<std::uint32_t>();
		const auto& boxes = region["boxes"];
		for (std::size_t b = 0; b < boxes.size(); ++b)
			r.boxes.emplace_back(pointOf(boxes(b)["min"]), pointOf(boxes(b)["max"]));
		regions.push_back(std::move(r));
	}
	return regions;
}
}  // namespace

MapSnapshot snapshotOf(const CAdaptiveOctoMap& map, const SnapshotOptions& options)
{
	MapSnapshot s;
	s.lowResolution = map.creationOptions().low.resolution;
	s.highResolution = map.creationOptions().high.resolution;
	s.hasFreeSpace = options.freeSpace;
	map.forEachLeaf(Resolution::Low, collector(s.lowOccupied, s.lowFree, options.freeSpace));
	map.forEachLeaf(Resolution::High, collector(s.highOccupied, s.highFree, options.freeSpace));
	for (const auto& r : map.highResolutionRegions()) s.regions.push_back({r.regionId, r.boxes});
	for (const auto& t : map.confirmedPersons()) s.persons.push_back({t.id, t.position, t.lastFrame, t.shape});
	for (const auto which : {Resolution::Low, Resolution::High})
		if (const auto* t = map.tree(which)) s.mapMemoryBytes += t->memoryUsage();
	s.status.switchInsertion = map.switchInsertionIndex();
	return s;
}

MapSnapshot snapshotOfTrees(const octomap::OcTree& low, const octomap::OcTree* high, const SnapshotOptions& options)
{
	MapSnapshot s;
	s.lowResolution = low.getResolution();
	s.highResolution = high ? high->getResolution() : 0;
	s.hasFreeSpace = options.freeSpace;
	forEachVisibleLeaf(low, nullptr, collector(s.lowOccupied, s.lowFree, options.freeSpace));
	// Whatever the policy was: a region-policy low tree has no node in region space.
	if (high) forEachVisibleLeaf(*high, &low, collector(s.highOccupied, s.highFree, options.freeSpace));
	s.mapMemoryBytes = low.memoryUsage() + (high ? high->memoryUsage() : 0);
	return s;
}

MapSnapshot snapshotOfRun(const std::filesystem::path& outDir, const SnapshotOptions& options)
{
	const io::RunFolder run(outDir);
	const auto lowFile = run.map().lowTree, highFile = run.map().highTree;
	if (!std::filesystem::exists(lowFile))
		throw std::runtime_error(lowFile.string() + ": not found (not an avm-map output folder?)");
	const auto low = readBinaryTree(lowFile);
	std::unique_ptr<octomap::OcTree> high;
	if (std::filesystem::exists(highFile)) high = readBinaryTree(highFile);
	MapSnapshot s = snapshotOfTrees(*low, high.get(), options);

	if (const auto f = run.trajectory(); std::filesystem::exists(f))
	{
		for (const auto& p : io::readTumTrajectory(f)) s.trajectory.push_back(p.pose);
		if (!s.trajectory.empty()) s.camera = s.trajectory.back();
		s.status.frame = s.trajectory.empty() ? std::nullopt : std::optional<std::size_t>(s.trajectory.size() - 1);
		s.status.frames = s.trajectory.size();
	}
	if (const auto f = run.persons(); std::filesystem::exists(f))
		for (const auto& t : persons::readPersonsCsv(f)) s.persons.push_back({t.id, t.position, t.lastFrame, t.shape});
	if (const auto f = run.personShapes(); std::filesystem::exists(f))
		for (auto& shape : persons::readPersonShapesPly(f))
		{
			const auto person = std::find_if(
				s.persons.begin(), s.persons.end(), [&](const SnapshotPerson& p) { return p.id == shape.id; });
			if (person == s.persons.end())
				throw std::runtime_error(
					f.string() + ": person " + std::to_string(shape.id) + " is not in " + run.persons().string());
			person->shape = std::move(shape.points);
			person->shapeColour = shape.colour;
		}
	if (const auto f = run.stats(); std::filesystem::exists(f))
	{
		try
		{
			const auto stats = mrpt::containers::yaml::FromFile(f.string());
			s.regions = readRegions(stats);
			if (stats.has("switch_frame") && !stats["switch_frame"].isNullNode())
				s.status.switchFrame = stats["switch_frame"].as<std::size_t>();
		}
		catch (const std::exception& e)
		{
			throw std::runtime_error(f.string() + ": not a stats.json of avm-map: " + e.what());
		}
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
	if (st.switchFrame)
		t << "switch at frame " << *st.switchFrame;
	else if (st.switchInsertion)
		t << "switch at insertion " << *st.switchInsertion;
	else
		t << "switch not yet";
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
