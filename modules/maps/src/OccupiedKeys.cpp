#include "avm/maps/OccupiedKeys.h"

#include <octomap/OcTree.h>

#include "avm/maps/OcTreeKeyLayout.h"

namespace avm
{
std::set<FinestKey> occupiedFinestKeys(
	const octomap::OcTree& tree, const std::function<bool(double, double, double)>& keep)
{
	std::set<FinestKey> out;
	if (tree.size() == 0) return out;
	for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it)
	{
		if (!tree.isNodeOccupied(*it)) continue;
		const auto first = it.getIndexKey();
		const unsigned span = keySpanAtDepth(it.getDepth());
		for (unsigned x = 0; x < span; x++)
			for (unsigned y = 0; y < span; y++)
				for (unsigned z = 0; z < span; z++)
				{
					const octomap::OcTreeKey k(first[0] + x, first[1] + y, first[2] + z);
					const auto c = tree.keyToCoord(k);
					if (keep(c.x(), c.y(), c.z())) out.emplace(k[0], k[1], k[2]);
				}
	}
	return out;
}

double intersectionOverUnion(const std::set<FinestKey>& a, const std::set<FinestKey>& b)
{
	if (a.empty() && b.empty()) return 1.0;
	std::size_t common = 0;
	for (const auto& k : a) common += b.count(k);
	return static_cast<double>(common) / static_cast<double>(a.size() + b.size() - common);
}
}  // namespace avm
