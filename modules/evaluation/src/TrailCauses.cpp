#include "avm/evaluation/TrailCauses.h"

#include <mrpt/math/TBoundingBox.h>
#include <mrpt/poses/CPose3D.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "avm/io/RunFolder.h"
#include "TrailVoxels.h"

namespace avm::evaluation
{
namespace
{
/** What ended in a trail voxel on one frame: a person pixel whose point no
 *  region box of the run held then, one a region box held, another pixel,
 *  a person pixel whose ray passed through a region box to end beyond it
 *  (with the boxes: background in the person's image box). */
constexpr unsigned char kPersonOutsideRegions = 1, kPersonInRegion = 2, kOtherPixel = 4, kPersonPastRegion = 8;

struct RegionSeen
{
	std::size_t frame = 0;
	double time = 0;
	bool first = false;  //!< the person's first region
	mrpt::math::TBoundingBox box;
};

std::vector<RegionSeen> readRegions(const std::filesystem::path& file)
{
	std::ifstream in(file);
	if (!in) throw std::runtime_error(file.string() + ": cannot be read");
	std::vector<RegionSeen> regions;
	std::vector<unsigned> seenIds;
	for (std::string line; std::getline(in, line);)
	{
		const auto bar = line.find('|');
		if (line.empty() || line[0] == '#' || bar == std::string::npos) continue;
		std::istringstream head(line.substr(0, bar)), tail(line.substr(bar + 1));
		RegionSeen r;
		unsigned id = 0;
		auto& lo = r.box.min;
		auto& hi = r.box.max;
		if (!(head >> r.frame >> r.time) || !(tail >> id >> lo.x >> lo.y >> lo.z >> hi.x >> hi.y >> hi.z)) continue;
		r.first = std::find(seenIds.begin(), seenIds.end(), id) == seenIds.end();
		if (r.first) seenIds.push_back(id);
		regions.push_back(r);
	}
	return regions;
}

/** A person pixel's flag: whether a region box of the run, applied by frame
 *  `f` (time `t`) and followed no longer than `horizon`, held its point `p`,
 *  or the ray from `origin` passed through one. */
unsigned char pixelCause(const std::vector<RegionSeen>& regions, std::size_t f, double t,
	const mrpt::math::TPoint3D& origin, const mrpt::math::TPoint3D& p, std::size_t lagFrames, double horizon);

/** Whether the segment from `a` to `b` passes through `box` (slab test). */
bool crosses(const mrpt::math::TBoundingBox& box, const mrpt::math::TPoint3D& a, const mrpt::math::TPoint3D& b)
{
	double enter = 0, leave = 1;
	for (int i = 0; i < 3; ++i)
	{
		const double d = b[i] - a[i];
		if (std::abs(d) < 1e-12)
		{
			if (a[i] < box.min[i] || a[i] > box.max[i]) return false;
			continue;
		}
		double t0 = (box.min[i] - a[i]) / d, t1 = (box.max[i] - a[i]) / d;
		if (t0 > t1) std::swap(t0, t1);
		enter = std::max(enter, t0);
		leave = std::min(leave, t1);
	}
	return enter <= leave;
}

bool covers(const mrpt::math::TBoundingBox& box, const TrailVoxel& v)
{
	const double h = v.size / 2;
	return v.centre.x() + h > box.min.x && v.centre.x() - h < box.max.x && v.centre.y() + h > box.min.y &&
		   v.centre.y() - h < box.max.y && v.centre.z() + h > box.min.z && v.centre.z() - h < box.max.z;
}
}  // namespace

namespace
{
unsigned char pixelCause(const std::vector<RegionSeen>& regions, std::size_t f, double t,
	const mrpt::math::TPoint3D& origin, const mrpt::math::TPoint3D& p, std::size_t lagFrames, double horizon)
{
	unsigned char what = kPersonOutsideRegions;
	for (const auto& r : regions)
	{
		if (r.frame + lagFrames > f || t - r.time > horizon) continue;
		if (r.box.containsPoint(p)) return kPersonInRegion;
		if (crosses(r.box, origin, p)) what = kPersonPastRegion;
	}
	return what;
}
}  // namespace

std::string describe(TrailCause cause)
{
	switch (cause)
	{
		case TrailCause::NoEndpoint:
			return "no pixel ended in it (detail folded into the low tree)";
		case TrailCause::BeforeFirstRegion:
			return "person pixels outside the regions, before the person's first one";
		case TrailCause::BetweenRegions:
			return "person pixels outside the regions, before a later one covered it";
		case TrailCause::NeverInRegion:
			return "person pixels outside the regions, no region box ever covered it";
		case TrailCause::PastRegion:
			return "person pixels past a region box (with the boxes: background beside or behind the person)";
		case TrailCause::InsideRegion:
			return "person pixels, each inside a region box then";
		case TrailCause::OtherPixelsOnly:
			return "only pixels the yardstick does not cut";
		case TrailCause::Count:
			break;
	}
	return "?";
}

TrailCauses explainTrails(const TrailOptions& options, const std::filesystem::path& avmDir, const TrailReference& high,
	const TrailReference& low, std::size_t lagFrames, double horizon, Yardstick yardstick)
{
	const io::RunFolder run(avmDir);
	RunTrailVoxels found(run, high, low, yardstick);
	const auto regions = readRegions(run.detections());
	const io::RgbdFrame* frame = nullptr;
	const mrpt::poses::CPose3D* sensor = nullptr;
	const std::vector<std::uint8_t>* cut = nullptr;
	PersonCuts cuts;
	forEachTrailPixel(
		options, found.trees,
		[&](const io::RgbdFrame& f, const mrpt::poses::CPose3D& s, PersonCuts c)
		{
			frame = &f, sensor = &s, cuts = std::move(c);
			cut = &cuts.of(yardstick);
		},
		[&](std::size_t i, const mrpt::math::TPoint3D& p, std::size_t, TrailVoxel& voxel)
		{
			unsigned char what = kOtherPixel;
			if (!cut->empty() && (*cut)[i])
				what =
					pixelCause(regions, frame->index, frame->timestamp(), sensor->translation(), p, lagFrames, horizon);
			voxel.hits[frame->index] |= what;
		});

	TrailCauses out;
	out.map = avmDir.string();
	out.yardstick = yardstick;
	for (const auto& t : found.trees)
		for (const auto& v : t.voxels)
		{
			unsigned char all = 0;
			for (const auto& h : v.hits) all |= h.second;
			auto cause = TrailCause::OtherPixelsOnly;
			std::size_t wait = 0;
			if (v.hits.empty())
				cause = TrailCause::NoEndpoint;
			else if (all & kPersonOutsideRegions)
			{
				const auto f = std::find_if(v.hits.begin(), v.hits.end(),
					[](const auto& h) {
						return h.second & kPersonOutsideRegions;
					})->first;
				const auto next = std::find_if(regions.begin(), regions.end(),
					[&](const RegionSeen& r) { return r.frame + lagFrames > f && covers(r.box, v); });
				if (next == regions.end())
					cause = TrailCause::NeverInRegion;
				else if (next->first)
					cause = TrailCause::BeforeFirstRegion, wait = next->frame + lagFrames - f;
				else
					cause = TrailCause::BetweenRegions;
			}
			else if (all & kPersonPastRegion)
				cause = TrailCause::PastRegion;
			else if (all & kPersonInRegion)
				cause = TrailCause::InsideRegion;
			auto& c = out.counts[static_cast<std::size_t>(cause)];
			++c.voxels;
			c.m3 += v.size * v.size * v.size;
			if ((all & kOtherPixel) && cause != TrailCause::OtherPixelsOnly)
				c.withOtherPixelsM3 += v.size * v.size * v.size;
			if (cause == TrailCause::BeforeFirstRegion) out.framesBeforeRegion.push_back(wait);
		}
	return out;
}

std::string toMarkdown(const TrailCauses& causes)
{
	double total = 0;
	for (const auto& c : causes.counts) total += c.m3;
	std::ostringstream out;
	out << "trail of " << causes.map << " against the reference without " << describe(causes.yardstick)
		<< ", by cause (" << total << " m³)\n\n";
	out << "| cause | voxels | trail [m³] | share of the trail | of it, non-person pixels too [m³] |\n"
		   "|---|---:|---:|---:|---:|\n";
	for (std::size_t i = 0; i < causes.counts.size(); ++i)
	{
		const auto& c = causes.counts[i];
		char line[512];
		std::snprintf(line, sizeof line, "| %s | %zu | %.3f | %.1f %% | %.3f |\n",
			describe(static_cast<TrailCause>(i)).c_str(), c.voxels, c.m3, total > 0 ? 100.0 * c.m3 / total : 0.0,
			c.withOtherPixelsM3);
		out << line;
	}
	auto waits = causes.framesBeforeRegion;
	if (!waits.empty())
	{
		std::sort(waits.begin(), waits.end());
		out << "\nframes from the first person pixel to the person's first region: median " << waits[waits.size() / 2]
			<< ", max " << waits.back() << "\n";
	}
	return out.str();
}
}  // namespace avm::evaluation
