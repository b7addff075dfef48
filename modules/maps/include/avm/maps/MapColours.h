// The colours of the adaptive map's trees and regions, wherever the map is
// drawn in 3D: map.3Dscene and MRPT's viewers (CDualOctoMap_render.cpp)
// and avm's live view (modules/viewer), so that both show a tree alike; and of
// the camera path, which the pictures (map_top.png, map_perspective.png) and
// the live view draw alike.
#pragma once

#include <mrpt/img/TColor.h>

namespace avm
{
inline const mrpt::img::TColor kLowColour(70, 110, 200), kHighColour(235, 90, 30);
inline const mrpt::img::TColor kLowFreeColour(150, 170, 220, 40), kHighFreeColour(250, 190, 150, 40);
inline const mrpt::img::TColor kRegionColour(40, 200, 60);
inline const mrpt::img::TColor kTrajectoryColour(20, 20, 20);
}  // namespace avm
