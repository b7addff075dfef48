// The size figures of a plain octomap tree, set beside avm's two trees by the
// map benchmark and the reference maps. CDualOctoMap::statsOf counts only the
// leaves the dual map shows (Algorithm 2); a plain tree shows all of its own.
#pragma once
#include <octomap/OcTree.h>

#include "avm/maps/CDualOctoMap.h"
#include "avm/maps/OcTreeFile.h"

namespace avm::evaluation
{
inline CDualOctoMap::TTreeStats plainTreeStats(const octomap::OcTree& t)
{
	CDualOctoMap::TTreeStats s;
	s.resolution = t.getResolution();
	for (auto it = t.begin_leafs(), end = t.end_leafs(); it != end; ++it)
		(t.isNodeOccupied(*it) ? s.occupiedLeaves : s.freeLeaves)++;
	s.memoryBytes = t.memoryUsage();
	s.binaryBytes = binaryTreeBytes(t).size();
	return s;
}
}  // namespace avm::evaluation
