// ini/default.ini as shipped, with the detector model of ../shared: the
// pipeline tests do not depend on scripts/get-data.sh having been run.
#pragma once

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/vector_loadsave.h>

#include <filesystem>

#include "TestData.h"

namespace avm::test
{
inline mrpt::config::CConfigFileMemory defaultIni()
{
	mrpt::config::CConfigFileMemory ini;
	ini.setContent(mrpt::io::file_get_contents((std::filesystem::path(AVM_SOURCE_DIR) / "ini/default.ini").string()));
	ini.write("detection", "model", sharedFile("models/yolox_nano.onnx").string());
	return ini;
}
}  // namespace avm::test
