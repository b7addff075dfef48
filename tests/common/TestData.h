// Paths of the real data the tests run on. ../shared is read-only; whatever a
// test makes goes below build/test-data.
#pragma once

#include <gtest/gtest.h>
#include <mrpt/io/vector_loadsave.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "avm/io/ProgramMain.h"

namespace avm::test
{
/// The shared data folder: $AVM_SHARED_DIR when set, else ../shared beside the repo.
inline std::filesystem::path sharedDir()
{
	if (const char* env = std::getenv("AVM_SHARED_DIR"); env && *env) return env;
	return AVM_SHARED_DIR;
}
inline std::filesystem::path sharedFile(const std::string& relative)
{
	const auto p = sharedDir() / relative;
	if (!std::filesystem::exists(p))
		throw std::runtime_error("test data missing: " + p.string() +
								 " (the tests need ../shared beside the repository, or AVM_SHARED_DIR)");
	return p;
}
inline std::filesystem::path bonnDatasetDir() { return sharedFile("datasets/bonn_crowd_sub300"); }
/// The Bonn sequence converted by avm-tum2rawlog (ctest fixture "bonn_rawlog"),
/// with MRPT's folder of external images pointed at its images, as the
/// programs' mains do (io::useImagesFolderOf): nearly every test reads it.
inline std::filesystem::path bonnRawlog()
{
	const std::filesystem::path p = AVM_BONN_RAWLOG;
	if (!std::filesystem::exists(p))
		throw std::runtime_error("fixture rawlog missing: " + p.string() + " (run the whole ctest suite)");
	io::useImagesFolderOf(p);
	return p;
}
/// A whole file, byte for byte: for comparing two runs' outputs.
inline std::string fileBytes(const std::filesystem::path& file) { return mrpt::io::file_get_contents(file.string()); }
/// A fresh, empty folder for one test's outputs.
inline std::filesystem::path scratchDir(const std::string& name)
{
	const auto p = std::filesystem::path(AVM_TEST_DATA_DIR) / "scratch" / name;
	std::filesystem::remove_all(p);
	std::filesystem::create_directories(p);
	return p;
}
inline std::filesystem::path binary(const std::string& name) { return std::filesystem::path(AVM_BIN_DIR) / name; }

struct CommandResult
{
	int exitCode;        //!< -1 when the command did not exit normally
	std::string output;  //!< stdout and stderr together
};

/** Runs a shell command, its output captured through a file in `scratch`. */
inline CommandResult runCommand(const std::string& command, const std::filesystem::path& scratch)
{
	const auto log = scratch / "command-output.log";
	const int status = std::system((command + " > '" + log.string() + "' 2>&1").c_str());
	const std::string text = mrpt::io::file_get_contents(log.string());
	std::filesystem::remove(log);
	return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text};
}
}  // namespace avm::test
