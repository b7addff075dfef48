#include "avm/viewer/TViewerOptions.h"

#include <mrpt/config/CConfigFileBase.h>

#include <cmath>

#include "avm/io/ErrorMessage.h"
#include "avm/io/IniOptions.h"

namespace avm::viewer
{
void TViewerOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& source, const std::string& section)
{
	enabled = io::readIniValue(source, section, "gui", enabled);
	fps = io::readIniValue(source, section, "gui_fps", fps);
	validate(section);
}

void TViewerOptions::saveToConfigFile(mrpt::config::CConfigFileBase& target, const std::string& section) const
{
	target.write(section, "gui", enabled);
	target.write(section, "gui_fps", fps);
}

void TViewerOptions::validate(const std::string& section) const
{
	if (!(std::isfinite(fps) && fps > 0 && fps <= 60))
		throw io::iniValueError(section, "gui_fps", fps, "out of range (0, 60]");
}
}  // namespace avm::viewer
