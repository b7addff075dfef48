// person_shapes.ply: each person's last shape (PersonTrack::shape), the file a
// user opens beside the map: an ASCII PLY point cloud (MeshLab, CloudCompare,
// MRPT's CPointCloudColoured::loadFromPlyFile), one vertex per voxel of the
// high-resolution tree, world frame [m], in the person colour, with the
// person's id (persons.csv's) as the vertex property `person`.
#pragma once

#include <mrpt/img/TColor.h>

#include <string>
#include <vector>

#include "avm/persons/PersonTracker.h"

namespace avm::persons
{
/** The text of person_shapes.ply: the tracks' shapes in the order of id, each
 *  point coloured `colour`. */
std::string personShapesPlyText(const std::vector<PersonTrack>& tracks, const mrpt::img::TColor& colour);
}  // namespace avm::persons
