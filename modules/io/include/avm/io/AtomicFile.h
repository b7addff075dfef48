// Outputs are written to a temporary file beside the target, flushed to the
// disk and renamed into place when complete, so a reader, a killed process or
// a power loss never sees half a file.
#pragma once

#include <filesystem>
#include <functional>

namespace avm::io
{
/** Calls `write(tmp)` with a temporary path in the target's folder (same
 *  extension, so writers that look at it still work), then renames it onto
 *  `target`. If `write` throws or leaves no file, the temporary is removed, the
 *  previous `target` (if any) is kept, and the exception goes on. */
void writeFileAtomically(
	const std::filesystem::path& target, const std::function<void(const std::filesystem::path& tmp)>& write);

/** The temporary name writeFileAtomically() uses for `target`. */
std::filesystem::path temporaryPathFor(const std::filesystem::path& target);
}  // namespace avm::io
