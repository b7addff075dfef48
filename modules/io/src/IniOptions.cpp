#include "avm/io/IniOptions.h"

#include "avm/io/IniKeyOptions.h"

#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <optional>
#include <string_view>
#include <type_traits>

namespace avm::io
{
namespace
{
std::string lower(std::string s)
{
	std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
	return s;
}

std::string trim(const std::string& s)
{
	const auto b = s.find_first_not_of(" \t\r\n");
	if (b == std::string::npos) return {};
	return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

/** The whole of `text` as a T, nothing when any of it is not (from_chars:
 *  no locale, no hexadecimal, no leading '+' of its own). */
template <class T>
std::optional<T> whole(std::string_view text, std::errc& error)
{
	if (text.size() > 1 && text[0] == '+' && text[1] != '-') text.remove_prefix(1);
	T v{};
	const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
	error = r.ec;
	if (r.ec != std::errc() || r.ptr != text.data() + text.size()) return {};
	return v;
}

[[noreturn]] void reject(
	const std::string& section, const std::string& key, const std::string& text, const std::string& why)
{
	throw iniValueError(section, key, text, why);
}

template <class T>
std::string rangeOf()
{
	return std::to_string(std::numeric_limits<T>::min()) + ".." + std::to_string(std::numeric_limits<T>::max());
}
}  // namespace

template <class T>
T parseIniValue(const std::string& section, const std::string& key, const std::string& raw)
{
	const std::string text = trim(raw);
	if constexpr (std::is_same_v<T, bool>)
	{
		if (text.empty()) reject(section, key, "\"\"", "empty value, true or false needed");
		// The words MRPT's read_bool knows; anything else it reads as false.
		const std::string w = lower(text);
		if (w == "true" || w == "yes" || w == "1") return true;
		if (w == "false" || w == "no" || w == "0") return false;
		reject(section, key, text, "not true or false");
	}
	else
	{
		if (text.empty()) reject(section, key, "\"\"", "empty value, a number needed");
		std::errc error{};
		// A plain whole number, the usual integer, in one exact parse.
		if constexpr (std::is_integral_v<T>)
			if (const auto v = whole<T>(text, error)) return *v;
		const bool beyondT = error == std::errc::result_out_of_range;
		const auto real = whole<double>(text, error);
		if (error == std::errc::result_out_of_range) reject(section, key, text, "out of range of a number");
		if (!real || !std::isfinite(*real)) reject(section, key, text, "not a number");
		if constexpr (std::is_floating_point_v<T>)
			return static_cast<T>(*real);
		else
		{
			// Anything else whole is written as a real number (1e3).
			if (*real != std::floor(*real)) reject(section, key, text, "not a whole number");
			if (beyondT || *real < double(std::numeric_limits<T>::min()) ||
				*real > double(std::numeric_limits<T>::max()))
				reject(section, key, text, "out of range (" + rangeOf<T>() + ")");
			return static_cast<T>(*real);
		}
	}
}

template bool parseIniValue<bool>(const std::string&, const std::string&, const std::string&);
template int parseIniValue<int>(const std::string&, const std::string&, const std::string&);
template unsigned parseIniValue<unsigned>(const std::string&, const std::string&, const std::string&);
template std::int64_t parseIniValue<std::int64_t>(const std::string&, const std::string&, const std::string&);
template double parseIniValue<double>(const std::string&, const std::string&, const std::string&);

std::vector<std::string> unknownKeys(
	const mrpt::config::CConfigFileBase& ini, const std::string& section, const mrpt::config::CLoadableOptions& options)
{
	mrpt::config::CConfigFileMemory known;
	options.saveToConfigFile(known, section);
	std::vector<std::string> knownKeys, present, unknown;
	known.getAllKeys(section, knownKeys);
	if (const auto* keyed = dynamic_cast<const CIniKeyNames*>(&options))
		for (const auto& old : keyed->oldKeyNames()) knownKeys.push_back(old);
	ini.getAllKeys(section, present);
	// MRPT reads ini keys without regard to case.
	for (auto& k : knownKeys) k = lower(k);
	for (const auto& k : present)
		if (std::find(knownKeys.begin(), knownKeys.end(), lower(k)) == knownKeys.end()) unknown.push_back(k);
	return unknown;
}

std::string unknownKeyWarning(const std::string& section, const std::string& key)
{
	return "unknown key [" + section + "] " + key + " (ignored)";
}

void warnRenamedKey(const std::string& section, const std::string& oldKey, const std::string& key, bool keyPresent)
{
	std::cerr << "warning: [" << section << "] " << oldKey << " is now called " << key
			  << (keyPresent ? ", which is set too: " + oldKey + " ignored" : ": read as " + key + "; rename it")
			  << "\n";
}
}  // namespace avm::io
