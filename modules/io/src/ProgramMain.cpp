#include "avm/io/ProgramMain.h"

#include <mrpt/img/CImage.h>
#include <mrpt/system/progress.h>
#include <unistd.h>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <iostream>
#include <stdexcept>

#include "avm/io/RawlogFrameReader.h"

namespace avm::io
{
namespace
{
/** Thrown by CommandLine::parse after --help or --version: the program is
 *  done, successfully. Not a std::exception, so that no error handler of a
 *  program's body takes it for one. */
struct ActionDone
{
};

/** The errors nested in `e` (rethrowNamingIniSource nests the original,
 *  with MRPT's call stack), innermost last: what --verbose adds. */
void printNested(std::ostream& out, const std::exception& e)
{
	try
	{
		std::rethrow_if_nested(e);
	}
	catch (const std::exception& inner)
	{
		out << "caused by: " << inner.what() << "\n";
		printNested(out, inner);
	}
	catch (...)
	{
	}
}

/** Lets glibc's malloc keep the blocks a program frees for its next
 *  allocations. Every frame allocates and frees the same large buffers
 *  (ORB's image pyramid, the detector's blobs, the depth images, 0.3-2 MB
 *  each); by default glibc maps each block above 128 KB afresh and returns
 *  the freed top of the heap, so the kernel zero-fills those pages again on
 *  every frame (about 570 page faults a frame in avm-map). What memory holds is
 *  unchanged, so the outputs are too. A live view (viewer::MapView) puts
 *  glibc's defaults back: there memory comes first. */
void keepFreedBlocksForReuse()
{
#if defined(__GLIBC__)
	mallopt(M_MMAP_THRESHOLD, 32 << 20);   // glibc's largest: blocks below 32 MB come from the heap
	mallopt(M_TRIM_THRESHOLD, 512 << 20);  // the heap's free top is returned beyond 512 MB only
#endif
}
}  // namespace

/** One line for a bad argument, instead of TCLAP's message and usage dump. */
class CommandLine::Output : public TCLAP::StdOutput
{
   public:
	explicit Output(std::string programName) : m_programName(std::move(programName)) {}

	void failure(TCLAP::CmdLineInterface& cmd, TCLAP::ArgException& e) override
	{
		std::string what = e.error();
		// TCLAP says only "One or more required arguments missing!": name them.
		if (what.rfind("One or more required arguments missing", 0) == 0)
		{
			what = "missing required argument";
			std::string sep = " ";
			for (const TCLAP::Arg* a : cmd.getArgList())
				if (a->isRequired() && !a->isSet())
				{
					what += sep + a->shortID();
					sep = ", ";
				}
		}
		else
		{
			while (!what.empty() && (what.back() == '!' || what.back() == '.')) what.pop_back();
			// argId() is "Argument: -c (--config)", or " (--name)" without a short flag.
			if (std::string id = e.argId(); id.rfind("Argument: ", 0) == 0)
			{
				id = id.substr(id.find_first_not_of(' ', 10));
				if (id.front() == '(' && id.back() == ')') id = id.substr(1, id.size() - 2);
				what = id + ": " + what;
			}
		}
		throw std::invalid_argument(what + " (see " + m_programName + " --help)");
	}

	const std::string& programName() const { return m_programName; }

   private:
	std::string m_programName;
};

CommandLine::CommandLine(const std::string& programName, const std::string& description)
	: TCLAP::CmdLine(description, ' ', versionString()),
	  m_output(std::make_unique<Output>(programName)),
	  m_verbose("", "verbose", "on an error, also print its details (MRPT's call stack)", *this)
{
	// MRPT's TCLAP setOutput() forgets the StdOutput its constructor made.
	delete _output;
	setOutput(m_output.get());
}

CommandLine::~CommandLine() = default;

void CommandLine::rejectUnknownOptions(int argc, const char** argv)
{
	// TCLAP hands an unknown "--option" to an unlabeled argument as its value
	// ("avm-eval --typo" reads a trajectory named --typo); a word that looks
	// like an option must be one. Values of options (e.g. --max-dt -1) and
	// everything after "--" are left alone.
	const auto find = [&](const std::string& word) -> const TCLAP::Arg*
	{
		for (const TCLAP::Arg* a : getArgList())
			if ((word.rfind("--", 0) == 0 && word.substr(2) == a->getName()) ||
				(!a->getFlag().empty() && word == "-" + a->getFlag()))
				return a;
		return nullptr;
	};
	for (int i = 1; i < argc; ++i)
	{
		const std::string word = argv[i];
		if (word == "--") break;
		if (word.size() < 2 || word[0] != '-' || std::isdigit(static_cast<unsigned char>(word[1])) || word[1] == '.')
			continue;
		if (const TCLAP::Arg* a = find(word.substr(0, word.find('='))))
		{
			if (a->isValueRequired() && word.find('=') == std::string::npos) ++i;
			continue;
		}
		// Short switches may be combined ("-qv").
		bool switches = word[1] != '-';
		for (std::size_t c = 1; switches && c < word.size(); ++c)
			switches = find(std::string("-") + word[c]) != nullptr;
		if (!switches)
			throw std::invalid_argument(word + ": unknown argument (see " + m_output->programName() + " --help)");
	}
}

bool CommandLine::parse(int argc, const char** argv)
{
	rejectUnknownOptions(argc, argv);
	// Output::failure throws on a bad argument, so false means --help or --version.
	if (!TCLAP::CmdLine::parse(argc, argv)) throw ActionDone{};
	return true;
}

void useImagesFolderOf(const std::filesystem::path& rawlog)
{
	mrpt::img::CImage::setImagesPathBase(imagesDirectoryOf(rawlog).string());
}

int runProgram(const std::string& name, const std::string& description, const std::function<int(CommandLine&)>& body)
{
	keepFreedBlocksForReuse();
	CommandLine cmd(name, description);
	try
	{
		return body(cmd);
	}
	catch (const ActionDone&)
	{
		return 0;
	}
	catch (const std::exception& e)
	{
		const std::string line = errorMessage(e);
		std::cerr << name << ": error: " << line << "\n";
		if (cmd.verbose())
		{
			if (e.what() != line) std::cerr << e.what() << "\n";
			printNested(std::cerr, e);
		}
	}
	return 1;
}

ProgressBar::ProgressBar(bool quiet) : m_quiet(quiet), m_terminal(::isatty(STDERR_FILENO) != 0) {}

ProgressBar::~ProgressBar()
{
	if (m_lineOpen) std::fputc('\n', stderr);
}

void ProgressBar::show(double fraction, const std::string& text)
{
	const bool done = fraction >= 1;
	if (m_quiet || (!m_terminal && !done)) return;
	std::fprintf(stderr, "\r%s%s%s", mrpt::system::progress(std::min(fraction, 1.0), 30).c_str(),
		text.empty() ? "" : " ", text.c_str());
	m_lineOpen = !done;
	if (done) std::fputc('\n', stderr);
	std::fflush(stderr);
}
}  // namespace avm::io
