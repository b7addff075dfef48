// Streams an MRPT rawlog (either format: action/sensory-frame pairs, or a plain
// sequence of observations) as RGB-D frames. A CObservationRobotPose with the
// timestamp of a CObservation3DRangeScan, just before or after it, is taken as
// that frame's ground-truth camera pose.
#pragma once

#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/COutputLogger.h>

#include <deque>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "avm/io/RawlogEntryReader.h"
#include "avm/io/RgbdFrame.h"

namespace avm::io
{
class RawlogFrameReader : public mrpt::system::COutputLogger
{
   public:
	/** Opens the rawlog. Its external images are read from MRPT's
	 *  process-wide images folder, which the program points at this rawlog's
	 *  (useImagesFolderOf in avm/io/ProgramMain.h) before the first frame.
	 *  Throws std::runtime_error naming the file if it is missing or unreadable. */
	explicit RawlogFrameReader(const std::filesystem::path& rawlog);
	/** loadImages = false: frames come with their external images unloaded
	 *  (and unchecked), for a quick pass over the rawlog. */
	RawlogFrameReader(const std::filesystem::path& rawlog, bool loadImages);
	~RawlogFrameReader() override;
	RawlogFrameReader(const RawlogFrameReader&) = delete;
	RawlogFrameReader& operator=(const RawlogFrameReader&) = delete;

	/** The next frame, or nothing at the end of the rawlog. A frame whose
	 *  images cannot be loaded is skipped with a warning (see skipped()).
	 *  Throws std::runtime_error naming the file and entry on corrupt or
	 *  truncated data, and naming the folder when the external images folder
	 *  is missing altogether; std::logic_error when MRPT's images folder is not
	 *  this rawlog's. */
	std::optional<RgbdFrame> next();

	/** Frames left out so far, one message each (index, file, reason). */
	const std::vector<std::string>& skipped() const { return m_skipped; }
	const std::filesystem::path& path() const { return m_path; }
	const std::filesystem::path& imagesDirectory() const { return m_imagesDir; }
	/** Fraction of the file read so far, 0..1 (by compressed bytes). */
	double progress() const { return m_entries.progress(); }

   private:
	/** Next observation of the stream, flattening sensory frames. */
	mrpt::obs::CObservation::Ptr nextObservation();
	mrpt::obs::CObservation::Ptr peekObservation();
	bool readEntry();

	std::filesystem::path m_path, m_imagesDir;
	RawlogEntryReader m_entries;
	std::deque<mrpt::obs::CObservation::Ptr> m_pending;
	bool m_loadImages = true;
	std::size_t m_frames = 0;
	std::vector<std::string> m_skipped;
};

/** The folder of a rawlog's external images: `<name>_Images`, `_images`,
 *  `_IMAGES` or `Images` beside it, the names MRPT's
 *  CRawlog::detectImagesDirectory tries (`<name>_Images` when none exists). */
std::filesystem::path imagesDirectoryOf(const std::filesystem::path& rawlog);

/** Appends a frame to a rawlog as RawlogFrameReader reads it back: the
 *  observation, then its ground-truth camera pose, if any, as a
 *  CObservationRobotPose labelled GROUND_TRUTH with the same timestamp. */
void writeFrame(mrpt::serialization::CArchive& out, const mrpt::obs::CObservation3DRangeScan& observation,
	const std::optional<mrpt::poses::CPose3D>& groundTruth);

/** Number of RGB-D frames in a rawlog (reads it through, images not loaded). */
std::size_t countFrames(const std::filesystem::path& rawlog);
}  // namespace avm::io
