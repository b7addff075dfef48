#include "avm/io/IniKeys.h"

#include <algorithm>
#include <charconv>

namespace avm::io
{
namespace
{
template <class T>
std::string shortest(T value)
{
	char text[64];
	const auto r = std::to_chars(text, text + sizeof(text), value);
	return std::string(text, r.ptr);
}
}  // namespace

std::string iniText(bool value) { return value ? "true" : "false"; }
std::string iniText(std::int64_t value) { return shortest(value); }
std::string iniText(std::uint64_t value) { return shortest(value); }
std::string iniText(double value) { return shortest(value); }

std::string IniKeyDoc::comment() const
{
	std::string text = description;
	if (!unit.empty()) text += " [" + unit + "]";
	return text + " (default " + (defaultText.empty() ? "\"\"" : defaultText) + ")";
}

std::string documentIniSection(const std::string& section, const std::vector<IniKeyDoc>& keys)
{
	std::size_t width = 0;
	for (const auto& k : keys) width = std::max(width, k.key.size() + 3 + k.defaultText.size());
	std::string text = "[" + section + "]\n";
	for (const auto& k : keys)
	{
		const std::string line = k.key + " = " + k.defaultText;
		text += line + std::string(width + 2 - line.size(), ' ') + "// " + k.comment() + "\n";
	}
	return text;
}
}  // namespace avm::io
