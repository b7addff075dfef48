#include "avm/viewer/TViewerOptions.h"

#include <mrpt/config/CConfigFileBase.h>

#include "avm/io/IniKeys.h"

namespace avm::viewer
{
io::IniKeys<TViewerOptions> TViewerOptions::iniKeys()
{
	io::IniKeys<TViewerOptions> keys;
	keys.number("gui", &TViewerOptions::enabled, "",
			"open the live 3D view (MRPT windows; avm-map --gui sets it); closing it ends the run as Ctrl-C does")
		.number("gui_fps", &TViewerOptions::fps, "Hz",
			"most redraws, and map snapshots, a second with gui = true, (0, 60]",
			{[](double v) { return v > 0 && v <= 60; }, "out of range (0, 60]"});
	return keys;
}
}  // namespace avm::viewer

template struct avm::io::CIniKeyOptions<avm::viewer::TViewerOptions>;
