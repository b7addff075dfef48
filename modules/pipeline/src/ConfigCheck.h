// Unknown keys in a user's ini: a key an options struct does not write back
// when saved is a key it does not read (typos, keys of another version).
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CLoadableOptions.h>

#include <string>
#include <vector>

namespace avm::pipeline
{
/** Keys present in [section] of ini that `options` does not know. */
std::vector<std::string> unknownKeys(
	const mrpt::config::CConfigFileBase& ini, const std::string& section,
	const mrpt::config::CLoadableOptions& options);
}  // namespace avm::pipeline
