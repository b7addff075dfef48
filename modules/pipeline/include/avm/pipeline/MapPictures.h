// PNG pictures of a finished map, drawn offscreen with OpenCV so that a person
// sees the result without a 3D viewer (and without a GL context on the
// machine): a top view and a perspective view of the occupied voxels coloured
// by resolution, with the camera trajectory, the high-resolution regions and
// the persons seen (id at their last position, their last shape).
// World z is taken as up.
#pragma once

#include <mrpt/math/TBoundingBox.h>
#include <mrpt/math/TPoint3D.h>

#include <cstdint>
#include <filesystem>
#include <vector>

#include "avm/io/Trajectory.h"

namespace avm::pipeline
{
struct PictureVoxel
{
	mrpt::math::TPoint3Df centre;
	float size = 0;  //!< edge [m]
	bool highResolution = false;
};

struct PicturePerson
{
	std::uint32_t id = 0;
	mrpt::math::TPoint3D position;  //!< last world position
	/** Last shape: voxel centres at the high resolution (PersonTrack::shape). */
	std::vector<mrpt::math::TPoint3Df> shape;
};

struct MapPictureContent
{
	std::vector<PictureVoxel> voxels;
	io::Trajectory trajectory;
	std::vector<mrpt::math::TBoundingBox> regions;
	std::vector<PicturePerson> persons;
	double lowResolution = 0, highResolution = 0;  //!< [m], for the legend
};

/** Orthographic view from above (world XY), written atomically. */
void drawTopView(const MapPictureContent& content, const std::filesystem::path& png, int sizePx);

/** A view from above and behind the start of the trajectory, looking at the
 *  map's centre; voxels are drawn far to near. Written atomically. */
void drawPerspectiveView(const MapPictureContent& content, const std::filesystem::path& png, int sizePx);
}  // namespace avm::pipeline
