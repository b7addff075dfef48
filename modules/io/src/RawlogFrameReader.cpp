#include "avm/io/RawlogFrameReader.h"

#include <mrpt/img/CImage.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace avm::io
{
namespace fs = std::filesystem;
using namespace mrpt::obs;

namespace
{
// Ground truth and depth are written with the same timestamp; allow for
// rounding by other writers.
constexpr double kSameTimeTolerance = 1e-3;  // [s]

bool sameTime(const CObservation& a, const CObservation& b)
{
	return std::abs(mrpt::Clock::toDouble(a.timestamp) - mrpt::Clock::toDouble(b.timestamp)) < kSameTimeTolerance;
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
	: mrpt::system::COutputLogger("RawlogFrameReader"),
	  m_path(rawlog),
	  m_imagesDir(imagesDirectoryOf(rawlog)),
	  m_entries(rawlog),
	  m_loadImages(loadImages)
{
}

RawlogFrameReader::~RawlogFrameReader() = default;

bool RawlogFrameReader::readEntry()
{
	const auto obj = m_entries.next();
	if (!obj) return false;
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
			throw std::logic_error(m_path.string() + ": its external images are in " + m_imagesDir.string() +
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
			if (scan->hasIntensityImage && scan->intensityImage.isExternallyStored() && !fs::is_directory(m_imagesDir))
				throw std::runtime_error(
					m_path.string() + ": external images folder " + m_imagesDir.string() + " not found");
			const std::string why =
				"frame " + std::to_string(frame.index) + " skipped: " + std::string(e.what()).substr(0, 300);
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

std::size_t countFrames(const fs::path& rawlog)
{
	RawlogFrameReader reader(rawlog, false);
	std::size_t n = 0;
	while (reader.next()) ++n;
	return n;
}
void writeFrame(mrpt::serialization::CArchive& out, const mrpt::obs::CObservation3DRangeScan& observation,
	const std::optional<mrpt::poses::CPose3D>& groundTruth)
{
	out << observation;
	if (!groundTruth) return;
	auto gt = mrpt::obs::CObservationRobotPose::Create();
	gt->sensorLabel = "GROUND_TRUTH";
	gt->timestamp = observation.timestamp;
	gt->pose = mrpt::poses::CPose3DPDFGaussian(*groundTruth);
	out << *gt;
}
}  // namespace avm::io
