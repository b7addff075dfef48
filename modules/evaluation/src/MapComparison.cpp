#include "avm/evaluation/MapComparison.h"

#include <octomap/OcTree.h>

#include <cmath>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>

#include "avm/io/RunFolder.h"
#include "avm/maps/OcTreeFile.h"
#include "avm/maps/OcTreeKeyLayout.h"
#include "avm/maps/OccupiedKeys.h"

namespace avm::evaluation
{
namespace
{
struct RunSpace
{
	double lowResolution = 0, highResolution = 0;
	std::set<FinestKey> low, high, space;
};

RunSpace occupiedSpaceOf(const std::filesystem::path& run)
{
	const auto files = io::RunFolder(run).map();
	const auto lowTree = readBinaryTree(files.lowTree);
	const auto highTree = readBinaryTree(files.highTree);
	RunSpace r;
	r.lowResolution = lowTree->getResolution();
	r.highResolution = highTree->getResolution();
	const auto all = [](double, double, double) { return true; };
	r.low = occupiedFinestKeys(*lowTree, all);
	r.high = occupiedFinestKeys(*highTree, all);
	r.space = r.high;
	// A low voxel holds ratio^3 high ones, which share its corner.
	const int ratio = int(std::lround(r.lowResolution / r.highResolution));
	const double inverseHigh = 1.0 / r.highResolution;
	const auto firstHighKey = [&](int lowKey)
	{
		const double corner = keyCentre(lowKey, r.lowResolution) - r.lowResolution / 2;
		return keyOf(corner + r.highResolution / 2, inverseHigh);
	};
	for (const auto& [x, y, z] : r.low)
	{
		const int hx = firstHighKey(x), hy = firstHighKey(y), hz = firstHighKey(z);
		for (int i = 0; i < ratio; ++i)
			for (int j = 0; j < ratio; ++j)
				for (int k = 0; k < ratio; ++k) r.space.emplace(hx + i, hy + j, hz + k);
	}
	return r;
}
}  // namespace

MapComparison compareOccupiedSpace(const std::filesystem::path& runA, const std::filesystem::path& runB)
{
	const RunSpace a = occupiedSpaceOf(runA), b = occupiedSpaceOf(runB);
	if (a.lowResolution != b.lowResolution || a.highResolution != b.highResolution)
		throw std::runtime_error(runB.string() + ": its trees are at " + std::to_string(b.lowResolution) + " / " +
								 std::to_string(b.highResolution) + " m, those of " + runA.string() + " at " +
								 std::to_string(a.lowResolution) + " / " + std::to_string(a.highResolution) + " m");
	MapComparison c;
	c.lowResolution = a.lowResolution;
	c.highResolution = a.highResolution;
	c.lowA = a.low.size();
	c.lowB = b.low.size();
	c.highA = a.high.size();
	c.highB = b.high.size();
	c.spaceA = a.space.size();
	c.spaceB = b.space.size();
	c.lowIoU = intersectionOverUnion(a.low, b.low);
	c.highIoU = intersectionOverUnion(a.high, b.high);
	c.spaceIoU = intersectionOverUnion(a.space, b.space);
	return c;
}
}  // namespace avm::evaluation
