#include "avm/io/ErrorMessage.h"

#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <cctype>
#include <stdexcept>

namespace avm::io
{
namespace
{
/** MRPT's THROW_EXCEPTION message is "file:line: [function] message"; the
 *  message alone, or `text` when it has no such location. */
std::string withoutLocation(const std::string& text)
{
	const auto colon = text.find(':');
	if (colon == std::string::npos || colon == 0) return text;
	std::size_t i = colon + 1;
	const std::size_t digits = i;
	while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]))) ++i;
	if (i == digits || text.compare(i, 3, ": [") != 0) return text;
	// The function's signature may hold brackets of its own (operator[]).
	int depth = 0;
	for (i += 2; i < text.size(); ++i)
	{
		if (text[i] == '[') ++depth;
		if (text[i] == ']' && --depth == 0) break;
	}
	if (i >= text.size()) return text;
	return text.substr(text.compare(i + 1, 1, " ") == 0 ? i + 2 : i + 1);
}

/** The non-empty lines of `text`, trimmed, joined with "; ". */
std::string oneLine(const std::string& text)
{
	std::string out;
	std::size_t start = 0;
	while (start <= text.size())
	{
		const auto end = std::min(text.find('\n', start), text.size());
		const auto b = text.find_first_not_of(" \t\r", start);
		if (b < end)
		{
			const auto e = text.find_last_not_of(" \t\r", end - 1);
			out += (out.empty() ? "" : "; ") + text.substr(b, e - b + 1);
		}
		start = end + 1;
	}
	return out;
}

}  // namespace

std::invalid_argument iniValueError(
	const std::string& section, const std::string& key, const std::string& value, const std::string& why)
{
	return std::invalid_argument("[" + section + "] " + key + " = " + value + ": " + why);
}

std::string errorMessage(const std::exception& e)
{
	// MRPT_END wraps an error in ExceptionWithCallBack<std::exception>, whose
	// what() is a report with the call stack and a location cut at the first
	// ']' (so "[section] key" loses its section); the wrapped error's own text
	// is kept in originalWhat.
	if (const auto* wrapped = dynamic_cast<const mrpt::ExceptionWithCallBackBase*>(&e))
		return oneLine(withoutLocation(wrapped->originalWhat));
	return oneLine(e.what());
}

void rethrowNamingIniSource(const std::string& source, const std::exception& e)
{
	const std::string message = errorMessage(e);
	if (message.rfind('[', 0) == 0) std::throw_with_nested(std::invalid_argument(source + ": " + message));
	throw;
}
}  // namespace avm::io
