#include "TreeOps.h"

#include <vector>

namespace avm::detail
{
std::unique_ptr<octomap::OcTree> makeTree(const CAdaptiveOctoMap::TTreeOptions& o)
{
	auto t = std::make_unique<octomap::OcTree>(o.resolution);
	t->setProbHit(o.probHit);
	t->setProbMiss(o.probMiss);
	t->setClampingThresMin(o.clampingThresMin);
	t->setClampingThresMax(o.clampingThresMax);
	t->setOccupancyThres(o.occupancyThres);
	return t;
}

namespace
{
/** Removes the finest voxel `key` below `node` (at `depth`); true when
 *  `node` is left without children and must go too. octomap 1.9.7's own
 *  deleteNode() deletes such an emptied inner node with its (empty) child
 *  array still allocated, which its node destructor asserts against. */
bool eraseRecurs(octomap::OcTree& t, octomap::OcTreeNode* node, unsigned depth, const octomap::OcTreeKey& key)
{
	if (depth == t.getTreeDepth()) return true;
	const unsigned pos = octomap::computeChildIdx(key, static_cast<int>(t.getTreeDepth() - 1 - depth));
	if (!t.nodeChildExists(node, pos))
	{
		if (t.nodeHasChildren(node) || node == t.getRoot()) return false;  // nothing there
		t.expandNode(node);	 // a pruned leaf: split it to remove a part
	}
	auto* child = t.getNodeChild(node, pos);
	if (!eraseRecurs(t, child, depth + 1, key)) return false;
	// Free the child's child array (allocated even when emptied): give it 8
	// equal children and prune them, which releases the array through
	// octomap's public API; then the child can be deleted safely.
	t.expandNode(child);
	t.pruneNode(child);
	t.deleteNodeChild(node, pos);
	if (!t.nodeHasChildren(node)) return node != t.getRoot();
	node->updateOccupancyChildren();
	return false;
}

void eraseVoxel(octomap::OcTree& t, const octomap::OcTreeKey& key)
{
	if (!t.getRoot()) return;
	eraseRecurs(t, t.getRoot(), 0, key);
	if (!t.nodeHasChildren(t.getRoot())) t.clear();
}
}  // namespace

void deleteSpace(octomap::OcTree& tree, const mrpt::math::TBoundingBox& box)
{
	if (tree.size() == 0) return;
	const double res = tree.getResolution();
	auto inBox = [&](double x, double y, double z) {
		return x >= box.min.x && x < box.max.x && y >= box.min.y && y < box.max.y && z >= box.min.z && z < box.max.z;
	};
	// Collect first: deleting while iterating would invalidate the iterator.
	std::vector<octomap::OcTreeKey> doomed;
	const octomap::point3d lo(box.min.x, box.min.y, box.min.z), hi(box.max.x, box.max.y, box.max.z);
	for (auto it = tree.begin_leafs_bbx(lo, hi), end = tree.end_leafs_bbx(); it != end; ++it)
	{
		const double size = it.getSize();
		const auto c = it.getCoordinate();
		if (it.getDepth() == tree.getTreeDepth())
		{
			if (inBox(c.x(), c.y(), c.z())) doomed.push_back(it.getKey());
			continue;
		}
		// A pruned leaf: its finest voxels inside the box (deleteNode expands it).
		const double h = 0.5 * size;
		for (double x = c.x() - h + 0.5 * res; x < c.x() + h; x += res)
			for (double y = c.y() - h + 0.5 * res; y < c.y() + h; y += res)
				for (double z = c.z() - h + 0.5 * res; z < c.z() + h; z += res)
					if (inBox(x, y, z)) doomed.push_back(tree.coordToKey(x, y, z));
	}
	for (const auto& k : doomed) eraseVoxel(tree, k);
}
}  // namespace avm::detail
