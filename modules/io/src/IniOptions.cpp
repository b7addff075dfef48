#include "avm/io/IniOptions.h"

#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <cctype>

namespace avm::io
{
std::vector<std::string> unknownKeys(
	const mrpt::config::CConfigFileBase& ini, const std::string& section,
	const mrpt::config::CLoadableOptions& options)
{
	mrpt::config::CConfigFileMemory known;
	options.saveToConfigFile(known, section);
	std::vector<std::string> knownKeys, present, unknown;
	known.getAllKeys(section, knownKeys);
	ini.getAllKeys(section, present);
	// MRPT reads ini keys without regard to case.
	const auto lower = [](std::string s) {
		std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
		return s;
	};
	for (auto& k : knownKeys) k = lower(k);
	for (const auto& k : present)
		if (std::find(knownKeys.begin(), knownKeys.end(), lower(k)) == knownKeys.end()) unknown.push_back(k);
	return unknown;
}
}  // namespace avm::io
