#include "avm/io/RawlogFrameReader.h"

#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace avm::io
{
namespace fs = std::filesystem;
using namespace mrpt::obs;

/** The rawlog file with one byte of look-ahead, so that the end of the data is
 *  seen before an entry is read: an entry that then fails to read is damage,
 *  never the normal end. */
class RawlogFrameReader::PeekableFile : public mrpt::io::CStream
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

namespace
{
// Ground truth and depth are written with the same timestamp; allow for
// rounding by other writers.
constexpr double kSameTimeTolerance = 1e-3;  // [s]

bool sameTime(const CObservation& a, const CObservation& b)
{
	return std::abs(mrpt::Clock::toDouble(a.timestamp) - mrpt::Clock::toDouble(b.timestamp)) <
		   kSameTimeTolerance;
}

bool hasExternalImages(const CObservation3DRangeScan& scan)
{
	return (scan.hasIntensityImage && scan.intensityImage.isExternallyStored()) ||
		   (scan.hasRangeImage && scan.rangeImage_isExternallyStored());
}

/** Whether MRPT's process-wide images folder is `dir` (or a link to it). */
bool mrptReadsImagesFrom(const fs::path& dir)
{
	const fs::path base = mrpt::img::CImage::getImagesPathBase();
	std::error_code ignored;
	return base == dir || fs::equivalent(base, dir, ignored);
}
}  // namespace

fs::path imagesDirectoryOf(const fs::path& rawlog)
{
	// MRPT 2.5.8's CRawlog::detectImagesDirectory drops the path separator
	// of absolute paths ("/a/bImages").
	const fs::path dir = rawlog.parent_path();
	const std::string stem = rawlog.stem().string();
	for (const std::string& name : {stem + "_Images", stem + "_images", stem + "_IMAGES", std::string("Images")})
		if (fs::is_directory(dir / name)) return dir / name;
	return dir / (stem + "_Images");
}

RawlogFrameReader::RawlogFrameReader(const fs::path& rawlog) : RawlogFrameReader(rawlog, true) {}

RawlogFrameReader::RawlogFrameReader(const fs::path& rawlog, bool loadImages)
	: mrpt::system::COutputLogger("RawlogFrameReader"), m_path(rawlog), m_loadImages(loadImages)
{
	if (!fs::exists(rawlog)) throw std::runtime_error(rawlog.string() + ": rawlog not found");
	if (fs::is_directory(rawlog)) throw std::runtime_error(rawlog.string() + ": is a folder, not a rawlog");
	m_file = std::make_unique<PeekableFile>(rawlog);
	m_archive = std::make_unique<mrpt::serialization::CArchiveStreamBase<PeekableFile>>(*m_file);
	m_imagesDir = imagesDirectoryOf(rawlog);
}

RawlogFrameReader::~RawlogFrameReader() = default;

bool RawlogFrameReader::readEntry()
{
	if (m_file->atEnd()) return false;
	mrpt::serialization::CSerializable::Ptr obj;
	try
	{
		obj = m_archive->ReadObject();
	}
	catch (const std::exception& e)
	{
		throw std::runtime_error(
			m_path.string() + ": corrupt or truncated rawlog at entry " + std::to_string(m_entries) +
			" (" + std::string(e.what()).substr(0, 300) + ")");
	}
	++m_entries;
	if (auto obs = std::dynamic_pointer_cast<CObservation>(obj))
		m_pending.push_back(obs);
	else if (auto sf = std::dynamic_pointer_cast<CSensoryFrame>(obj))
		for (const auto& o : *sf) m_pending.push_back(o);
	// Actions (odometry increments) carry nothing avm uses.
	return true;
}

CObservation::Ptr RawlogFrameReader::peekObservation()
{
	while (m_pending.empty())
		if (!readEntry()) return {};
	return m_pending.front();
}

CObservation::Ptr RawlogFrameReader::nextObservation()
{
	auto obs = peekObservation();
	if (obs) m_pending.pop_front();
	return obs;
}

std::optional<RgbdFrame> RawlogFrameReader::next()
{
	CObservationRobotPose::Ptr lastPose;
	while (auto obs = nextObservation())
	{
		if (auto pose = std::dynamic_pointer_cast<CObservationRobotPose>(obs))
		{
			lastPose = pose;
			continue;
		}
		auto scan = std::dynamic_pointer_cast<CObservation3DRangeScan>(obs);
		if (!scan) continue;

		RgbdFrame frame;
		frame.index = m_frames++;
		frame.observation = scan;
		if (auto after = std::dynamic_pointer_cast<CObservationRobotPose>(peekObservation());
			after && sameTime(*after, *scan))
			lastPose = std::dynamic_pointer_cast<CObservationRobotPose>(nextObservation());
		if (lastPose && sameTime(*lastPose, *scan))
		{
			const auto p = lastPose->pose.getMeanVal();
			if (isFinite(p))
				frame.groundTruth = p;
			else
				logFmt(mrpt::system::LVL_WARN, "frame %zu: ground-truth pose is not finite, ignored\n", frame.index);
		}
		lastPose.reset();

		if (!m_loadImages) return frame;
		// Another rawlog's folder could hold files of the same names.
		if (hasExternalImages(*scan) && !mrptReadsImagesFrom(m_imagesDir))
			throw std::logic_error(
				m_path.string() + ": its external images are in " + m_imagesDir.string() +
				" but MRPT reads them from " + mrpt::img::CImage::getImagesPathBase() +
				" (the program must call io::useImagesFolderOf first)");
		try
		{
			scan->load();
			if (scan->hasIntensityImage) scan->intensityImage.forceLoad();
		}
		catch (const std::exception& e)
		{
			// One missing image costs one frame; a missing folder costs them all.
			if (scan->hasIntensityImage && scan->intensityImage.isExternallyStored() &&
				!fs::is_directory(m_imagesDir))
				throw std::runtime_error(
					m_path.string() + ": external images folder " + m_imagesDir.string() + " not found");
			const std::string why = "frame " + std::to_string(frame.index) + " skipped: " +
									std::string(e.what()).substr(0, 300);
			m_skipped.push_back(why);
			logStr(mrpt::system::LVL_WARN, why + "\n");
			continue;
		}
		if (!scan->hasRangeImage)
		{
			m_skipped.push_back("frame " + std::to_string(frame.index) + " skipped: no depth image");
			continue;
		}
		return frame;
	}
	return {};
}

double RawlogFrameReader::progress() const
{
	const auto total = m_file->getTotalBytesCount();
	return total ? std::min(1.0, double(m_file->getPosition()) / double(total)) : 1.0;
}

std::size_t countFrames(const fs::path& rawlog)
{
	RawlogFrameReader reader(rawlog, false);
	std::size_t n = 0;
	while (reader.next()) ++n;
	return n;
}
}  // namespace avm::io
