// Options structs read from a user's ini file: values read as what they are
// (MRPT's read_int/read_double turn "abc" or an empty value into 0 without a
// word, which a range check then reports as a wrong number), and the keys
// they do not know reported: a key an options struct does not write back
// when saved is a key it does not read (a typo, or a key of another version).
#pragma once

#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CLoadableOptions.h>

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "avm/io/ErrorMessage.h"

namespace avm::io
{
/** `text`, the value of [section] key, as T (bool, int, unsigned, std::int64_t,
 *  double). An empty value, a value that is not a number (for bool: not true,
 *  false, yes, no, 1 or 0), a fraction for an integer and a number T cannot
 *  hold each throw std::invalid_argument "[section] key = text: <which>". */
template <class T>
T parseIniValue(const std::string& section, const std::string& key, const std::string& text);

/** The text of [section] key of `ini`; nothing when the key is absent. */
inline std::optional<std::string> readIniText(
	const mrpt::config::CConfigFileBase& ini, const std::string& section, const std::string& key)
{
	// read_string with a sentinel, not keyExists: the same (case-insensitive)
	// lookup as MRPT's readers.
	static const std::string absent = std::string(1, '\x01') + "absent";
	std::string text = ini.read_string(section, key, absent);
	if (text == absent) return std::nullopt;
	return text;
}

/** [section] key of `ini` as T (see parseIniValue), or `def` when absent. */
template <class T>
T readIniValue(
	const mrpt::config::CConfigFileBase& ini, const std::string& section, const std::string& key, const T& def)
{
	const auto text = readIniText(ini, section, key);
	return text ? parseIniValue<T>(section, key, *text) : def;
}

/** Keys present in [section] of ini that `options` does not know (MRPT reads
 *  keys without regard to case, so this compares without it too); the old
 *  name of a renamed key is known (warnRenamedKey speaks of it). */
std::vector<std::string> unknownKeys(const mrpt::config::CConfigFileBase& ini, const std::string& section,
	const mrpt::config::CLoadableOptions& options);

/** What every avm program says of a key that no options struct reads:
 *  "unknown key [section] key (ignored)". */
std::string unknownKeyWarning(const std::string& section, const std::string& key);

/** Tells stderr that [section] `oldKey` is now `key`: read as that, or, when
 *  `keyPresent`, ignored. */
void warnRenamedKey(const std::string& section, const std::string& oldKey, const std::string& key, bool keyPresent);

/** Options of type T from [section] of an ini file; keys T does not know go
 *  to `unknown`. Throws std::runtime_error when the file or section is missing,
 *  std::invalid_argument "<file>: [section] key = value: why" on a bad value. */
template <class T>
T loadOptionsFromFile(const std::filesystem::path& ini, const std::string& section, std::vector<std::string>& unknown)
{
	if (!std::filesystem::is_regular_file(ini)) throw std::runtime_error(ini.string() + ": config file not found");
	const mrpt::config::CConfigFile cfg(ini.string());
	if (!cfg.sectionExists(section)) throw std::runtime_error(ini.string() + ": no section [" + section + "]");
	T options;
	unknown = unknownKeys(cfg, section, options);
	namingIniFile(ini.string(), [&] { options.loadFromConfigFile(cfg, section); });
	return options;
}
}  // namespace avm::io
