#include "avm/plugin/TrailShare.h"

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
#include "avm/persons/PersonLabels.h"

namespace avm::maps
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

TrailReference::TrailReference(double resolution, double maxRange)
	: m_reference(std::make_unique<octomap::OcTree>(resolution)),
	  m_single(std::make_unique<octomap::OcTree>(resolution)),
	  m_maxRange(maxRange)
{
}

TrailReference::~TrailReference() = default;

void TrailReference::insert(const mrpt::obs::CObservation3DRangeScan& obs, const mrpt::poses::CPose3D& robotPose,
	const std::vector<std::uint8_t>& cut)
{
	const auto camera = io::DepthCamera::of(obs);
	const mrpt::poses::CPose3D sensor = robotPose + obs.sensorPose;
	const auto o = sensor.translation();
	const octomap::point3d origin(o.x, o.y, o.z);
	octomap::Pointcloud all, kept;
	for (int v = 0; v < camera.height; v++)
		for (int u = 0; u < camera.width; u++)
		{
			const std::uint16_t raw = obs.rangeImage(v, u);
			if (raw == 0) continue;
			const auto p = sensor.composePoint(camera.unproject(u, v, raw * obs.rangeUnits));
			const octomap::point3d q(p.x, p.y, p.z);
			all.push_back(q);
			const auto i = static_cast<std::size_t>(v) * camera.width + u;
			if (cut.empty() || !cut[i]) kept.push_back(q);
		}
	m_single->insertPointCloud(all, origin, m_maxRange, false, true);
	m_reference->insertPointCloud(kept, origin, m_maxRange, false, true);
}

TrailRow TrailReference::judge(const octomap::OcTree& map, const std::string& name) const
{
	if (std::abs(map.getResolution() - m_reference->getResolution()) > 1e-9)
		throw std::invalid_argument(name + ": resolution " + std::to_string(map.getResolution()) +
									" m, the reference is at " + std::to_string(m_reference->getResolution()) + " m");
	TrailRow row;
	row.map = name;
	for (auto it = map.begin_leafs(), end = map.end_leafs(); it != end; ++it)
	{
		if (!map.isNodeOccupied(*it)) continue;
		const double size = it.getSize(), volume = size * size * size;
		row.occupiedM3 += volume;
		const auto* ref = m_reference->search(it.getKey(), it.getDepth());
		if (ref && !m_reference->isNodeOccupied(ref)) row.trailM3 += volume;
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
		const auto cut = personPixelMask(*frame->observation, options.personLabel);
		high.insert(*frame->observation, *frame->groundTruth, cut);
		low.insert(*frame->observation, *frame->groundTruth, cut);
		++result.frames;
		if (std::find(cut.begin(), cut.end(), 1) != cut.end()) ++result.framesWithPersons;
		if (progress) progress(result.frames, total);
	}
	if (result.frames == 0) throw std::runtime_error(options.rawlog.string() + ": no frames with ground truth");
	result.rows.push_back(high.judge(high.single(), "single OctoMap, high resolution, all pixels"));
	result.rows.push_back(low.judge(low.single(), "single OctoMap, low resolution, all pixels"));
	for (const auto& dir : options.avmMaps)
	{
		const auto files = io::RunFolder(dir).map();
		auto row = high.judge(*readBinaryTree(files.highTree), files.highTree.string());
		const auto lowRow = low.judge(*readBinaryTree(files.lowTree), files.lowTree.string());
		row.map = "avm " + dir.string() + " (low + high)";
		row.occupiedM3 += lowRow.occupiedM3;
		row.trailM3 += lowRow.trailM3;
		result.rows.push_back(row);
	}
	if (inspect) inspect(high, low);
	return result;
}

std::string toMarkdown(const TrailResult& r)
{
	std::ostringstream out;
	out << "frames: " << r.frames << " (" << r.framesWithPersons << " with persons)\n\n";
	out << "| map | occupied [m³] | trail [m³] | trail share |\n|---|---|---|---|\n";
	for (const auto& row : r.rows)
	{
		char line[512];
		std::snprintf(line, sizeof line, "| %s | %.3f | %.3f | %.1f %% |\n", row.map.c_str(), row.occupiedM3,
			row.trailM3, 100.0 * row.share());
		out << line;
	}
	return out.str();
}
}  // namespace avm::maps
