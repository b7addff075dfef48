// Bad input to avm-tum2rawlog: each case names the file and the problem, exits
// non-zero, and leaves no output behind (an earlier output stays intact).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "TestData.h"
#include "avm/io/RawlogFrameReader.h"
#include "avm/io/RgbdFrame.h"
#include "avm/io/Trajectory.h"
#include "avm/io/TumDataset.h"

using namespace avm;
namespace fs = std::filesystem;

namespace
{
test::CommandResult runConverter(
	const fs::path& dataset, const fs::path& out, const std::string& options = "--camera bonn --gt-body bonn")
{
	return test::runCommand(
		test::binary("avm-tum2rawlog").string() + " " + options + " '" + dataset.string() + "' '" + out.string() + "'",
		out.parent_path());
}

/** A 3-frame copy of the Bonn dataset to damage. */
fs::path smallDataset(const std::string& name)
{
	const fs::path dir = test::scratchDir(name) / "dataset";
	fs::create_directories(dir / "rgb");
	fs::create_directories(dir / "depth");
	const fs::path src = test::bonnDatasetDir();
	std::ifstream in(src / "associations.txt");
	std::ofstream out(dir / "associations.txt");
	std::string line;
	for (int n = 0; n < 3 && std::getline(in, line); ++n)
	{
		out << line << "\n";
		std::istringstream ss(line);
		std::string t1, rgb, t2, depth;
		ss >> t1 >> rgb >> t2 >> depth;
		fs::copy_file(src / rgb, dir / rgb);
		fs::copy_file(src / depth, dir / depth);
	}
	fs::copy_file(src / "groundtruth.txt", dir / "groundtruth.txt");
	return dir;
}

std::vector<std::string> lines(const fs::path& file)
{
	std::ifstream in(file);
	std::vector<std::string> out;
	for (std::string l; std::getline(in, l);) out.push_back(l);
	return out;
}

void writeLines(const fs::path& file, const std::vector<std::string>& ls)
{
	std::ofstream out(file);
	for (const auto& l : ls) out << l << "\n";
}

/** The depth column (time, file) of a row of associations.txt. */
std::pair<double, std::string> depthOf(const fs::path& dataset, int row)
{
	std::istringstream ss(lines(dataset / "associations.txt")[row]);
	std::string t1, rgb, t2, depth;
	ss >> t1 >> rgb >> t2 >> depth;
	return {std::stod(t2), depth};
}

std::string depthFile(const fs::path& dataset, int row) { return depthOf(dataset, row).second; }

/** Runs the converter on a damaged dataset over an earlier good output and
 *  checks the error text, the exit code and that nothing changed on disk. */
void expectRejected(const fs::path& dataset, const std::string& expectedInMessage)
{
	const fs::path outDir = dataset.parent_path() / "out";
	fs::create_directories(outDir);
	const fs::path out = outDir / "run.rawlog";
	std::ofstream(out) << "earlier output";
	const auto r = runConverter(dataset, out);
	EXPECT_NE(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find(expectedInMessage), std::string::npos)
		<< "expected '" << expectedInMessage << "' in: " << r.output;
	std::ifstream in(out);
	std::string kept;
	std::getline(in, kept);
	EXPECT_EQ(kept, "earlier output") << "the earlier output was touched";
	std::vector<std::string> left;
	for (const auto& e : fs::directory_iterator(outDir)) left.push_back(e.path().filename().string());
	EXPECT_EQ(left, std::vector<std::string>{"run.rawlog"}) << "partial outputs left behind";
}
}  // namespace

TEST(TumToRawlogBadInput, SmallDatasetConverts)
{
	const auto ds = smallDataset("bad-none");
	const fs::path out = ds.parent_path() / "ok.rawlog";
	const auto r = runConverter(ds, out);
	EXPECT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("frames:       3"), std::string::npos) << r.output;
	EXPECT_TRUE(fs::exists(out));
	EXPECT_TRUE(fs::exists(ds.parent_path() / "ok_Images"));
	EXPECT_TRUE(fs::exists(ds.parent_path() / "ok_groundtruth.txt"));
}

