// The trail voxels of a map's tree (occupied in it, free in a reference),
// found again by the points that end in them: for avm-trail's diagnostics
// (TrailCauses, TrailPixels), which follow the pixels of every frame.
#pragma once

#include <mrpt/poses/CPose3D.h>
#include <octomap/OcTree.h>

#include <array>
#include <cstddef>
#include <map>
#include <memory>
#include <unordered_map>
#include <vector>

#include "avm/io/DepthCamera.h"
#include "avm/io/RawlogFrameReader.h"
#include "avm/io/RunFolder.h"
#include "avm/maps/OcTreeFile.h"
#include "avm/evaluation/TrailShare.h"

namespace avm::evaluation
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

/** A run's two trees and their trail voxels against one yardstick's
 *  references of the same resolutions: index 0 the high tree, 1 the low. */
struct RunTrailVoxels
{
	std::unique_ptr<octomap::OcTree> highTree, lowTree;
	std::array<TrailVoxels, 2> trees;

	RunTrailVoxels(const io::RunFolder& run, const TrailReference& high, const TrailReference& low, Yardstick y)
		: highTree(readBinaryTree(run.map().highTree)), lowTree(readBinaryTree(run.map().lowTree))
	{
		trees[0].collect(*highTree, high.reference(y));
		trees[1].collect(*lowTree, low.reference(y));
	}
};

/** Follows the rawlog's pixels into the trail voxels, as the references
 *  were built: for each frame with ground truth (up to options.maxFrames),
 *  onFrame(frame, sensorPose, cuts), then for each of its depth pixels whose
 *  point lies within options.maxRange and in a trail voxel,
 *  onPixel(pixel index, point, tree index, voxel). */
template <class OnFrame, class OnPixel>
void forEachTrailPixel(const TrailOptions& options, std::array<TrailVoxels, 2>& trees, OnFrame onFrame, OnPixel onPixel)
{
	io::RawlogFrameReader reader(options.rawlog);
	std::size_t frames = 0;
	while (auto frame = reader.next())
	{
		if (options.maxFrames > 0 && frames >= options.maxFrames) break;
		if (!frame->groundTruth) continue;
		++frames;
		const auto& obs = *frame->observation;
		const auto camera = io::DepthCamera::of(obs);
		const mrpt::poses::CPose3D sensor = *frame->groundTruth + obs.sensorPose;
		onFrame(*frame, sensor, personCuts(obs, sensor, options));
		for (int v = 0; v < camera.height; v++)
			for (int u = 0; u < camera.width; u++)
			{
				const std::uint16_t raw = obs.rangeImage(v, u);
				if (raw == 0) continue;
				const auto local = camera.unproject(u, v, raw * obs.rangeUnits);
				if (local.norm() > options.maxRange) continue;  // octomap keeps no endpoint there
				const auto p = sensor.composePoint(local);
				const auto i = static_cast<std::size_t>(v) * camera.width + u;
				for (std::size_t t = 0; t < trees.size(); ++t)
					for (auto* voxel : trees[t].at(octomap::point3d(p.x, p.y, p.z))) onPixel(i, p, t, *voxel);
			}
	}
}
}  // namespace avm::evaluation
