// The shell every avm program shares. runProgram hands the program's body a
// TCLAP command line to declare its arguments on and parse; --help and
// --version end the program there with status 0, and whatever escapes the
// body (a bad argument, any std::exception, MRPT's call-stack wrappers
// included) becomes one line on stderr, "<program>: error: <message>", and
// exit status 1. --verbose adds the error's details (MRPT's call stack).
#pragma once

#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "avm/io/ErrorMessage.h"

namespace avm::io
{
/** The project's version: CMake's project(VERSION), plus "(git <commit>)"
 *  when built from a checkout ("-dirty" when tracked files had changes). */
std::string versionString();

/** A TCLAP command line with the conventions of every avm program: the
 *  version is versionString(), --verbose is declared, and a bad argument
 *  throws one line (naming the argument) instead of TCLAP's usage dump. */
class CommandLine : public TCLAP::CmdLine
{
   public:
	CommandLine(const std::string& programName, const std::string& description);
	~CommandLine() override;

	using TCLAP::CmdLine::parse;
	/** TCLAP's parse. MRPT's TCLAP returns false after printing --help or
	 *  --version and lets the program go on; this throws instead, what
	 *  runProgram turns into exit status 0. */
	bool parse(int argc, const char** argv) override;

	bool verbose() { return m_verbose.getValue(); }

   private:
	/** Throws on a word that looks like an option but is none of ours. */
	void rejectUnknownOptions(int argc, const char** argv);

	class Output;
	std::unique_ptr<Output> m_output;
	TCLAP::SwitchArg m_verbose;
};

/** Points MRPT's process-wide folder of external images
 *  (CImage::setImagesPathBase) at the rawlog's (imagesDirectoryOf), which
 *  reading its frames needs. Process-wide state is the program's to set, so
 *  mains call this, never a library. */
void useImagesFolderOf(const std::filesystem::path& rawlog);

/** Runs `body` with the program's command line and returns its exit status:
 *  0 after --help or --version, 1 after reporting what it threw. First it
 *  sets glibc's malloc to keep freed blocks for reuse (a frame's large
 *  buffers are freed and allocated again every frame). */
int runProgram(const std::string& name, const std::string& description, const std::function<int(CommandLine&)>& body);

/** The progress bar of every avm program, on stderr: redrawn in place in a
 *  terminal; in a log, drawn once, when the work is done, so the log keeps
 *  the totals without a line per step. A quiet bar draws nothing. */
class ProgressBar
{
   public:
	explicit ProgressBar(bool quiet);
	/** Ends the bar's line if the work stopped before it was done. */
	~ProgressBar();
	ProgressBar(const ProgressBar&) = delete;
	ProgressBar& operator=(const ProgressBar&) = delete;

	/** `fraction` of the work done (1: all, which ends the line), then `text`. */
	void show(double fraction, const std::string& text = {});

   private:
	bool m_quiet, m_terminal;
	bool m_lineOpen = false;
};

}  // namespace avm::io
