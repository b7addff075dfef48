// Fuzz inputs as files: the parsers under test read from paths.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace avm::fuzz
{
/** A temporary file holding the input, removed when this goes out of scope. */
class InputFile
{
   public:
	InputFile(const uint8_t* data, size_t size, const std::string& extension)
		: m_path(std::filesystem::temp_directory_path() / ("avm-fuzz-" + std::to_string(::getpid()) + extension))
	{
		std::ofstream(m_path, std::ios::binary).write(reinterpret_cast<const char*>(data), size);
	}
	~InputFile()
	{
		std::error_code ignored;
		std::filesystem::remove(m_path, ignored);
	}
	InputFile(const InputFile&) = delete;
	InputFile& operator=(const InputFile&) = delete;
	const std::filesystem::path& path() const { return m_path; }

   private:
	std::filesystem::path m_path;
};
}  // namespace avm::fuzz