TEST(TumToRawlogBadInput, PlainRawlogWithEmbeddedImagesHasTheSameFrames)
{
	// The fast-to-replay form (--embed-images --compression 0): no gzip, colour
	// inside; the same pixels and poses as the default form.
	const auto ds = smallDataset("plain-embedded");
	const fs::path gz = ds.parent_path() / "gz.rawlog", plain = ds.parent_path() / "plain.rawlog";
	ASSERT_EQ(runConverter(ds, gz).exitCode, 0);
	const auto r = runConverter(ds, plain, "--camera bonn --gt-body bonn --embed-images --compression 0");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_FALSE(fs::exists(ds.parent_path() / "plain_Images"));
	std::ifstream head(plain, std::ios::binary);
	const int b0 = head.get(), b1 = head.get();
	EXPECT_FALSE(b0 == 0x1f && b1 == 0x8b) << "a gzip header in a --compression 0 rawlog";
	EXPECT_GT(fs::file_size(plain), 3u * 640 * 480 * 5) << "3 frames of raw depth (2 B) and colour (3 B) a pixel";

	// One reader at a time: MRPT's folder of external images is process-wide.
	const auto framesOf = [](const fs::path& rawlog)
	{
		io::useImagesFolderOf(rawlog);
		io::RawlogFrameReader reader(rawlog);
		std::vector<io::RgbdFrame> out;
		while (auto f = reader.next()) out.push_back(*f);
		return out;
	};
	const auto fromGz = framesOf(gz), fromPlain = framesOf(plain);
	ASSERT_EQ(fromGz.size(), 3u);
	ASSERT_EQ(fromPlain.size(), 3u);
	for (std::size_t i = 0; i < 3; ++i)
	{
		const auto &fa = fromGz[i], &fb = fromPlain[i];
		EXPECT_EQ(cv::norm(io::depthInMetres(*fa.observation), io::depthInMetres(*fb.observation), cv::NORM_INF), 0);
		EXPECT_EQ(cv::norm(io::colourImage(*fa.observation), io::colourImage(*fb.observation), cv::NORM_INF), 0);
		ASSERT_TRUE(fa.groundTruth && fb.groundTruth);
		EXPECT_EQ(fa.groundTruth->asString(), fb.groundTruth->asString());
	}
	const auto bad = runConverter(ds, plain, "--compression 10");
	EXPECT_NE(bad.exitCode, 0);
	EXPECT_NE(bad.output.find("compression level 10: must be 0..9"), std::string::npos) << bad.output;
}

TEST(TumToRawlogBadInput, MissingFolder)
{
	const auto base = test::scratchDir("bad-missing-folder");
	fs::create_directories(base / "out");
	const auto r = runConverter(base / "nowhere", base / "out" / "x.rawlog");
	EXPECT_NE(r.exitCode, 0);
	EXPECT_NE(r.output.find("nowhere: dataset folder not found"), std::string::npos) << r.output;
	EXPECT_TRUE(fs::is_empty(base / "out"));
}

TEST(TumToRawlogBadInput, MissingLists)
{
	const auto ds = smallDataset("bad-lists");
	fs::remove(ds / "associations.txt");
	expectRejected(ds, "rgb.txt: not found");
}

TEST(TumToRawlogBadInput, MissingImage)
{
	const auto ds = smallDataset("bad-missing-image");
	fs::remove(ds / depthFile(ds, 1));
	expectRejected(ds, depthFile(ds, 1) + ": image not found");
}

TEST(TumToRawlogBadInput, UnreadableImage)
{
	const auto ds = smallDataset("bad-unreadable");
	std::ofstream(ds / depthFile(ds, 2)) << "not a png";
	expectRejected(ds, depthFile(ds, 2) + ": unreadable image");
}

TEST(TumToRawlogBadInput, MismatchedImageSize)
{
	const auto ds = smallDataset("bad-size");
	cv::imwrite((ds / depthFile(ds, 0)).string(), cv::Mat(240, 320, CV_16UC1, cv::Scalar(5000)));
	expectRejected(ds, "image is 320x240, the camera is 640x480");
}

TEST(TumToRawlogBadInput, TimestampsOutOfOrder)
{
	const auto ds = smallDataset("bad-order");
	auto ls = lines(ds / "associations.txt");
	std::swap(ls[1], ls[2]);
	writeLines(ds / "associations.txt", ls);
	expectRejected(ds, "associations.txt:3: timestamps out of order");
}

TEST(TumToRawlogBadInput, MalformedListLine)
{
	const auto ds = smallDataset("bad-line");
	auto ls = lines(ds / "associations.txt");
	ls[1] = "1548339824.93624 rgb/only-one-file.png";
	writeLines(ds / "associations.txt", ls);
	expectRejected(ds, "associations.txt:2: expected");
}

