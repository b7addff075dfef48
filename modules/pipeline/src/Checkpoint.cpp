#include "Checkpoint.h"

#include <mrpt/io/CFileInputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdint>
#include <stdexcept>

#include "avm/io/AtomicFile.h"
#include "avm/io/ErrorMessage.h"
#include "avm/io/RunFolder.h"

namespace avm::pipeline
{
namespace fs = std::filesystem;
using mrpt::serialization::CArchive;

namespace
{
const std::string kMagic = "avm-checkpoint";
constexpr std::uint8_t kVersion = 1;

/** Reads a checkpoint's header and run; `rest(archive)` reads on. Any
 *  failure becomes one line naming the file, `what` the use it failed for. */
template <typename Rest>
CheckpointedRun readFile(const fs::path& file, const std::string& what, Rest rest)
{
	try
	{
		mrpt::io::CFileInputStream stream(file.string());
		auto in = mrpt::serialization::archiveFrom(stream);
		std::string magic;
		in >> magic;
		if (magic != kMagic) throw std::runtime_error("not an avm checkpoint");
		if (const auto version = in.ReadAs<std::uint8_t>(); version != kVersion)
			throw std::runtime_error(
				"checkpoint version " + std::to_string(version) + ", this avm reads " + std::to_string(kVersion));
		CheckpointedRun run;
		std::string rawlog;
		in >> run.ini >> rawlog;
		run.rawlog = rawlog;
		run.poseSource = in.ReadAs<std::uint8_t>() ? PoseSource::GroundTruth : PoseSource::VisualOdometry;
		rest(in);
		return run;
	}
	catch (const std::exception& e)
	{
		std::string why = io::errorMessage(e);
		// MRPT's words for a stream that ends inside a value.
		if (why.find("Cannot read requested number of bytes") != std::string::npos)
			why = "the file ends early (cut short while it was copied?)";
		throw std::runtime_error(file.string() + ": " + what + ": " + why);
	}
}

/** `file`, which must exist. */
const fs::path& existingCheckpoint(const fs::path& file)
{
	if (!fs::exists(file))
		throw std::runtime_error(file.string() +
								 ": no checkpoint (the run finished, which removes it, or was stopped before its "
								 "first frame, or " +
								 file.parent_path().string() + " is not an avm-map output folder)");
	return file;
}

constexpr const char* kCannotResume = "cannot resume from this checkpoint";
constexpr const char* kCannotContinue = "cannot continue from this session";
}  // namespace

CheckpointedRun detail::readCheckpointedRun(const fs::path& file)
{
	return readFile(existingCheckpoint(file), kCannotResume, [](CArchive&) {});
}

fs::path detail::sessionFile(const fs::path& previous)
{
	const io::RunFolder run(previous);
	if (!fs::is_directory(previous)) throw std::runtime_error(previous.string() + ": no such folder");
	if (fs::exists(run.session())) return run.session();
	if (fs::exists(run.checkpoint()))
		throw std::runtime_error(previous.string() +
								 ": the run was interrupted (it has a checkpoint, no session): finish it with "
								 "avm-map --resume " +
								 previous.string() + ", then continue it");
	throw std::runtime_error(run.session().string() + ": no session (" + previous.string() +
							 " is not the output folder of a finished avm-map run)");
}

CheckpointedRun readSessionRun(const fs::path& previous)
{
	return readFile(detail::sessionFile(previous), kCannotContinue, [](CArchive&) {});
}

namespace detail
{
void writeCheckpoint(const fs::path& file, const CheckpointedRun& run, const CheckpointProgress& progress,
	const mrpt::maps::CMultiMetricMap& maps, FrameProcessor& processor)
{
	io::writeFileAtomically(file,
		[&](const fs::path& tmp)
		{
			mrpt::io::CFileOutputStream stream;
			if (!stream.open(tmp.string())) throw std::runtime_error(tmp.string() + ": cannot write the checkpoint");
			auto out = mrpt::serialization::archiveFrom(stream);
			out << kMagic;
			out.WriteAs<std::uint8_t>(kVersion);
			out << run.ini << run.rawlog.string();
			out.WriteAs<std::uint8_t>(run.poseSource == PoseSource::GroundTruth);
			out << progress.seconds << progress.cpuSeconds << progress.log;
			// The processor first: it finishes the insertion in flight, which
			// writes to the maps.
			processor.saveState(out);
			out.WriteAs<std::uint64_t>(maps.maps.size());
			for (const auto& m : maps.maps) out << *m;
			out << kMagic;  // the end: a file cut short fails to read, not to resume
		});
}

CheckpointProgress readCheckpoint(const fs::path& file, mrpt::maps::CMultiMetricMap& maps, FrameProcessor& processor)
{
	return readState(existingCheckpoint(file), kCannotResume, maps, processor);
}

CheckpointProgress readSession(const fs::path& previous, mrpt::maps::CMultiMetricMap& maps, FrameProcessor& processor)
{
	return readState(sessionFile(previous), kCannotContinue, maps, processor);
}

CheckpointProgress readState(
	const fs::path& file, const std::string& what, mrpt::maps::CMultiMetricMap& maps, FrameProcessor& processor)
{
	CheckpointProgress progress;
	readFile(file, what,
		[&](CArchive& in)
		{
			in >> progress.seconds >> progress.cpuSeconds >> progress.log;
			processor.loadState(in);
			if (in.ReadAs<std::uint64_t>() != maps.maps.size())
				throw std::runtime_error("its maps are not those of the configuration's map definition");
			// Into the maps the configuration made: the processor holds references to them.
			for (auto& m : maps.maps) in >> *m;
			std::string end;
			in >> end;
			if (end != kMagic) throw std::runtime_error("the file ends early");
		});
	return progress;
}
}  // namespace detail
}  // namespace avm::pipeline
