// Options of the live view (avm-map --gui, avm-view), set by the program
// (avm-map: from [pipeline] gui_fps).
#pragma once

#include <string>

namespace avm::viewer
{
struct TViewerOptions
{
	double fps = 5.0;                     //!< [Hz] most redraws a second, (0, 60]
	unsigned width = 1024, height = 768;  //!< [px] the 3D window
	std::string title = "avm";            //!< window title (and its prefix for the image window)
};
}  // namespace avm::viewer
