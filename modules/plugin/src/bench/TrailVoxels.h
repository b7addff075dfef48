// The trail voxels of a map's tree (occupied in it, free in a reference),
// found again by the points that end in them: for avm-trail's diagnostics
// (TrailCauses, TrailPixels), which follow the pixels of every frame.
#pragma once

#include <octomap/OcTree.h>

#include <cstddef>
#include <map>
#include <unordered_map>
#include <vector>

namespace avm::maps
{
struct TrailVoxel
{
	octomap::point3d centre;
	double size = 0;
	octomap::OcTreeKey key;  //!< at its depth
	unsigned depth = 0;
	/** Frame index -> which pixels ended in the voxel then (the caller's flags). */
	std::map<std::size_t, unsigned char> hits;
};

/** The trail voxels of one tree, found by key at each depth they have. */
struct TrailVoxels
{
	const octomap::OcTree* tree = nullptr;
	std::vector<TrailVoxel> voxels;
	std::map<unsigned, std::unordered_map<octomap::OcTreeKey, std::size_t, octomap::OcTreeKey::KeyHash>> byDepth;

	void collect(const octomap::OcTree& map, const octomap::OcTree& reference)
	{
		tree = &map;
		for (auto it = map.begin_leafs(), end = map.end_leafs(); it != end; ++it)
		{
			if (!map.isNodeOccupied(*it)) continue;
			const auto* ref = reference.search(it.getKey(), it.getDepth());
			if (!ref || reference.isNodeOccupied(ref)) continue;
			const auto key = map.adjustKeyAtDepth(it.getKey(), it.getDepth());
			byDepth[it.getDepth()][key] = voxels.size();
			voxels.push_back({it.getCoordinate(), it.getSize(), key, it.getDepth(), {}});
		}
	}
	/** The trail voxels `p` lies in. */
	std::vector<TrailVoxel*> at(const octomap::point3d& p)
	{
		std::vector<TrailVoxel*> found;
		octomap::OcTreeKey key;
		if (!tree->coordToKeyChecked(p, key)) return found;
		for (auto& [depth, index] : byDepth)
			if (const auto it = index.find(tree->adjustKeyAtDepth(key, depth)); it != index.end())
				found.push_back(&voxels[it->second]);
		return found;
	}
};

}  // namespace avm::maps
