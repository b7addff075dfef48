// Error messages as avm programs print them: one line, and an error about an
// ini key named with the file (or --set) it came from.
#pragma once

#include <exception>
#include <sstream>
#include <stdexcept>
#include <string>

namespace avm::io
{
/** The error of a bad ini value, worded as every options struct words it:
 *  std::invalid_argument "[section] key = value: why" (what
 *  rethrowNamingIniSource recognises). */
std::invalid_argument iniValueError(
	const std::string& section, const std::string& key, const std::string& value, const std::string& why);

/** The same for a value read as a number or bool (written as a stream writes it). */
template <class T>
std::invalid_argument iniValueError(
	const std::string& section, const std::string& key, const T& value, const std::string& why)
{
	std::ostringstream text;
	text << std::boolalpha << value;
	return iniValueError(section, key, text.str(), why);
}

/** The message of an error on one line: without the call stack and the
 *  "file:line: [function]" location MRPT's wrappers add (MRPT_END,
 *  THROW_EXCEPTION), line breaks joined. */
std::string errorMessage(const std::exception& e);

/** For a catch block: an error about an ini key (a message "[section] key =
 *  value: why", the convention of every options struct) is thrown again as
 *  std::invalid_argument "<source>: [section] key = value: why", the
 *  original nested in it for --verbose; any other error goes on unchanged. */
[[noreturn]] void rethrowNamingIniSource(const std::string& source, const std::exception& e);

/** Runs `load`, which reads options from the ini `file`, naming the file in
 *  an error about one of its keys (see rethrowNamingIniSource). */
template <class F>
decltype(auto) namingIniFile(const std::string& file, F&& load)
{
	try
	{
		return load();
	}
	catch (const std::exception& e)
	{
		rethrowNamingIniSource(file, e);
	}
}
}  // namespace avm::io
