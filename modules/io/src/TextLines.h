// The line-oriented text files of the TUM layout: '#' comments and blank lines
// are skipped, errors name the file and line.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace avm::io::detail
{
[[noreturn]] inline void failAt(const std::filesystem::path& file, std::size_t line, const std::string& what)
{
	throw std::runtime_error(file.string() + ":" + std::to_string(line) + ": " + what);
}

/** Calls onLine(stream, lineNo) for every line that is not blank or a comment. */
template <typename OnLine>
void forEachDataLine(const std::filesystem::path& file, OnLine onLine)
{
	std::ifstream in(file);
	if (!in) throw std::runtime_error(file.string() + ": cannot open");
	std::string text;
	std::size_t lineNo = 0;
	while (std::getline(in, text))
	{
		++lineNo;
		const auto first = text.find_first_not_of(" \t\r");
		if (first == std::string::npos || text[first] == '#') continue;
		std::istringstream ss(text);
		onLine(ss, lineNo);
	}
}
}  // namespace avm::io::detail
