// Any bytes as a serialized avm::CAdaptiveOctoMap: read, or rejected with an
// exception; never a crash. What was read must serialize again.
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>

#include "avm/plugin/CAdaptiveOctoMap.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	mrpt::io::CMemoryStream in;
	in.assignMemoryNotOwn(data, size);
	avm::CAdaptiveOctoMap map;
	try
	{
		auto archive = mrpt::serialization::archiveFrom(in);
		archive.ReadObject(&map);
	}
	catch (const std::exception&)
	{
		return 0;
	}
	mrpt::io::CMemoryStream out;
	auto archive = mrpt::serialization::archiveFrom(out);
	archive << map;
	return 0;
}
