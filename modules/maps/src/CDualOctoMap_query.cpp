// Queries that hide the two trees: which tree is responsible for a point,
// what it knows there, and the per-tree figures of the paper's comparison.
#include <octomap/OcTree.h>

#include <sstream>

#include "OverlapFilter.h"
#include "ResolutionPolicy.h"
#include "SurfaceSketch.h"
#include "TreeOps.h"
#include "avm/io/DepthCamera.h"
#include "avm/maps/CDualOctoMap.h"
#include "avm/maps/OcTreeFile.h"

using namespace avm;

namespace
{
TOccupancyQuery answer(const octomap::OcTree& tree, const octomap::OcTreeNode* node, Resolution which)
{
	TOccupancyQuery q;
	q.tree = which;
	q.resolution = tree.getResolution();
	if (!node) return q;
	q.probability = node->getOccupancy();
	q.state = tree.isNodeOccupied(node) ? OccupancyState::Occupied : OccupancyState::Free;
	return q;
}
}  // namespace

TOccupancyQuery CDualOctoMap::query(const mrpt::math::TPoint3D& p) const
{
	if (m_policy->policy() == SwitchPolicy::Region)
	{
		if (m_high && m_policy->inHighResolutionSpace(p))
			return answer(*m_high, m_high->search(p.x, p.y, p.z), Resolution::High);
		return answer(*m_low, m_low->search(p.x, p.y, p.z), Resolution::Low);
	}
	// Paper: the low tree wins wherever it has a node (Algorithm 2).
	if (!m_high || !detail::overlapFilterAdmits(*m_low, p))
		return answer(*m_low, m_low->search(p.x, p.y, p.z), Resolution::Low);
	return answer(*m_high, m_high->search(p.x, p.y, p.z), Resolution::High);
}

void avm::forEachVisibleLeaf(
	const octomap::OcTree& tree, const octomap::OcTree* hiddenBy, const std::function<void(const TLeafVoxel&)>& visit)
{
	if (tree.size() == 0) return;
	for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it)
	{
		TLeafVoxel v;
		v.center = detail::toTPoint(it.getCoordinate());
		if (hiddenBy && !detail::overlapFilterAdmits(*hiddenBy, v.center)) continue;
		v.size = it.getSize();
		v.probability = it->getOccupancy();
		v.occupied = tree.isNodeOccupied(*it);
		visit(v);
	}
}

void CDualOctoMap::forEachLeaf(Resolution which, const std::function<void(const TLeafVoxel&)>& visit) const
{
	const octomap::OcTree* t = tree(which);
	if (!t) return;
	// The region policy's low tree holds no region space: nothing to hide.
	const bool overlapFiltered = which == Resolution::High && m_policy->policy() == SwitchPolicy::Paper;
	forEachVisibleLeaf(*t, overlapFiltered ? m_low.get() : nullptr, visit);
}

std::optional<CDualOctoMap::TRayHit> CDualOctoMap::castRay(
	const mrpt::math::TPoint3D& origin, const mrpt::math::TPoint3D& direction, double maxRange) const
{
	const double n = direction.norm();
	if (!(n > 0) || !(maxRange > 0)) return std::nullopt;
	const mrpt::math::TPoint3D u = direction * (1.0 / n);
	const double step = 0.5 * (m_high ? m_creation.high.resolution : m_creation.low.resolution);
	for (double s = 0; s <= maxRange; s += step)
	{
		const auto p = origin + u * s;
		const auto q = query(p);
		if (q.state != OccupancyState::Occupied) continue;
		const auto& t = q.tree == Resolution::High ? *m_high : *m_low;
		return TRayHit{detail::toTPoint(t.keyToCoord(t.coordToKey(p.x, p.y, p.z))), q.tree, q.resolution};
	}
	return std::nullopt;
}

std::optional<mrpt::math::TBoundingBox> CDualOctoMap::knownSpaceBoundingBox() const
{
	std::optional<mrpt::math::TBoundingBox> box;
	auto grow = [&](const TLeafVoxel& v)
	{
		const double h = 0.5 * v.size;
		const mrpt::math::TBoundingBox b(
			v.center - mrpt::math::TPoint3D(h, h, h), v.center + mrpt::math::TPoint3D(h, h, h));
		box = box ? box->unionWith(b) : b;
	};
	forEachLeaf(Resolution::Low, grow);
	forEachLeaf(Resolution::High, grow);
	return box;
}

bool CDualOctoMap::inCameraView(const mrpt::math::TBoundingBox& box, const mrpt::obs::CObservation3DRangeScan& scan,
	const mrpt::poses::CPose3D& sensorPose) const
{
	const auto p = sensorPose.inverseComposePoint((box.min + box.max) * 0.5);
	return p.x <= m_creation.low.maxRange && io::DepthCamera::of(scan).project(p).has_value();
}

CDualOctoMap::TTreeStats CDualOctoMap::statsOf(Resolution which) const
{
	TTreeStats s;
	s.resolution = which == Resolution::Low ? m_creation.low.resolution : m_creation.high.resolution;
	const octomap::OcTree* t = tree(which);
	if (!t) return s;
	forEachLeaf(which, [&](const TLeafVoxel& v) { (v.occupied ? s.occupiedLeaves : s.freeLeaves)++; });
	s.memoryBytes = t->memoryUsage();
	// The sketch is the low tree's: where in its voxels the surface was.
	if (which == Resolution::Low) s.memoryBytes += m_sketch->memoryBytes();
	s.binaryBytes = binaryTreeBytes(*t).size();
	return s;
}

CDualOctoMap::TTreeStats CDualOctoMap::lowResolutionStats() const { return statsOf(Resolution::Low); }
CDualOctoMap::TTreeStats CDualOctoMap::highResolutionStats() const { return statsOf(Resolution::High); }

std::string CDualOctoMap::asString() const
{
	std::ostringstream s;
	s << "CAdaptiveOctoMap: policy " << toString(m_policy->policy()) << ", low " << m_creation.low.resolution << " m ("
	  << m_low->size() << " nodes), high " << m_creation.high.resolution << " m (" << (m_high ? m_high->size() : 0)
	  << " nodes), " << m_policy->regions().size() << " regions, " << m_insertions << " insertions";
	return s.str();
}
