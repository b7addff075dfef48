#include <gtest/gtest.h>

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <fstream>

#include "TestData.h"
#include "avm/io/RawlogFrameReader.h"

using namespace avm;
namespace fs = std::filesystem;

TEST(RawlogFrameReader, ConvertedBonnSequenceHas300FramesInTimeOrderWithGroundTruth)
{
	io::RawlogFrameReader reader(test::bonnRawlog());
	std::size_t n = 0;
	double last = 0;
	while (auto f = reader.next())
	{
		EXPECT_EQ(f->index, n);
		EXPECT_GT(f->timestamp(), last) << "frame " << n;
		last = f->timestamp();
		ASSERT_TRUE(f->groundTruth.has_value()) << "frame " << n;
		EXPECT_TRUE(f->observation->hasIntensityImage);
		EXPECT_EQ(io::colourImage(*f->observation).size(), cv::Size(640, 480));
		++n;
	}
	EXPECT_EQ(n, 300u);
	EXPECT_TRUE(reader.skipped().empty());
	EXPECT_EQ(io::countFrames(test::bonnRawlog()), 300u);
}

TEST(RawlogFrameReader, MrptTestRawlogIsOneRgbdFrame)
{
	io::RawlogFrameReader reader(test::sharedFile("datasets/tests_rgbd.rawlog"));
	auto f = reader.next();
	ASSERT_TRUE(f);
	EXPECT_TRUE(f->observation->hasRangeImage);
	EXPECT_EQ(f->observation->rangeImage.cols(), 640);
	EXPECT_EQ(f->observation->rangeImage.rows(), 480);
	EXPECT_FALSE(f->groundTruth);
	EXPECT_FALSE(reader.next());
}

TEST(RawlogFrameReader, MissingRawlogNamesTheFile)
{
	try
	{
		io::RawlogFrameReader reader("no/such/file.rawlog");
		FAIL() << "no exception";
	}
	catch (const std::runtime_error& e)
	{
		EXPECT_NE(std::string(e.what()).find("no/such/file.rawlog"), std::string::npos) << e.what();
	}
}

TEST(RawlogFrameReader, TruncatedRawlogIsReportedNotTakenAsTheEnd)
{
	const auto dir = test::scratchDir("truncated-rawlog");
	const auto cut = dir / "cut.rawlog";
	{
		const std::string bytes = mrpt::io::file_get_contents(test::sharedFile("datasets/tests_rgbd.rawlog").string());
		std::ofstream(cut, std::ios::binary).write(bytes.data(), bytes.size() / 2);
	}
	io::RawlogFrameReader reader(cut);
	try
	{
		reader.next();
		FAIL() << "a truncated rawlog read as if complete";
	}
	catch (const std::runtime_error& e)
	{
		const std::string what = e.what();
		EXPECT_NE(what.find("cut.rawlog"), std::string::npos) << what;
		EXPECT_NE(what.find("truncated"), std::string::npos) << what;
	}
}

TEST(RawlogFrameReader, UncompressedRawlogCutInsideAnEntryIsReported)
{
	// Plain rawlogs have no gzip trailer to betray the cut: the reader must
	// tell the end between entries from an entry that stops half way.
	const auto dir = test::scratchDir("truncated-plain-rawlog");
	io::RawlogFrameReader source(test::sharedFile("datasets/tests_rgbd.rawlog"));
	const auto frame = source.next();
	ASSERT_TRUE(frame);
	const auto whole = dir / "whole.rawlog";
	{
		mrpt::io::CFileOutputStream out(whole.string());
		auto archive = mrpt::serialization::archiveFrom(out);
		archive << *frame->observation << *frame->observation;
	}
	io::RawlogFrameReader complete(whole);
	EXPECT_TRUE(complete.next());
	EXPECT_TRUE(complete.next());
	EXPECT_FALSE(complete.next());

	const auto cut = dir / "cut.rawlog";
	fs::copy_file(whole, cut);
	fs::resize_file(cut, fs::file_size(whole) * 3 / 4);
	io::RawlogFrameReader reader(cut);
	EXPECT_THROW(while (reader.next()){}, std::runtime_error);
}

TEST(RawlogFrameReader, GarbageFileIsReportedAsCorrupt)
{
	const auto file = test::scratchDir("garbage-rawlog") / "garbage.rawlog";
	std::ofstream(file) << "this is not a rawlog, just some text that goes on for a while\n";
	io::RawlogFrameReader reader(file);
	EXPECT_THROW(reader.next(), std::runtime_error);
}

TEST(RawlogFrameReader, OneMissingImageSkipsThatFrameOnly)
{
	const auto dir = test::scratchDir("missing-image");
	// Three frames of the Bonn rawlog with external images; remove one image.
	io::RawlogFrameReader source(test::bonnRawlog());
	const auto rawlog = dir / "three.rawlog";
	fs::create_directories(dir / "three_Images");
	{
		mrpt::io::CFileGZOutputStream out(rawlog.string());
		auto archive = mrpt::serialization::archiveFrom(out);
		for (int i = 0; i < 3; ++i)
		{
			auto f = source.next();
			ASSERT_TRUE(f);
			const auto name = f->observation->intensityImage.getExternalStorageFile();
			fs::copy_file(source.imagesDirectory() / name, dir / "three_Images" / name);
			archive << *f->observation;
			if (i == 1) fs::remove(dir / "three_Images" / name);
		}
	}
	io::useImagesFolderOf(rawlog);
	io::RawlogFrameReader reader(rawlog);
	std::vector<std::size_t> read;
	while (auto f = reader.next()) read.push_back(f->index);
	EXPECT_EQ(read, (std::vector<std::size_t>{0, 2}));
	ASSERT_EQ(reader.skipped().size(), 1u);
	EXPECT_NE(reader.skipped()[0].find("frame 1 skipped"), std::string::npos) << reader.skipped()[0];

	fs::remove_all(dir / "three_Images");
	io::RawlogFrameReader noImages(rawlog);
	try
	{
		noImages.next();
		FAIL() << "a missing images folder went unnoticed";
	}
	catch (const std::runtime_error& e)
	{
		EXPECT_NE(std::string(e.what()).find("three_Images not found"), std::string::npos) << e.what();
	}
}
