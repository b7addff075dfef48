// Any text as an MRPT ini defining the adaptive map: the map is created, or
// the options are rejected with an exception naming the key; never a crash.
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CMultiMetricMap.h>

#include <string>

#include "avm/plugin/CAdaptiveOctoMap.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	try
	{
		const mrpt::config::CConfigFileMemory ini(std::string(reinterpret_cast<const char*>(data), size));
		mrpt::maps::TSetOfMetricMapInitializers definition;
		definition.loadFromConfigFile(ini, "map");
		const auto maps = mrpt::maps::CMultiMetricMap::Create(definition);
		if (const auto map = maps->mapByClass<avm::CAdaptiveOctoMap>()) map->highResolutionStats();
	}
	catch (const std::exception&)
	{
	}
	return 0;
}
