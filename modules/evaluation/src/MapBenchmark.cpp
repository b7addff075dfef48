#include "avm/evaluation/MapBenchmark.h"

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <memory>
#include <numeric>
#include <sstream>

#include "avm/io/RawlogFrameReader.h"
#include "avm/io/ThreadCpuTime.h"
#include "avm/io/TimingSummary.h"
#include "avm/plugin/CAdaptiveOctoMap.h"
#include "avm/maps/OcTreeFile.h"
#include "PlainTreeStats.h"

namespace avm::evaluation
{
namespace
{
struct Frame
{
	mrpt::obs::CObservation3DRangeScan::Ptr obs;
	mrpt::poses::CPose3D pose;
};

/** One contender: inserts a frame (timed by the caller) and reports sizes. */
struct Contender
{
	std::string name;
	std::function<void(const Frame&, const octomap::Pointcloud&, const octomap::point3d&)> insert;
	std::function<void(MapBenchmarkRow&)> sizes;
	std::vector<double> ms, cpuMs;
};

void addSizes(const CDualOctoMap::TTreeStats& s, MapBenchmarkRow& row)
{
	row.occupiedLeaves += s.occupiedLeaves;
	row.freeLeaves += s.freeLeaves;
	row.memoryBytes += s.memoryBytes;
	row.binaryBytes += s.binaryBytes;
}

Contender plainOctomap(double res, double maxRange, bool discretize)
{
	auto tree = std::make_shared<octomap::OcTree>(res);
	Contender c;
	std::ostringstream name;
	name << "octomap insertPointCloud " << res << " m" << (discretize ? " discretize" : "");
	c.name = name.str();
	c.insert = [tree, maxRange, discretize](const Frame&, const octomap::Pointcloud& cloud, const octomap::point3d& o)
	{ tree->insertPointCloud(cloud, o, maxRange, false, discretize); };
	c.sizes = [tree](MapBenchmarkRow& row) { addSizes(plainTreeStats(*tree), row); };
	return c;
}

Contender adaptive(const std::string& name, const std::shared_ptr<CAdaptiveOctoMap>& map)
{
	Contender c;
	c.name = name;
	c.insert = [map](const Frame& f, const octomap::Pointcloud&, const octomap::point3d&)
	{ map->insertObservation(*f.obs, f.pose); };
	c.sizes = [map](MapBenchmarkRow& row)
	{
		addSizes(map->lowResolutionStats(), row);
		addSizes(map->highResolutionStats(), row);
	};
	return c;
}

bool hasPersonLabels(const mrpt::obs::CObservation3DRangeScan& obs)
{
	return obs.pixelLabels && obs.pixelLabels->checkLabelNameExistence("person") >= 0;
}

mrpt::math::TBoundingBox defaultRegion(const Frame& f)
{
	const auto& img = f.obs->rangeImage;
	const double d = img(img.rows() / 2, img.cols() / 2) * f.obs->rangeUnits;
	if (!(d > 0))
		throw std::runtime_error(
			"avm-bench-map: no depth at the first frame's "
			"centre pixel; give --region");
	const auto p = (f.pose + f.obs->sensorPose).composePoint(mrpt::math::TPoint3D(d, 0, 0));
	return {p - mrpt::math::TPoint3D(0.6, 0.6, 1.0), p + mrpt::math::TPoint3D(0.6, 0.6, 1.0)};
}

MapBenchmarkRow summarize(Contender& c)
{
	MapBenchmarkRow row;
	row.name = c.name;
	row.frames = c.ms.size();
	if (!c.ms.empty())
	{
		const auto times = io::summariseTimes(c.ms);
		row.meanMs = times.meanMs;
		row.medianMs = times.medianMs;
		row.p95Ms = times.p95Ms;
		row.meanCpuMs = std::accumulate(c.cpuMs.begin(), c.cpuMs.end(), 0.0) / static_cast<double>(c.cpuMs.size());
	}
	c.sizes(row);
	return row;
}
/** The frames with ground truth, depth and labels only (the colour image
 * dropped). */
std::vector<Frame> readFrames(const MapBenchmarkOptions& opts)
{
	std::vector<Frame> frames;
	avm::io::RawlogFrameReader reader(opts.rawlog);
	while (auto f = reader.next())
	{
		if (opts.maxFrames && frames.size() >= opts.maxFrames) break;
		if (!f->groundTruth) continue;
		f->observation->hasIntensityImage = false;
		f->observation->intensityImage = mrpt::img::CImage();
		frames.push_back({f->observation, *f->groundTruth});
	}
	if (frames.empty())
		throw std::runtime_error("avm-bench-map: no frames with ground truth in " + opts.rawlog.string());
	return frames;
}

/** The adaptive maps (region policy, its threaded twin, paper policy) and
 *  octomap's, in the order of the table. Without person labels in the
 *  frames, the region maps get one fixed region (`result.regionSource` says
 * which). */
std::vector<Contender> makeContenders(
	const MapBenchmarkOptions& opts, const std::vector<Frame>& frames, MapBenchmarkResult& result)
{
	const bool labelled =
		std::any_of(frames.begin(), frames.end(), [](const Frame& f) { return hasPersonLabels(*f.obs); });
	CAdaptiveOctoMap::TCreationOptions regionRes, paperRes;
	regionRes.low.resolution = opts.regionLow;
	regionRes.high.resolution = opts.regionHigh;
	paperRes.low.resolution = opts.paperLow;
	paperRes.high.resolution = opts.paperHigh;
	for (auto* t : {&regionRes.low, &regionRes.high, &paperRes.low, &paperRes.high}) t->maxRange = opts.maxRange;
	CAdaptiveOctoMap::TInsertionOptions regionIns, paperIns;
	paperIns.switchPolicy = SwitchPolicy::Paper;
	paperIns.switchAtFraction = opts.paperSwitchFraction;
	auto regionMap = std::make_shared<CAdaptiveOctoMap>(regionRes, regionIns, CAdaptiveOctoMap::TLikelihoodOptions());
	auto paperMap = std::make_shared<CAdaptiveOctoMap>(paperRes, paperIns, CAdaptiveOctoMap::TLikelihoodOptions());
	std::shared_ptr<CAdaptiveOctoMap> threadedMap;
	if (opts.regionThreads > 1)
	{
		auto ins = regionIns;
		ins.insertionThreads = opts.regionThreads;
		threadedMap = std::make_shared<CAdaptiveOctoMap>(regionRes, ins, CAdaptiveOctoMap::TLikelihoodOptions());
	}
	paperMap->setExpectedFrameCount(frames.size());
	if (labelled)
		result.regionSource = "person pixel labels of the rawlog";
	else
	{
		const auto box = opts.region ? *opts.region : defaultRegion(frames.front());
		regionMap->addHighResolutionRegion(box);
		if (threadedMap) threadedMap->addHighResolutionRegion(box);
		result.regionSource = "fixed box " + box.asString() + " (no person labels in the rawlog)";
	}

	std::vector<Contender> contenders;
	std::ostringstream rn, pn;
	rn << "avm region " << opts.regionLow << "/" << opts.regionHigh << " m";
	pn << "avm paper " << opts.paperLow << "/" << opts.paperHigh << " m (switch at " << opts.paperSwitchFraction << ")";
	contenders.push_back(adaptive(rn.str(), regionMap));
	if (threadedMap)
		contenders.push_back(adaptive(rn.str() + ", " + std::to_string(opts.regionThreads) + " threads", threadedMap));
	contenders.push_back(plainOctomap(opts.regionHigh, opts.maxRange, true));
	contenders.push_back(plainOctomap(opts.regionLow, opts.maxRange, true));
	if (opts.withPlainOctomap) contenders.push_back(plainOctomap(opts.regionHigh, opts.maxRange, false));
	contenders.push_back(adaptive(pn.str(), paperMap));
	contenders.push_back(plainOctomap(opts.paperLow, opts.maxRange, true));
	contenders.push_back(plainOctomap(opts.paperHigh, opts.maxRange, true));
	return contenders;
}

/** octomap's input for one frame (world points and the sensor origin), made
 *  outside its timer; returns the number of points. */
std::size_t octomapInput(const Frame& f, octomap::Pointcloud& cloud, octomap::point3d& origin)
{
	mrpt::maps::CSimplePointsMap pts;
	mrpt::obs::T3DPointsProjectionParams pp;
	pp.takeIntoAccountSensorPoseOnRobot = true;
	pp.robotPoseInTheWorld = f.pose;
	f.obs->unprojectInto(pts, pp);
	cloud.reserve(pts.size());
	const auto& xs = pts.getPointsBufferRef_x();
	const auto& ys = pts.getPointsBufferRef_y();
	const auto& zs = pts.getPointsBufferRef_z();
	for (std::size_t k = 0; k < pts.size(); k++) cloud.push_back(xs[k], ys[k], zs[k]);
	const auto o = (f.pose + f.obs->sensorPose).translation();
	origin = octomap::point3d(o.x, o.y, o.z);
	return pts.size();
}
}  // namespace

MapBenchmarkResult runMapBenchmark(
	const MapBenchmarkOptions& opts, const std::function<void(std::size_t, std::size_t)>& progress)
{
	const std::vector<Frame> frames = readFrames(opts);
	MapBenchmarkResult result;
	result.frames = frames.size();
	std::vector<Contender> contenders = makeContenders(opts, frames, result);

	std::size_t points = 0;
	const std::size_t turn = std::max<std::size_t>(1, opts.framesPerTurn);
	for (std::size_t begin = 0; begin < frames.size(); begin += turn)
	{
		const std::size_t end = std::min(frames.size(), begin + turn);
		std::vector<octomap::Pointcloud> clouds(end - begin);
		std::vector<octomap::point3d> origins(end - begin);
		for (std::size_t i = begin; i < end; i++)
			points += octomapInput(frames[i], clouds[i - begin], origins[i - begin]);
		for (auto& c : contenders)
			for (std::size_t i = begin; i < end; i++)
			{
				const auto t0 = std::chrono::steady_clock::now();
				const double cpu0 = io::threadCpuMs();
				c.insert(frames[i], clouds[i - begin], origins[i - begin]);
				c.cpuMs.push_back(io::threadCpuMs() - cpu0);
				c.ms.push_back(
					std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
			}
		if (progress) progress(end, frames.size());
	}
	result.meanPointsPerFrame = static_cast<double>(points) / static_cast<double>(frames.size());
	for (auto& c : contenders) result.rows.push_back(summarize(c));
	return result;
}

std::string toMarkdown(const MapBenchmarkResult& r)
{
	std::ostringstream s;
	s.setf(std::ios::fixed);
	s << "frames: " << r.frames << ", mean points per frame: " << static_cast<long>(r.meanPointsPerFrame)
	  << "\nregion: " << r.regionSource << "\n\n";
	s << "| map | mean ms/frame | median | p95 | mean CPU ms/frame | occupied "
		 "leaves | free leaves | memory bytes | "
		 ".bt bytes |\n";
	s << "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
	for (const auto& row : r.rows)
	{
		s.precision(2);
		s << "| " << row.name << " | " << row.meanMs << " | " << row.medianMs << " | " << row.p95Ms << " | "
		  << row.meanCpuMs << " | " << row.occupiedLeaves << " | " << row.freeLeaves << " | " << row.memoryBytes
		  << " | " << row.binaryBytes << " |\n";
	}
	return s.str();
}
}  // namespace avm::evaluation
