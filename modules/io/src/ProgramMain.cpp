#include "avm/io/ProgramMain.h"

#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <iostream>

namespace avm::io
{
int runProgram(const char* name, const std::function<int()>& body)
{
	try
	{
		return body();
	}
	catch (const TCLAP::ArgException& e)
	{
		std::cerr << name << ": " << e.error() << " for " << e.argId() << "\n";
	}
	catch (const std::exception& e)
	{
		std::cerr << name << ": error: " << e.what() << "\n";
	}
	return 1;
}
}  // namespace avm::io