TEST(TumToRawlogBadInput, GroundTruthNotCoveringTheFrames)
{
	const auto ds = smallDataset("bad-gt");
	auto ls = lines(ds / "groundtruth.txt");
	ls.resize(6);  // two comment lines and four poses, all before the first frame
	writeLines(ds / "groundtruth.txt", ls);
	expectRejected(ds, "does not cover frame 0");
}

/** The ground truth of `dataset` cut to start `lateBy` seconds after the
 *  first frame (its first pose after the frame moved to that time), as when
 *  the motion capture starts after the camera. */
void groundTruthStartingAfterTheFirstFrame(const fs::path& dataset, double lateBy)
{
	const double depth0 = depthOf(dataset, 0).first;
	std::vector<std::string> kept;
	for (const auto& l : lines(dataset / "groundtruth.txt"))
	{
		if (l.empty() || l[0] == '#')
		{
			kept.push_back(l);
			continue;
		}
		const double t = std::stod(l.substr(0, l.find(' ')));
		if (t <= depth0) continue;
		if (kept.empty() || kept.back()[0] == '#')
		{
			std::ostringstream moved;
			moved.precision(16);
			moved << depth0 + lateBy << l.substr(l.find(' '));
			kept.push_back(moved.str());
		}
		else
			kept.push_back(l);
	}
	writeLines(dataset / "groundtruth.txt", kept);
}

TEST(TumToRawlogBadInput, GroundTruthStartingAfterTheFirstFrameNamesTheTrimOption)
{
	const auto ds = smallDataset("gt-late");
	groundTruthStartingAfterTheFirstFrame(ds, 0.006);
	expectRejected(ds, "does not cover frame 0");
	const auto r = runConverter(ds, ds.parent_path() / "x.rawlog");
	EXPECT_NE(r.output.find("the frame is 0.006 s before its first pose; --trim-to-ground-truth leaves out the frames "
							"outside the ground truth"),
		std::string::npos)
		<< r.output;
}

TEST(TumToRawlogBadInput, TrimToGroundTruthLeavesOutTheFramesBeforeIt)
{
	const auto ds = smallDataset("gt-late-trimmed");
	groundTruthStartingAfterTheFirstFrame(ds, 0.006);
	const fs::path out = ds.parent_path() / "trimmed.rawlog";
	const auto r = runConverter(ds, out, "--camera bonn --gt-body bonn --trim-to-ground-truth");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("frames:       2"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("skipped:      1\n  frame 0 (" + depthFile(ds, 0) + ", t="), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("before the ground truth (--trim-to-ground-truth)"), std::string::npos) << r.output;

	io::useImagesFolderOf(out);
	io::RawlogFrameReader reader(out);
	std::vector<io::RgbdFrame> frames;
	while (auto f = reader.next()) frames.push_back(*f);
	ASSERT_EQ(frames.size(), 2u);
	for (std::size_t i = 0; i < frames.size(); ++i)
	{
		EXPECT_TRUE(frames[i].groundTruth) << "frame " << i;
		EXPECT_NEAR(
			mrpt::Clock::toDouble(frames[i].observation->timestamp), depthOf(ds, static_cast<int>(i) + 1).first, 1e-4);
	}
	EXPECT_EQ(io::readTumTrajectory(ds.parent_path() / "trimmed_groundtruth.txt").size(), 2u);
}

TEST(TumToRawlogBadInput, TrimToGroundTruthWithNoFrameCoveredFails)
{
	const auto ds = smallDataset("gt-none-covered");
	auto ls = lines(ds / "groundtruth.txt");
	ls.resize(6);  // two comment lines and four poses, all before the first frame
	writeLines(ds / "groundtruth.txt", ls);
	const fs::path outDir = ds.parent_path() / "out";
	fs::create_directories(outDir);
	const auto r = runConverter(ds, outDir / "x.rawlog", "--camera bonn --gt-body bonn --trim-to-ground-truth");
	EXPECT_NE(r.exitCode, 0);
	EXPECT_NE(r.output.find(") covers none of the 3 frames ("), std::string::npos) << r.output;
	EXPECT_TRUE(fs::is_empty(outDir));
}

TEST(TumToRawlogBadInput, UnknownCameraPresetListsTheKnownOnes)
{
	const auto ds = smallDataset("bad-camera");
	const auto r = runConverter(ds, ds.parent_path() / "x.rawlog", "--camera kinect9 --gt-body bonn");
	EXPECT_NE(r.exitCode, 0);
	EXPECT_NE(r.output.find("unknown camera preset 'kinect9' (known: bonn, tum-fr1"), std::string::npos) << r.output;
}
