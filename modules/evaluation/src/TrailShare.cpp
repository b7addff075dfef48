#include "avm/evaluation/TrailShare.h"

#include <mrpt/poses/CPose3D.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "avm/io/DepthCamera.h"
#include "avm/io/RawlogFrameReader.h"
#include "avm/io/RunFolder.h"
#include "avm/maps/OcTreeFile.h"
#include "avm/persons/PersonBand.h"
#include "avm/persons/PersonLabels.h"

namespace avm::evaluation
{
std::vector<std::uint8_t> personPixelMask(const mrpt::obs::CObservation3DRangeScan& obs, const std::string& label)
{
	std::vector<std::uint8_t> mask;
	for (const auto& l : persons::readPersonLabels(obs, label))
		for (const auto i : l.pixels)
		{
			if (mask.empty()) mask.assign(static_cast<std::size_t>(obs.rangeImage.rows()) * obs.rangeImage.cols(), 0);
			if (i < mask.size()) mask[i] = 1;
		}
	return mask;
}

std::string describe(Yardstick yardstick)
{
	return yardstick == Yardstick::Boxes ? "whole person boxes" : "the persons' own pixels (depth band)";
}

PersonCuts personCuts(
	const mrpt::obs::CObservation3DRangeScan& obs, const mrpt::poses::CPose3D& sensorPoseInWorld, const TrailOptions& o)
{
	PersonCuts cuts;
	cuts.boxes = personPixelMask(obs, o.personLabel);
	cuts.personMask = cuts.boxes;
	if (cuts.boxes.empty()) return cuts;
	// A pixel is background only where some sighted person's pixels hold it
	// and no sighted person's band does.
	constexpr std::uint8_t kBackground = 1, kPerson = 2;
	std::vector<std::uint8_t> claims(cuts.boxes.size(), 0);
	for (const auto& pixels : persons::personPixelsFromLabels(obs, o.personLabel, o.sighting.minPixels))
	{
		const auto est = persons::estimateSighting(obs, sensorPoseInWorld, pixels, o.sighting);
		if (!est.sighting) continue;
		for (const auto i : pixels) claims[i] |= kBackground;
		for (const auto i : persons::personBandPixels(obs, pixels, *est.sighting, o.sighting)) claims[i] |= kPerson;
	}
	for (std::size_t i = 0; i < claims.size(); ++i)
		if (claims[i] == kBackground) cuts.personMask[i] = 0;
	return cuts;
}

TrailRow& TrailRow::operator+=(const TrailRow& other)
{
	occupiedM3 += other.occupiedM3;
	for (std::size_t y = 0; y < trailM3.size(); ++y)
	{
		trailM3[y] += other.trailM3[y];
		trailNoFineSurfaceM3[y] += other.trailNoFineSurfaceM3[y];
	}
	return *this;
}

TrailReference::TrailReference(double resolution, double maxRange)
	: m_single(std::make_unique<octomap::OcTree>(resolution)), m_maxRange(maxRange)
{
	for (auto& r : m_references) r = std::make_unique<octomap::OcTree>(resolution);
}

TrailReference::~TrailReference() = default;

namespace
{
std::size_t cutDepthPixels(const mrpt::obs::CObservation3DRangeScan& obs, const std::vector<std::uint8_t>& cut)
{
	std::size_t n = 0;
	const auto cols = static_cast<std::size_t>(obs.rangeImage.cols());
	for (std::size_t i = 0; i < cut.size(); ++i) n += cut[i] && obs.rangeImage(i / cols, i % cols) != 0;
	return n;
}
}  // namespace

void TrailReference::insert(
	const mrpt::obs::CObservation3DRangeScan& obs, const mrpt::poses::CPose3D& robotPose, const PersonCuts& cuts)
{
	const auto camera = io::DepthCamera::of(obs);
	const mrpt::poses::CPose3D sensor = robotPose + obs.sensorPose;
	const auto o = sensor.translation();
	const octomap::point3d origin(o.x, o.y, o.z);
	octomap::Pointcloud all;
	std::array<octomap::Pointcloud, static_cast<std::size_t>(Yardstick::Count)> kept;
	for (int v = 0; v < camera.height; v++)
		for (int u = 0; u < camera.width; u++)
		{
			const std::uint16_t raw = obs.rangeImage(v, u);
			if (raw == 0) continue;
			const auto p = sensor.composePoint(camera.unproject(u, v, raw * obs.rangeUnits));
			const octomap::point3d q(p.x, p.y, p.z);
			all.push_back(q);
			const auto i = static_cast<std::size_t>(v) * camera.width + u;
			for (std::size_t y = 0; y < kept.size(); ++y)
			{
				const auto& cut = cuts.of(static_cast<Yardstick>(y));
				if (cut.empty() || !cut[i]) kept[y].push_back(q);
			}
		}
	m_single->insertPointCloud(all, origin, m_maxRange, false, true);
	for (std::size_t y = 0; y < kept.size(); ++y)
		m_references[y]->insertPointCloud(kept[y], origin, m_maxRange, false, true);
}

namespace
{
/** Whether `tree` holds an occupied leaf inside the cube of edge `size`
 *  centred at `c` (its faces excluded). */
bool occupiedInside(const octomap::OcTree& tree, const octomap::point3d& c, double size)
{
	const float h = static_cast<float>(size / 2 - tree.getResolution() / 4);
	const octomap::point3d lo(c.x() - h, c.y() - h, c.z() - h), hi(c.x() + h, c.y() + h, c.z() + h);
	for (auto it = tree.begin_leafs_bbx(lo, hi), end = tree.end_leafs_bbx(); it != end; ++it)
		if (tree.isNodeOccupied(*it)) return true;
	return false;
}
}  // namespace

TrailRow TrailReference::judge(const octomap::OcTree& map, const std::string& name, const TrailReference* finer) const
{
	const double resolution = m_single->getResolution();
	if (std::abs(map.getResolution() - resolution) > 1e-9)
		throw std::invalid_argument(name + ": resolution " + std::to_string(map.getResolution()) +
									" m, the reference is at " + std::to_string(resolution) + " m");
	TrailRow row;
	row.map = name;
	for (auto it = map.begin_leafs(), end = map.end_leafs(); it != end; ++it)
	{
		if (!map.isNodeOccupied(*it)) continue;
		const double size = it.getSize(), volume = size * size * size;
		row.occupiedM3 += volume;
		for (std::size_t y = 0; y < m_references.size(); ++y)
		{
			const auto* ref = m_references[y]->search(it.getKey(), it.getDepth());
			if (!ref || m_references[y]->isNodeOccupied(ref)) continue;
			row.trailM3[y] += volume;
			if (!finer || !occupiedInside(finer->reference(static_cast<Yardstick>(y)), it.getCoordinate(), size))
				row.trailNoFineSurfaceM3[y] += volume;
		}
	}
	return row;
}

TrailResult measureTrails(const TrailOptions& options,
	const std::function<void(std::size_t done, std::size_t total)>& progress,
	const std::function<void(const TrailReference& high, const TrailReference& low)>& inspect)
{
	TrailReference high(options.highResolution, options.maxRange), low(options.lowResolution, options.maxRange);
	TrailResult result;
	const std::size_t total = options.maxFrames > 0 ? options.maxFrames : io::countFrames(options.rawlog);
	io::RawlogFrameReader reader(options.rawlog);
	while (auto frame = reader.next())
	{
		if (options.maxFrames > 0 && result.frames >= options.maxFrames) break;
		if (!frame->groundTruth) continue;
		const auto& obs = *frame->observation;
		const auto cuts = personCuts(obs, *frame->groundTruth + obs.sensorPose, options);
		high.insert(obs, *frame->groundTruth, cuts);
		low.insert(obs, *frame->groundTruth, cuts);
		++result.frames;
		if (std::find(cuts.boxes.begin(), cuts.boxes.end(), 1) != cuts.boxes.end()) ++result.framesWithPersons;
		for (std::size_t y = 0; y < result.cutPixels.size(); ++y)
			result.cutPixels[y] += cutDepthPixels(obs, cuts.of(static_cast<Yardstick>(y)));
		if (progress) progress(result.frames, total);
	}
	if (result.frames == 0) throw std::runtime_error(options.rawlog.string() + ": no frames with ground truth");
	result.rows.push_back(high.judge(high.single(), "single OctoMap, high resolution, all pixels"));
	result.rows.push_back(low.judge(low.single(), "single OctoMap, low resolution, all pixels", &high));
	// The persons' own pixels cut: a map with no trail against the person
	// mask. What it still has against the boxes is background the boxes'
	// reference does not see, a floor under any map that maps that background.
	result.rows.push_back(high.judge(
		high.reference(Yardstick::PersonMask), "single OctoMap, high resolution, without the persons' own pixels"));
	result.rows.push_back(low.judge(low.reference(Yardstick::PersonMask),
		"single OctoMap, low resolution, without the persons' own pixels", &high));
	for (const auto& dir : options.avmMaps)
	{
		const auto files = io::RunFolder(dir).map();
		auto row = high.judge(*readBinaryTree(files.highTree), files.highTree.string());
		const auto lowRow = low.judge(*readBinaryTree(files.lowTree), files.lowTree.string(), &high);
		row.map = "avm " + dir.string() + " (low + high)";
		row += lowRow;
		result.rows.push_back(row);
	}
	if (inspect) inspect(high, low);
	return result;
}

std::string toMarkdown(const TrailResult& r)
{
	std::ostringstream out;
	const auto mask = Yardstick::PersonMask, boxes = Yardstick::Boxes;
	out << "frames: " << r.frames << " (" << r.framesWithPersons
		<< " with persons); depth pixels cut: " << r.cutPixels[static_cast<std::size_t>(mask)]
		<< " by the person mask, " << r.cutPixels[static_cast<std::size_t>(boxes)] << " by the boxes\n\n";
	out << "| map | occupied [m³] | trail, person mask [m³] | trail share, person mask | trail, boxes [m³] | "
		   "trail share, boxes |\n|---|---:|---:|---:|---:|---:|\n";
	for (const auto& row : r.rows)
	{
		char line[512];
		std::snprintf(line, sizeof line, "| %s | %.3f | %.3f | %.1f %% | %.3f | %.1f %% |\n", row.map.c_str(),
			row.occupiedM3, row.trail(mask), 100.0 * row.share(mask), row.trail(boxes), 100.0 * row.share(boxes));
		out << line;
	}
	out << "\nthe same, a low-resolution voxel counted as trail only where the high-resolution reference of the same "
		   "yardstick holds no occupied voxel inside it either\n\n"
		   "| map | trail, person mask [m³] | trail share, person mask | trail, boxes [m³] | trail share, boxes |\n"
		   "|---|---:|---:|---:|---:|\n";
	for (const auto& row : r.rows)
	{
		char line[512];
		std::snprintf(line, sizeof line, "| %s | %.3f | %.1f %% | %.3f | %.1f %% |\n", row.map.c_str(),
			row.trailNoFineSurface(mask), 100.0 * row.shareNoFineSurface(mask), row.trailNoFineSurface(boxes),
			100.0 * row.shareNoFineSurface(boxes));
		out << line;
	}
	return out.str();
}
}  // namespace avm::evaluation
