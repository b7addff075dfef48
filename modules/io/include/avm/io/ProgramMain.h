// The shell every avm program shares: whatever escapes the program's body
// (a TCLAP argument error, any std::exception) becomes one line on stderr,
// prefixed with the program's name, and exit status 1.
#pragma once

#include <functional>

namespace avm::io
{
/** Runs `body` and returns its exit status, or 1 after reporting what it threw. */
int runProgram(const char* name, const std::function<int()>& body);
}  // namespace avm::io
