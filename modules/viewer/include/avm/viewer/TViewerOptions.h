// Options of the live view (avm-map --gui, avm-view).
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <string>

namespace avm::io
{
template <class Options>
class IniKeys;  // avm/io/IniKeys.h
}

namespace avm::viewer
{
/** Keys `gui` and `gui_fps` of a section (avm-map: [pipeline]). */
struct TViewerOptions : public mrpt::config::CLoadableOptions
{
	bool enabled = false;  //!< `gui`: open the live view
	double fps = 5.0;  //!< `gui_fps` [Hz] most redraws a second, (0, 60]
	/** @name Not loaded: set by the program
	 * @{ */
	unsigned width = 1024, height = 768;  //!< [px] the 3D window
	std::string title = "avm";	//!< window title (and its prefix for the image window)
	/** @} */

	/** The loaded keys: name, member, unit, description, check. */
	static io::IniKeys<TViewerOptions> iniKeys();
	/** Throws std::invalid_argument "[section] key = value: why" on a value
	 *  that is not a bool / number or out of range. */
	void loadFromConfigFile(const mrpt::config::CConfigFileBase& source, const std::string& section) override;
	void saveToConfigFile(mrpt::config::CConfigFileBase& target, const std::string& section) const override;
	void validate(const std::string& section) const;
};
}  // namespace avm::viewer
