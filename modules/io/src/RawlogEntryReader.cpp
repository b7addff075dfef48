#include "avm/io/RawlogEntryReader.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace avm::io
{
namespace fs = std::filesystem;

/** The rawlog file with one byte of look-ahead, so that the end of the data is
 *  seen before an entry is read: an entry that then fails to read is damage,
 *  never the normal end. */
class RawlogEntryReader::PeekableFile : public mrpt::io::CStream
{
   public:
	explicit PeekableFile(const fs::path& file)
	{
		if (!m_file.open(file.string())) throw std::runtime_error(file.string() + ": cannot open rawlog");
	}
	bool atEnd()
	{
		if (m_peeked) return false;
		m_peeked = m_file.Read(&m_byte, 1) == 1;
		return !m_peeked;
	}
	size_t Read(void* buffer, size_t count) override
	{
		if (count == 0) return 0;
		auto* out = static_cast<uint8_t*>(buffer);
		size_t n = 0;
		if (m_peeked)
		{
			*out++ = m_byte;
			m_peeked = false;
			n = 1;
		}
		return n + m_file.Read(out, count - n);
	}
	size_t Write(const void*, size_t) override { throw std::logic_error("rawlog opened for reading"); }
	uint64_t Seek(int64_t, TSeekOrigin) override { throw std::logic_error("rawlog stream cannot seek"); }
	uint64_t getTotalBytesCount() const override { return m_file.getTotalBytesCount(); }
	uint64_t getPosition() const override { return m_file.getPosition(); }

   private:
	mrpt::io::CFileGZInputStream m_file;
	uint8_t m_byte = 0;
	bool m_peeked = false;
};

RawlogEntryReader::RawlogEntryReader(const fs::path& rawlog) : m_path(rawlog)
{
	if (!fs::exists(rawlog)) throw std::runtime_error(rawlog.string() + ": rawlog not found");
	if (fs::is_directory(rawlog)) throw std::runtime_error(rawlog.string() + ": is a folder, not a rawlog");
	m_file = std::make_unique<PeekableFile>(rawlog);
	m_archive = std::make_unique<mrpt::serialization::CArchiveStreamBase<PeekableFile>>(*m_file);
}

RawlogEntryReader::~RawlogEntryReader() = default;

mrpt::serialization::CSerializable::Ptr RawlogEntryReader::next()
{
	if (m_file->atEnd()) return {};
	mrpt::serialization::CSerializable::Ptr obj;
	try
	{
		obj = m_archive->ReadObject();
	}
	catch (const std::exception& e)
	{
		throw std::runtime_error(m_path.string() + ": corrupt or truncated rawlog at entry " +
								 std::to_string(m_entries) + " (" + std::string(e.what()).substr(0, 300) + ")");
	}
	// A stored null would read as the end of the data.
	if (!obj) throw std::runtime_error(m_path.string() + ": empty object at entry " + std::to_string(m_entries));
	++m_entries;
	return obj;
}

double RawlogEntryReader::progress() const
{
	const auto total = m_file->getTotalBytesCount();
	return total ? std::min(1.0, double(m_file->getPosition()) / double(total)) : 1.0;
}
}  // namespace avm::io
