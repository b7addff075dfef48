#include "avm/detection/RawlogDetection.h"

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "avm/detection/PersonLabels.h"
#include "avm/io/AtomicFile.h"
#include "avm/io/RawlogEntryReader.h"
#include "avm/io/RawlogFrameReader.h"
#include "avm/io/RgbdFrame.h"

namespace avm::detection
{
namespace fs = std::filesystem;
using mrpt::obs::CObservation3DRangeScan;

namespace
{
/** Points `link` at `target` unless it already is that folder. Returns
 *  whether a link was made (so it can be removed on failure). */
bool linkImagesFolder(const fs::path& target, const fs::path& link)
{
	if (fs::exists(link) || fs::is_symlink(link))
	{
		if (fs::exists(link) && fs::equivalent(link, target)) return false;
		throw std::runtime_error(link.string() + ": exists and is not the input's images folder " + target.string() +
								 " (remove it or choose another output name)");
	}
	fs::create_directory_symlink(fs::absolute(target), link);
	return true;
}

/** Calls fn on every entry of a rawlog, in order. Throws naming the file on a
 *  missing, corrupt or truncated rawlog. */
void forEachEntry(const fs::path& rawlog, const std::function<void(mrpt::serialization::CSerializable&)>& fn)
{
	io::RawlogEntryReader entries(rawlog);
	while (const auto obj = entries.next()) fn(*obj);
}

/** The RGB-D observations of a rawlog entry (itself, or inside a sensory frame). */
std::vector<CObservation3DRangeScan*> rgbdObservations(mrpt::serialization::CSerializable& obj)
{
	std::vector<CObservation3DRangeScan*> scans;
	if (auto* scan = dynamic_cast<CObservation3DRangeScan*>(&obj))
		scans.push_back(scan);
	else if (auto* sf = dynamic_cast<mrpt::obs::CSensoryFrame*>(&obj))
		for (auto& o : *sf)
			if (auto* s = dynamic_cast<CObservation3DRangeScan*>(o.get())) scans.push_back(s);
	return scans;
}

class LabellingPass
{
   public:
	LabellingPass(DetectorBase& d, std::size_t every, LabelRawlogSummary& s)
		: m_detector(d), m_every(every), m_summary(s)
	{
	}

	void process(CObservation3DRangeScan& obs)
	{
		const std::size_t index = m_summary.frames++;
		if (index % m_every != 0) return;
		try
		{
			obs.load();
			if (obs.hasIntensityImage) obs.intensityImage.forceLoad();
			const cv::Mat bgr = io::colourImage(obs);
			if (!obs.hasRangeImage) throw std::runtime_error("no depth image");
			// Boxes found in the colour image are used as depth pixels.
			if (bgr.cols != obs.rangeImage.cols() || bgr.rows != obs.rangeImage.rows())
				throw std::runtime_error("colour and depth images differ in size (not registered)");
			const auto detections = m_detector.detect(bgr);
			writePersonLabels(obs, detections);
			const cv::Size size(bgr.cols, bgr.rows);
			const auto persons = personsOnly(detections);
			++m_summary.detectedFrames;
			m_summary.persons += persons.size();
			if (!persons.empty()) ++m_summary.framesWithPerson;
			for (const auto& d : detections)
			{
				// The depth the map's sighting estimator (default options) finds.
				const auto z = persons::estimateSighting(obs, {}, personPixels(d, size), {}).sighting;
				char line[64];
				std::snprintf(line, sizeof(line), "%zu %.6f ", index, mrpt::Clock::toDouble(obs.timestamp));
				m_lines << line << formatDetection(d) << " " << (z ? std::to_string(z->depth) : std::string("nan"))
						<< "\n";
			}
		}
		catch (const std::exception& e)
		{
			m_summary.skipped.push_back(
				"frame " + std::to_string(index) + " not labelled: " + std::string(e.what()).substr(0, 300));
		}
		obs.unload();  // external images are re-read from disk if needed; the rawlog keeps only their names
	}

	std::string text() const { return m_lines.str(); }

   private:
	DetectorBase& m_detector;
	std::size_t m_every;
	LabelRawlogSummary& m_summary;
	std::ostringstream m_lines;
};
}  // namespace

std::string formatDetection(const Detection& d)
{
	char buf[160];
	std::snprintf(buf, sizeof(buf), "%s %.3f %.1f %.1f %.1f %.1f", d.className.c_str(), d.score, d.box.x, d.box.y,
		d.box.width, d.box.height);
	std::string s = buf;
	std::replace(s.begin(), s.begin() + static_cast<long>(d.className.size()), ' ', '_');  // "traffic light"
	return s;
}

LabelRawlogSummary labelRawlog(DetectorBase& detector, const fs::path& in, const fs::path& out, std::size_t every,
	const std::function<void(double)>& progress)
{
	if (every == 0) throw std::invalid_argument("detection interval must be >= 1 frame");
	// A first pass finds a missing or damaged input before anything is
	// written, and counts the frames for the progress bar.
	std::size_t total = 0;
	forEachEntry(in, [&](mrpt::serialization::CSerializable& obj) { total += rgbdObservations(obj).size(); });
	if (fs::exists(out) && fs::equivalent(in, out))
		throw std::runtime_error(out.string() + ": the output would overwrite the input rawlog");
	if (!out.parent_path().empty()) fs::create_directories(out.parent_path());

	LabelRawlogSummary summary;
	summary.rawlog = out;
	summary.detectionsFile = out.parent_path() / (out.stem().string() + "_detections.txt");
	const fs::path inImages = io::imagesDirectoryOf(in);
	const fs::path outImages = out.parent_path() / (out.stem().string() + "_Images");
	const bool linked = fs::is_directory(inImages) && linkImagesFolder(inImages, outImages);
	if (fs::is_directory(inImages)) summary.imagesDir = outImages;

	LabellingPass pass(detector, every, summary);
	try
	{
		io::writeFileAtomically(out,
			[&](const fs::path& tmp)
			{
				mrpt::io::CFileGZOutputStream outFile(tmp.string());
				auto writer = mrpt::serialization::archiveFrom(outFile);
				forEachEntry(in,
					[&](mrpt::serialization::CSerializable& obj)
					{
						const auto scans = rgbdObservations(obj);
						for (auto* scan : scans) pass.process(*scan);
						writer << obj;
						if (progress && !scans.empty())
							progress(double(summary.frames) / std::max<std::size_t>(1, total));
					});
			});
		const std::string header = "# avm-detect: " + detector.description() + "\n# input " + in.string() +
								   "\n# frame timestamp class score x y w h depth   (box [px] in the colour image; "
								   "depth [m] = robust person depth)\n";
		io::writeFileAtomically(summary.detectionsFile,
			[&](const fs::path& tmp)
			{
				std::FILE* f = std::fopen(tmp.c_str(), "w");
				if (!f) throw std::runtime_error(tmp.string() + ": cannot write");
				const std::string text = header + pass.text();
				const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
				if (std::fclose(f) != 0 || !ok)
					throw std::runtime_error(summary.detectionsFile.string() + ": write failed");
			});
	}
	catch (...)
	{
		if (linked)
		{
			std::error_code ignored;
			fs::remove(outImages, ignored);
		}
		throw;
	}
	return summary;
}

}  // namespace avm::detection
