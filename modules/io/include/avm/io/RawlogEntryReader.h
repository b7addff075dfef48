// The entries of an MRPT rawlog as stored (an observation, a sensory frame, an
// action collection), one at a time, in either format: the one loop over a
// rawlog's entries, for readers of frames (RawlogFrameReader) and for copies
// of a rawlog (avm-detect's labelled rawlog).
#pragma once

#include <mrpt/serialization/CSerializable.h>

#include <cstddef>
#include <filesystem>
#include <memory>

namespace mrpt::serialization
{
class CArchive;
}

namespace avm::io
{
class RawlogEntryReader
{
   public:
	/** Throws std::runtime_error naming the file if it is missing, a folder or
	 *  unreadable. */
	explicit RawlogEntryReader(const std::filesystem::path& rawlog);
	~RawlogEntryReader();
	RawlogEntryReader(const RawlogEntryReader&) = delete;
	RawlogEntryReader& operator=(const RawlogEntryReader&) = delete;

	/** The next entry, or nullptr at the end of the data. Throws
	 *  std::runtime_error naming the file and the entry on corrupt or
	 *  truncated data, never taking it for the end. */
	mrpt::serialization::CSerializable::Ptr next();

	/** Fraction of the file read so far, 0..1 (by compressed bytes). */
	double progress() const;

   private:
	std::filesystem::path m_path;
	class PeekableFile;
	std::unique_ptr<PeekableFile> m_file;
	std::unique_ptr<mrpt::serialization::CArchive> m_archive;
	std::size_t m_entries = 0;
};
}  // namespace avm::io
