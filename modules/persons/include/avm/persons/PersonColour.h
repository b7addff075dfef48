// The colour persons are drawn in, wherever they are: their last shapes in
// map.3Dscene and person_shapes.ply, the pictures (map_top.png,
// map_perspective.png) and the live view, beside the map's own colours
// (avm/maps/MapColours.h).
#pragma once

#include <mrpt/img/TColor.h>

namespace avm::persons
{
inline const mrpt::img::TColor kPersonColour(160, 0, 160);
}  // namespace avm::persons
