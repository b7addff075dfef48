#include "avm/io/AtomicFile.h"

#include <fcntl.h>
#include <unistd.h>

#include <stdexcept>
#include <string>

namespace avm::io
{
namespace fs = std::filesystem;

fs::path temporaryPathFor(const fs::path& target)
{
	const std::string name =
		"." + target.stem().string() + ".partial-" + std::to_string(::getpid()) + target.extension().string();
	return target.parent_path() / name;
}

namespace
{
/** Flushes a file (or folder) to the disk: without it, a power loss soon
 *  after the rename can leave the new name on an empty file. */
void syncToDisk(const fs::path& path, int flags)
{
	const int fd = ::open(path.c_str(), flags);
	if (fd < 0) return;  // nothing to flush through (the rename still stands)
	::fsync(fd);
	::close(fd);
}
}  // namespace

void writeFileAtomically(const fs::path& target, const std::function<void(const fs::path&)>& write)
{
	const fs::path tmp = temporaryPathFor(target);
	try
	{
		write(tmp);
		if (!fs::exists(tmp)) throw std::runtime_error("nothing was written to " + target.string());
		syncToDisk(tmp, O_RDONLY);
		fs::rename(tmp, target);
		syncToDisk(target.parent_path().empty() ? fs::path(".") : target.parent_path(), O_RDONLY | O_DIRECTORY);
	}
	catch (...)
	{
		std::error_code ignored;
		fs::remove(tmp, ignored);
		throw;
	}
}
}  // namespace avm::io
