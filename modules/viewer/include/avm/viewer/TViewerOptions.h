// Options of the live view (avm-map --gui, avm-view).
#pragma once

#include <string>

#include "avm/io/IniKeyOptions.h"

namespace avm::viewer
{
/** Keys `gui` and `gui_fps` of a section (avm-map: [pipeline]). */
struct TViewerOptions : public io::CIniKeyOptions<TViewerOptions>
{
	bool enabled = false;  //!< `gui`: open the live view
	double fps = 5.0;      //!< `gui_fps` [Hz] most redraws a second, (0, 60]
	/** @name Not loaded: set by the program
	 * @{ */
	unsigned width = 1024, height = 768;  //!< [px] the 3D window
	std::string title = "avm";            //!< window title (and its prefix for the image window)
	/** @} */

	/** The loaded keys: name, member, unit, description, check. */
	static io::IniKeys<TViewerOptions> iniKeys();
};
}  // namespace avm::viewer
