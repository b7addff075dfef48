// Any byte string as a rawlog: the reader returns frames or throws
// std::runtime_error; it never crashes, hangs or leaks.
#include <stdexcept>

#include "FuzzInput.h"
#include "avm/io/ProgramMain.h"
#include "avm/io/RawlogFrameReader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	const avm::fuzz::InputFile file(data, size, ".rawlog");
	try
	{
		avm::io::useImagesFolderOf(file.path());
		avm::io::RawlogFrameReader reader(file.path());
		reader.setMinLoggingLevel(mrpt::system::LVL_ERROR);
		for (int frames = 0; frames < 16 && reader.next(); ++frames)
		{
		}
	}
	catch (const std::exception&)
	{
	}
	return 0;
}
