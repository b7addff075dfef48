#include "avm/io/TumToRawlog.h"

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/datetime.h>

#include <opencv2/imgcodecs.hpp>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "avm/io/AtomicFile.h"
#include "avm/io/RawlogFrameReader.h"
#include "avm/io/RgbdFrame.h"
#include "avm/io/Trajectory.h"

namespace avm::io
{
namespace fs = std::filesystem;

namespace
{
std::vector<RgbdPair> readPairs(const fs::path& dir, double maxDifference, std::vector<std::string>& skipped)
{
	if (!fs::is_directory(dir)) throw std::runtime_error(dir.string() + ": dataset folder not found");
	if (fs::exists(dir / "associations.txt")) return readAssociations(dir / "associations.txt");
	for (const char* list : {"rgb.txt", "depth.txt"})
		if (!fs::exists(dir / list))
			throw std::runtime_error(
				(dir / list).string() + ": not found (need associations.txt, or rgb.txt and depth.txt)");
	auto assoc = associateNearest(readTumFileList(dir / "rgb.txt"), readTumFileList(dir / "depth.txt"), maxDifference);
	skipped = std::move(assoc.skipped);
	return std::move(assoc.pairs);
}

cv::Mat readImage(const fs::path& file, int flags, int expectedType, const mrpt::img::TCamera& cam)
{
	if (!fs::exists(file)) throw std::runtime_error(file.string() + ": image not found");
	cv::Mat img = cv::imread(file.string(), flags);
	if (img.empty()) throw std::runtime_error(file.string() + ": unreadable image");
	if (img.type() != expectedType)
		throw std::runtime_error(
			file.string() +
			(expectedType == CV_16UC1 ? ": depth image is not 16-bit single channel" : ": colour image is not 8-bit"));
	if (img.cols != static_cast<int>(cam.ncols) || img.rows != static_cast<int>(cam.nrows))
	{
		std::ostringstream s;
		s << file.string() << ": image is " << img.cols << "x" << img.rows << ", the camera is " << cam.ncols << "x"
		  << cam.nrows;
		throw std::runtime_error(s.str());
	}
	return img;
}

mrpt::obs::CObservation3DRangeScan::Ptr makeObservation(const RgbdPair& pair, const fs::path& dir,
	const TumConversionOptions& opt, const std::optional<fs::path>& imagesDir)
{
	const auto& cam = opt.camera.intrinsics;
	const cv::Mat depth = readImage(dir / pair.depth.file, cv::IMREAD_ANYDEPTH, CV_16UC1, cam);
	const fs::path rgbFile = dir / pair.rgb.file;
	cv::Mat rgb = readImage(rgbFile, cv::IMREAD_COLOR, CV_8UC3, cam);

	auto obs = mrpt::obs::CObservation3DRangeScan::Create();
	obs->sensorLabel = "RGBD";
	obs->timestamp = mrpt::Clock::fromDouble(pair.depth.timestamp);
	obs->range_is_depth = true;
	obs->hasRangeImage = true;
	obs->rangeUnits = static_cast<float>(1.0 / opt.camera.depthFactor);
	obs->maxRange = static_cast<float>(65535.0 / opt.camera.depthFactor);
	obs->rangeImage.resize(depth.rows, depth.cols);
	for (int y = 0; y < depth.rows; ++y)
	{
		const auto* row = depth.ptr<uint16_t>(y);
		for (int x = 0; x < depth.cols; ++x) obs->rangeImage(y, x) = row[x];
	}
	// Registered pair: both images share one pinhole model and one position.
	obs->cameraParams = cam;
	obs->cameraParamsIntensity = cam;
	obs->relativePoseIntensityWRTDepth = opticalToSensorPose().getOppositeScalar();
	obs->sensorPose = opticalToSensorPose();
	obs->hasIntensityImage = true;
	if (imagesDir)
	{
		// The PNG is copied byte for byte: lossless, and RawLogViewer shows it.
		const std::string name = fs::path(pair.rgb.file).filename().string();
		fs::copy_file(rgbFile, *imagesDir / name, fs::copy_options::overwrite_existing);
		obs->intensityImage.setExternalStorage(name);
	}
	else
		obs->intensityImage = mrpt::img::CImage(rgb, mrpt::img::DEEP_COPY);
	return obs;
}

/** A timestamp to the digit (precision 16), or a duration to the millisecond. */
std::string timeText(double t, bool duration = false)
{
	std::ostringstream s;
	if (duration) s << std::fixed;
	s.precision(duration ? 3 : 16);
	s << t;
	return s.str();
}

/** With trimToGroundTruth: `pairs` without the frames outside the span of
 *  `groundTruth`, each listed in `skipped`. */
std::vector<RgbdPair> trimmedToGroundTruth(std::vector<RgbdPair> pairs, const Trajectory& groundTruth,
	const fs::path& gtFile, std::vector<std::string>& skipped)
{
	const double first = groundTruth.front().timestamp, last = groundTruth.back().timestamp;
	std::vector<RgbdPair> kept;
	for (std::size_t i = 0; i < pairs.size(); ++i)
	{
		const double t = pairs[i].depth.timestamp;
		if (t >= first && t <= last)
			kept.push_back(pairs[i]);
		else
			skipped.push_back("frame " + std::to_string(i) + " (" + pairs[i].depth.file + ", t=" + timeText(t) +
							  "): " + (t < first ? "before" : "after") + " the ground truth (--trim-to-ground-truth)");
	}
	if (kept.empty())
		throw std::runtime_error(gtFile.string() + ": ground truth (" + timeText(first) + " .. " + timeText(last) +
								 ") covers none of the " + std::to_string(pairs.size()) + " frames (" +
								 timeText(pairs.front().depth.timestamp) + " .. " +
								 timeText(pairs.back().depth.timestamp) + ")");
	return kept;
}

/** The body pose of frame `i` (`pair`), interpolated in the ground truth; an
 *  error that says how far outside it the frame is, or that it falls in a gap. */
mrpt::poses::CPose3D bodyPoseAt(
	const Trajectory& groundTruth, std::size_t i, const RgbdPair& pair, const fs::path& dir, const fs::path& gtFile)
{
	const double t = pair.depth.timestamp;
	if (const auto body = interpolatePose(groundTruth, t)) return *body;
	const double first = groundTruth.front().timestamp, last = groundTruth.back().timestamp;
	const bool outside = t < first || t > last;
	throw std::runtime_error(
		gtFile.string() + ": ground truth (" + timeText(first) + " .. " + timeText(last) + ") does not cover frame " +
		std::to_string(i) + " (" + (dir / pair.depth.file).string() + ", t=" + timeText(t) + "): " +
		(outside ? std::string("the frame is ") + timeText(t < first ? first - t : t - last, true) + " s " +
					   (t < first ? "before its first" : "after its last") +
					   " pose; --trim-to-ground-truth leaves out the frames outside the ground "
					   "truth"
				 : std::string("a gap in the ground truth around it")));
}

/** The rawlog's stream at `file`: gzip at `compressionLevel` 1..9, plain at 0. */
std::unique_ptr<mrpt::io::CStream> openRawlogFile(const fs::path& file, int compressionLevel, const fs::path& named)
{
	std::unique_ptr<mrpt::io::CStream> stream;
	if (compressionLevel > 0)
	{
		auto gz = std::make_unique<mrpt::io::CFileGZOutputStream>();
		if (gz->open(file.string(), compressionLevel)) stream = std::move(gz);
	}
	else if (auto plain = std::make_unique<mrpt::io::CFileOutputStream>(); plain->open(file.string()))
		stream = std::move(plain);
	if (!stream) throw std::runtime_error(named.string() + ": cannot write");
	return stream;
}

/** The dataset's ground truth when it is used (nothing otherwise), and
 *  `pairs` cut to its span with trimToGroundTruth, then to options.frames. */
std::optional<Trajectory> readGroundTruth(const fs::path& gtFile, const TumConversionOptions& opt,
	std::vector<RgbdPair>& pairs, std::vector<std::string>& skipped)
{
	std::optional<Trajectory> groundTruth;
	// Trimming reads the ground truth even when the rawlog is to have none:
	// a cut of a sequence numbers its frames as the whole trimmed one does.
	if ((opt.useGroundTruth || opt.trimToGroundTruth) && fs::exists(gtFile))
	{
		groundTruth = readTumTrajectory(gtFile);
		if (groundTruth->empty()) throw std::runtime_error(gtFile.string() + ": no poses");
	}
	if (opt.trimToGroundTruth)
	{
		if (!groundTruth)
			throw std::invalid_argument(gtFile.string() + ": not found; trimming to the ground truth needs it");
		pairs = trimmedToGroundTruth(std::move(pairs), *groundTruth, gtFile, skipped);
	}
	if (opt.frames)
	{
		const auto [first, last] = *opt.frames;
		if (first > last || last >= pairs.size())
			throw std::invalid_argument("frames " + std::to_string(first) + ":" + std::to_string(last) + ": the " +
										(opt.trimToGroundTruth ? "trimmed " : "") +
										"sequence has frames 0:" + std::to_string(pairs.size() - 1));
		pairs = std::vector<RgbdPair>(pairs.begin() + std::ptrdiff_t(first), pairs.begin() + std::ptrdiff_t(last + 1));
	}
	if (!opt.useGroundTruth) groundTruth.reset();
	return groundTruth;
}

/** Moves `from` onto `to`, replacing a previous folder or file. */
void replace(const fs::path& from, const fs::path& to)
{
	fs::remove_all(to);
	fs::rename(from, to);
}
}  // namespace

TumConversionSummary convertTumToRawlog(const fs::path& dir, const fs::path& outRawlog, const TumConversionOptions& opt,
	const std::function<void(std::size_t, std::size_t)>& progress)
{
	if (opt.compressionLevel < 0 || opt.compressionLevel > 9)
		throw std::invalid_argument(
			"compression level " + std::to_string(opt.compressionLevel) + ": must be 0..9 (0 = a plain file)");
	TumConversionSummary summary;
	auto pairs = readPairs(dir, opt.maxTimeDifference, summary.skipped);
	if (pairs.empty()) throw std::runtime_error(dir.string() + ": no RGB-D pairs to convert");

	const fs::path gtFile = dir / "groundtruth.txt";
	const auto groundTruth = readGroundTruth(gtFile, opt, pairs, summary.skipped);

	const fs::path outDir = outRawlog.parent_path().empty() ? fs::path(".") : outRawlog.parent_path();
	if (!fs::is_directory(outDir)) throw std::runtime_error(outDir.string() + ": output folder not found");
	const std::string stem = outRawlog.stem().string();
	summary.rawlog = outRawlog;
	summary.imagesDir = outDir / (stem + "_Images");
	summary.groundTruthFile = outDir / (stem + "_groundtruth.txt");

	std::optional<fs::path> partialImages;
	if (!opt.embedImages)
	{
		partialImages = outDir / ("." + stem + "_Images.partial");
		fs::remove_all(*partialImages);
		fs::create_directories(*partialImages);
	}
	Trajectory cameraTrajectory;
	try
	{
		writeFileAtomically(outRawlog,
			[&](const fs::path& tmp)
			{
				const auto file = openRawlogFile(tmp, opt.compressionLevel, outRawlog);
				auto out = mrpt::serialization::archiveFrom(*file);
				for (std::size_t i = 0; i < pairs.size(); ++i)
				{
					auto obs = makeObservation(pairs[i], dir, opt, partialImages);
					std::optional<mrpt::poses::CPose3D> camera;
					if (groundTruth)
					{
						camera = bodyPoseAt(*groundTruth, i, pairs[i], dir, gtFile) + opt.groundTruthBodyToCamera;
						cameraTrajectory.push_back({pairs[i].depth.timestamp, *camera});
					}
					writeFrame(out, *obs, camera);
					if (progress) progress(i + 1, pairs.size());
				}
			});
	}
	catch (...)
	{
		if (partialImages) fs::remove_all(*partialImages);
		throw;
	}
	if (partialImages) replace(*partialImages, summary.imagesDir);
	if (groundTruth)
	{
		writeTumTrajectory(summary.groundTruthFile, cameraTrajectory,
			"camera optical-frame ground truth of " + outRawlog.filename().string());
		summary.withGroundTruth = true;
	}
	summary.frames = pairs.size();
	return summary;
}
}  // namespace avm::io
