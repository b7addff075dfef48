// person_shapes.ply: each person's last shape (PersonTrack::shape), the file a
// user opens beside the map: an ASCII PLY point cloud (MeshLab, CloudCompare,
// MRPT's CPointCloudColoured::loadFromPlyFile), one vertex per voxel of the
// high-resolution tree, world frame [m], in the person colour, with the
// person's id (persons.csv's) as the vertex property `person`.
#pragma once

#include <mrpt/img/TColor.h>
#include <mrpt/math/TPoint3D.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "avm/persons/PersonTracker.h"

namespace avm::persons
{
/** The text of person_shapes.ply: the tracks' shapes in the order of id, each
 *  point coloured `colour`. */
std::string personShapesPlyText(const std::vector<PersonTrack>& tracks, const mrpt::img::TColor& colour);

/** One person's shape as person_shapes.ply holds it. */
struct PersonShape
{
	std::uint32_t id = 0;      //!< the person's id in persons.csv
	mrpt::img::TColor colour;  //!< of the person's first point
	std::vector<mrpt::math::TPoint3Df> points;
};

/** The shapes of a person_shapes.ply as personShapesPlyText() writes it, one
 *  per person in the order of the file. (MRPT's PLY reader,
 *  CPointCloudColoured::loadFromPlyFile, keeps the points and colours but not
 *  the `person` property.) Throws std::runtime_error naming the file, and
 *  the line, when it is not such a file. */
std::vector<PersonShape> readPersonShapesPly(const std::filesystem::path& file);
}  // namespace avm::persons
