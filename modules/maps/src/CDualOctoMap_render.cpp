// What MRPT viewers show: both trees as voxels in distinct colours (only
// stock MRPT OpenGL classes, so a .3Dscene opens without the plugin), and
// the occupied voxel centres as a points map.
#include <mrpt/opengl/CBox.h>
#include <mrpt/opengl/CText3D.h>
#include <mrpt/opengl/COctoMapVoxels.h>
#include <mrpt/opengl/CSetOfObjects.h>

#include "ResolutionPolicy.h"
#include "avm/maps/CDualOctoMap.h"
#include "avm/maps/MapColours.h"

using namespace avm;

namespace
{
// Voxel sets of the COctoMapVoxels object.
enum VoxelSet : std::size_t
{
	LowOccupied,
	HighOccupied,
	LowFree,
	HighFree,
	VoxelSetCount
};
}  // namespace

void CDualOctoMap::getVisualizationInto(mrpt::opengl::CSetOfObjects& outObj) const
{
	if (!genericMapParams.enableSaveAs3DObject) return;
	auto voxels = mrpt::opengl::COctoMapVoxels::Create();
	voxels->resizeVoxelSets(VoxelSetCount);
	auto add = [&](Resolution which)
	{
		const bool high = which == Resolution::High;
		forEachLeaf(which,
			[&](const TLeafVoxel& v)
			{
				if (v.occupied)
					voxels->push_back_Voxel(high ? HighOccupied : LowOccupied,
						mrpt::opengl::COctoMapVoxels::TVoxel(v.center, v.size, high ? kHighColour : kLowColour));
				else if (renderingOptions.showFreeSpace)
					voxels->push_back_Voxel(
						high ? HighFree : LowFree, mrpt::opengl::COctoMapVoxels::TVoxel(
													   v.center, v.size, high ? kHighFreeColour : kLowFreeColour));
			});
	};
	add(Resolution::Low);
	add(Resolution::High);
	if (const auto box = knownSpaceBoundingBox()) voxels->setBoundingBox(box->min, box->max);
	voxels->showGridLines(false);
	voxels->enableCubeTransparency(renderingOptions.showFreeSpace);
	outObj.insert(voxels);

	if (!renderingOptions.showRegions) return;
	for (const auto& r : m_policy->regions())
	{
		for (const auto& b : r.boxes)
		{
			auto box = mrpt::opengl::CBox::Create(b.min, b.max, true /*wireframe*/);
			box->setColor_u8(kRegionColour);
			outObj.insert(box);
		}
		if (r.regionId == 0 || r.boxes.empty()) continue;
		const auto& latest = r.boxes.back();
		auto label = mrpt::opengl::CText3D::Create(regionLabel(r.regionId), "sans", 0.15);
		label->setLocation((latest.min.x + latest.max.x) / 2, (latest.min.y + latest.max.y) / 2, latest.max.z);
		label->setColor_u8(kRegionColour);
		outObj.insert(label);
	}
}

const mrpt::maps::CSimplePointsMap* CDualOctoMap::getAsSimplePointsMap() const
{
	if (m_pointsCacheValid) return &m_pointsCache;
	m_pointsCache.clear();
	auto add = [&](const TLeafVoxel& v)
	{
		if (v.occupied) m_pointsCache.insertPoint(v.center);
	};
	forEachLeaf(Resolution::Low, add);
	forEachLeaf(Resolution::High, add);
	m_pointsCacheValid = true;
	return &m_pointsCache;
}
