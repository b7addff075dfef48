// What the detection tests share: the default model's options and running
// the avm-detect executable.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "TestData.h"
#include "avm/detection/TDetectorOptions.h"

namespace avm::test
{
/** Default options with the shared YOLOX-Nano model. */
inline detection::TDetectorOptions yoloxOptions()
{
	detection::TDetectorOptions o;
	o.model = sharedFile("models/yolox_nano.onnx").string();
	return o;
}

/** The avm-detect argument selecting the shared YOLOX-Nano model. */
inline std::string yoloxModelArgument() { return "--model " + sharedFile("models/yolox_nano.onnx").string(); }

struct AppRun
{
	int exitCode = -1;
	std::string out, err;
};

/** Runs avm-detect with `args` (shell syntax), capturing its output in `dir`. */
inline AppRun runAvmDetect(const std::string& args, const std::filesystem::path& dir)
{
	const auto out = dir / "stdout.txt", err = dir / "stderr.txt";
	const std::string cmd = binary("avm-detect").string() + " " + args + " >" + out.string() + " 2>" + err.string();
	const int status = std::system(cmd.c_str());
	return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, mrpt::io::file_get_contents(out.string()),
		mrpt::io::file_get_contents(err.string())};
}
}  // namespace avm::test
