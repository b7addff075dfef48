// Options structs read from a user's ini file, with the keys they do not
// know reported: a key an options struct does not write back when saved is a
// key it does not read (a typo, or a key of another version).
#pragma once

#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CLoadableOptions.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace avm::io
{
/** Keys present in [section] of ini that `options` does not know (MRPT reads
 *  keys without regard to case, so this compares without it too). */
std::vector<std::string> unknownKeys(
	const mrpt::config::CConfigFileBase& ini, const std::string& section,
	const mrpt::config::CLoadableOptions& options);

/** Options of type T from [section] of an ini file; keys T does not know go
 *  to `unknown`. Throws std::runtime_error when the file or section is missing,
 *  std::invalid_argument (prefixed with the file name) on a bad value. */
template <class T>
T loadOptionsFromFile(const std::filesystem::path& ini, const std::string& section, std::vector<std::string>& unknown)
{
	if (!std::filesystem::is_regular_file(ini)) throw std::runtime_error(ini.string() + ": config file not found");
	const mrpt::config::CConfigFile cfg(ini.string());
	if (!cfg.sectionExists(section)) throw std::runtime_error(ini.string() + ": no section [" + section + "]");
	T options;
	unknown = unknownKeys(cfg, section, options);
	try
	{
		options.loadFromConfigFile(cfg, section);
	}
	catch (const std::invalid_argument& e)
	{
		throw std::invalid_argument(ini.string() + ": " + e.what());
	}
	return options;
}
}  // namespace avm::io
