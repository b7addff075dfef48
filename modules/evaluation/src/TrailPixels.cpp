#include "avm/evaluation/TrailPixels.h"

#include <mrpt/poses/CPose3D.h>

#include <algorithm>
#include <cstdio>
#include <sstream>
#include <vector>

#include "TrailVoxels.h"
#include "avm/persons/PersonBand.h"
#include "avm/persons/PersonLabels.h"

namespace avm::evaluation
{
namespace
{
constexpr std::size_t kClasses = static_cast<std::size_t>(TrailPixelClass::Count);
using Counts = std::array<std::size_t, kClasses>;

/** Per trail voxel, besides its pixel counts: the behind pixels' summed
 *  distance past the band, the frames whose cut and uncut pixels ended in it. */
struct VoxelExtra
{
	double pastBand = 0;
	std::size_t cutFrames = 0, uncutFrames = 0, lastCutFrame = ~std::size_t(0), lastUncutFrame = ~std::size_t(0);
};

void add(TrailPixelCount& c, const TrailVoxel& v, bool otherToo, bool personMaskTrail)
{
	const double m3 = v.size * v.size * v.size;
	++c.voxels;
	c.m3 += m3;
	if (otherToo) c.otherPixelsM3 += m3;
	if (personMaskTrail) c.personMaskTrailM3 += m3;
}
/** Each trail voxel of one tree into `out` (by its first and its most
 *  frequent pixel class) and one line of `csv`; `maskReference`: the same
 *  resolution's reference without the persons' own pixels. */
void summarize(const TrailVoxels& tree, const std::vector<Counts>& counts, const std::vector<VoxelExtra>& extra,
	const octomap::OcTree& maskReference, const char* name, TrailPixels& out, std::ostream& csv)
{
	for (std::size_t k = 0; k < tree.voxels.size(); ++k)
	{
		const auto& v = tree.voxels[k];
		const auto& n = counts[k];
		const auto& e = extra[k];
		const auto* ref = maskReference.search(v.key, v.depth);  // as TrailReference::judge
		const bool maskTrail = ref && !maskReference.isNodeOccupied(ref);
		const bool otherToo = n[static_cast<std::size_t>(TrailPixelClass::Other)] > 0;
		std::size_t first = kClasses - 1, most = kClasses - 1, cutPixels = 0;
		for (std::size_t c = 0; c + 1 < kClasses; ++c) cutPixels += n[c];
		for (std::size_t c = 0; c < kClasses; ++c)
			if (n[c] > 0)
			{
				first = c;
				break;
			}
		// Most among the cut pixels, when there are any.
		for (std::size_t c = 0; c + 1 < kClasses; ++c)
			if (cutPixels > 0 && (most == kClasses - 1 || n[c] > n[most])) most = c;
		csv << name << ',' << v.centre.x() << ',' << v.centre.y() << ',' << v.centre.z() << ',' << v.size;
		for (const auto x : n) csv << ',' << x;
		const auto behind = n[static_cast<std::size_t>(TrailPixelClass::Behind)];
		csv << ',' << (behind > 0 ? e.pastBand / double(behind) : 0.0) << ',' << e.cutFrames << ',' << e.uncutFrames
			<< ',' << static_cast<long long>(e.lastCutFrame) << ',' << static_cast<long long>(e.lastUncutFrame) << ','
			<< maskTrail << '\n';
		add(out.byFirst[first], v, otherToo, maskTrail);
		add(out.byMost[most], v, otherToo, maskTrail);
	}
}
}  // namespace

std::vector<std::uint8_t> trailPixelClasses(const mrpt::obs::CObservation3DRangeScan& obs,
	const mrpt::poses::CPose3D& sensorPose, const TrailOptions& o, const std::vector<std::uint8_t>& cut,
	double edgeRatio, std::vector<float>& personDepth)
{
	const int rows = static_cast<int>(obs.rangeImage.rows()), cols = static_cast<int>(obs.rangeImage.cols());
	std::vector<std::uint8_t> cls(static_cast<std::size_t>(rows) * cols, std::uint8_t(TrailPixelClass::Other));
	personDepth.assign(cls.size(), 0);
	if (cut.empty()) return cls;
	std::vector<std::uint8_t> band(cls.size(), 0);
	for (std::size_t i = 0; i < cls.size(); ++i)
		if (cut[i]) cls[i] = std::uint8_t(TrailPixelClass::NoSighting);
	for (const auto& pixels : persons::personPixelsFromLabels(obs, o.personLabel, o.sighting.minPixels))
	{
		const auto est = persons::estimateSighting(obs, sensorPose, pixels, o.sighting);
		if (!est.sighting) continue;
		// The nearest sighted person is the one a pixel is judged against.
		for (const auto i : pixels)
			if (personDepth[i] == 0 || est.sighting->depth < personDepth[i]) personDepth[i] = est.sighting->depth;
		for (const auto i : persons::personBandPixels(obs, pixels, *est.sighting, o.sighting)) band[i] = 1;
	}
	for (int v = 0; v < rows; ++v)
		for (int u = 0; u < cols; ++u)
		{
			const auto i = static_cast<std::size_t>(v) * cols + u;
			if (!cut[i] || personDepth[i] == 0) continue;
			if (band[i])
			{
				cls[i] = std::uint8_t(TrailPixelClass::Band);
				continue;
			}
			bool nextToBand = false;
			for (int dv = -1; dv <= 1 && !nextToBand; ++dv)
				for (int du = -1; du <= 1; ++du)
				{
					const int uu = u + du, vv = v + dv;
					if (uu >= 0 && vv >= 0 && uu < cols && vv < rows && band[static_cast<std::size_t>(vv) * cols + uu])
						nextToBand = true;
				}
			const double d = obs.rangeImage(v, u) * obs.rangeUnits;
			if (nextToBand && persons::onDepthEdge(obs, u, v, edgeRatio))
				cls[i] = std::uint8_t(TrailPixelClass::Mixed);
			else
				cls[i] = std::uint8_t(d > personDepth[i] ? TrailPixelClass::Behind : TrailPixelClass::InFront);
		}
	return cls;
}

std::string describe(TrailPixelClass c)
{
	switch (c)
	{
		case TrailPixelClass::Band:
			return "the person's own (in the depth band)";
		case TrailPixelClass::Mixed:
			return "mixed: depth edge next to a band pixel";
		case TrailPixelClass::Behind:
			return "behind the band, not mixed";
		case TrailPixelClass::InFront:
			return "in front of the band, not mixed";
		case TrailPixelClass::NoSighting:
			return "a label with no sighting";
		case TrailPixelClass::Other:
			return "not cut by the yardstick";
		case TrailPixelClass::Count:
			break;
	}
	return "?";
}

TrailPixels classifyTrailPixels(const TrailOptions& options, const std::filesystem::path& avmDir,
	const TrailReference& high, const TrailReference& low, Yardstick yardstick, double edgeRatio)
{
	const io::RunFolder run(avmDir);
	RunTrailVoxels found(run, high, low, yardstick);
	auto& trees = found.trees;
	std::vector<std::vector<Counts>> counts(2);
	std::vector<std::vector<VoxelExtra>> extra(2);
	for (std::size_t t = 0; t < 2; ++t)
	{
		counts[t].assign(trees[t].voxels.size(), Counts{});
		extra[t].assign(trees[t].voxels.size(), VoxelExtra{});
	}

	TrailPixels out;
	out.map = avmDir.string();
	out.yardstick = yardstick;
	out.edgeRatio = edgeRatio;
	std::size_t frameIndex = 0;
	const mrpt::obs::CObservation3DRangeScan* obs = nullptr;
	std::vector<std::uint8_t> cls;
	std::vector<float> personDepth;
	forEachTrailPixel(
		options, trees,
		[&](const io::RgbdFrame& f, const mrpt::poses::CPose3D& sensor, const PersonCuts& cuts)
		{
			frameIndex = f.index, obs = f.observation.get();
			cls = trailPixelClasses(*obs, sensor, options, cuts.of(yardstick), edgeRatio, personDepth);
		},
		[&](std::size_t i, const mrpt::math::TPoint3D&, std::size_t t, TrailVoxel& voxel)
		{
			const auto c = cls[i];
			const auto k = static_cast<std::size_t>(&voxel - trees[t].voxels.data());
			++counts[t][k][c];
			++out.pixels[c];
			auto& e = extra[t][k];
			if (c == std::uint8_t(TrailPixelClass::Behind))
			{
				const auto v = static_cast<int>(i / obs->rangeImage.cols()),
						   u = static_cast<int>(i % obs->rangeImage.cols());
				const double past =
					obs->rangeImage(v, u) * obs->rangeUnits - personDepth[i] - options.sighting.depthBand;
				++out.behindPastBand[past <= 0.25 ? 0 : past <= 0.5 ? 1 : past <= 1 ? 2 : 3];
				e.pastBand += past;
			}
			const bool cutPixel = c != std::uint8_t(TrailPixelClass::Other);
			auto& last = cutPixel ? e.lastCutFrame : e.lastUncutFrame;
			if (last != frameIndex) ++(cutPixel ? e.cutFrames : e.uncutFrames), last = frameIndex;
		});
	std::ostringstream csv;
	csv << "tree,x,y,z,size,band,mixed,behind,in_front,no_sighting,uncut,behind_past_band_mean,cut_frames,uncut_"
		   "frames,last_cut_frame,last_uncut_frame,person_mask_trail\n";
	summarize(trees[0], counts[0], extra[0], high.reference(Yardstick::PersonMask), "high", out, csv);
	summarize(trees[1], counts[1], extra[1], low.reference(Yardstick::PersonMask), "low", out, csv);
	out.voxelsCsv = csv.str();
	return out;
}

std::string toMarkdown(const TrailPixels& t)
{
	double total = 0;
	for (const auto& c : t.byFirst) total += c.m3;
	std::ostringstream out;
	out << "trail of " << t.map << " against the reference without " << describe(t.yardstick)
		<< ", by the pixels that ended in it (" << total << " m³; depth edge: 3x3 range > " << t.edgeRatio
		<< " of the depth)\n\n";
	out << "| pixel class | pixels | voxels (first class) | trail [m³] | share | of it, uncut pixels too [m³] | of it, "
		   "trail against the person mask too [m³] | voxels (most pixels) | trail [m³] | share | of it, uncut pixels "
		   "too "
		   "[m³] | of it, trail against the person mask too [m³] |\n"
		   "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
	for (std::size_t c = 0; c < kClasses; ++c)
	{
		const auto& f = t.byFirst[c];
		const auto& m = t.byMost[c];
		char line[640];
		std::snprintf(line, sizeof line,
			"| %s | %zu | %zu | %.3f | %.1f %% | %.3f | %.3f | %zu | %.3f | %.1f %% | %.3f | %.3f |\n",
			describe(static_cast<TrailPixelClass>(c)).c_str(), t.pixels[c], f.voxels, f.m3,
			total > 0 ? 100.0 * f.m3 / total : 0.0, f.otherPixelsM3, f.personMaskTrailM3, m.voxels, m.m3,
			total > 0 ? 100.0 * m.m3 / total : 0.0, m.otherPixelsM3, m.personMaskTrailM3);
		out << line;
	}
	const auto& b = t.behindPastBand;
	out << "\nbehind pixels by how far past the band: <= 0.25 m " << b[0] << ", 0.25-0.5 m " << b[1] << ", 0.5-1 m "
		<< b[2] << ", > 1 m " << b[3] << "\n";
	return out.str();
}
}  // namespace avm::evaluation
