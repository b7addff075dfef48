#include "avm/io/AtomicFile.h"

#include <unistd.h>

#include <stdexcept>
#include <string>

namespace avm::io
{
namespace fs = std::filesystem;

fs::path temporaryPathFor(const fs::path& target)
{
	const std::string name = "." + target.stem().string() + ".partial-" +
							 std::to_string(::getpid()) + target.extension().string();
	return target.parent_path() / name;
}

void writeFileAtomically(const fs::path& target, const std::function<void(const fs::path&)>& write)
{
	const fs::path tmp = temporaryPathFor(target);
	try
	{
		write(tmp);
		if (!fs::exists(tmp)) throw std::runtime_error("nothing was written to " + target.string());
		fs::rename(tmp, target);
	}
	catch (...)
	{
		std::error_code ignored;
		fs::remove(tmp, ignored);
		throw;
	}
}
}  // namespace avm::io
