// Checkpoints of the odometry: a run resumed from saveState()
// continues with exactly the poses of the uninterrupted run, on real Bonn
// frames; a damaged state is refused with a clear message.
#include <gtest/gtest.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "TestData.h"
#include "avm/io/RawlogFrameReader.h"
#include "avm/odometry/VisualOdometry.h"

using namespace avm;

namespace
{
std::vector<std::uint8_t> savedState(const odometry::VisualOdometry& vo)
{
	mrpt::io::CMemoryStream mem;
	auto out = mrpt::serialization::archiveFrom(mem);
	vo.saveState(out);
	const auto* bytes = static_cast<const std::uint8_t*>(mem.getRawBufferData());
	return {bytes, bytes + mem.getTotalBytesCount()};
}

void loadState(odometry::VisualOdometry& vo, const std::vector<std::uint8_t>& bytes)
{
	mrpt::io::CMemoryStream mem;
	if (!bytes.empty()) mem.Write(bytes.data(), bytes.size());  // MRPT refuses a null buffer
	mem.Seek(0);
	auto in = mrpt::serialization::archiveFrom(mem);
	vo.loadState(in);
}

/** The message loadState throws for these bytes, or "" if it accepts them. */
std::string loadError(odometry::VisualOdometry& vo, const std::vector<std::uint8_t>& bytes)
{
	try
	{
		loadState(vo, bytes);
	}
	catch (const std::runtime_error& e)
	{
		return e.what();
	}
	return "";
}

/** An estimate but its pose, as text (the RMSE in hexadecimal: every bit). */
std::string summary(const odometry::OdometryEstimate& e)
{
	std::ostringstream s;
	s << "tracked " << e.tracked << ", keyframe " << e.keyframe << ", inliers " << e.inliers << ", rmse "
	  << std::hexfloat << e.reprojectionRmse << ", " << e.status;
	return s.str();
}

/** How two estimates differ ("" when they are the same, the pose bit for bit). */
std::string difference(const odometry::OdometryEstimate& a, const odometry::OdometryEstimate& b)
{
	const auto Ha = a.pose.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
	const auto Hb = b.pose.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
	for (int r = 0; r < 3; ++r)
		for (int c = 0; c < 4; ++c)
			if (!(Ha(r, c) == Hb(r, c))) return "pose differs: " + a.pose.asString() + " vs " + b.pose.asString();
	if (summary(a) != summary(b)) return summary(a) + " vs " + summary(b);
	return "";
}

/** The state is saved after each frame of `saveAfter`; each time a new
 *  instance restored from it runs the next 40 frames beside the original,
 *  which must give the same estimates bit for bit. No person boxes. */
void expectResumedRunsBitIdentical(const odometry::TOdometryOptions& options, const std::vector<std::size_t>& saveAfter)
{
	constexpr std::size_t resumedFrames = 40;
	odometry::VisualOdometry original(options);
	std::map<std::size_t, odometry::VisualOdometry> resumed;  // by the frame saved after
	std::map<std::size_t, std::size_t> keyframes, tracked;
	io::RawlogFrameReader reader(test::bonnRawlog());
	while (auto f = reader.next())
	{
		if (f->index > saveAfter.back() + resumedFrames) break;
		const auto estimate = original.process(*f->observation);
		for (auto& [saved, vo] : resumed)
			if (f->index <= saved + resumedFrames)
			{
				ASSERT_EQ(difference(estimate, vo.process(*f->observation)), "")
					<< "frame " << f->index << ", resumed after frame " << saved;
				keyframes[saved] += estimate.keyframe;
				tracked[saved] += estimate.tracked;
			}
		if (std::find(saveAfter.begin(), saveAfter.end(), f->index) != saveAfter.end())
		{
			mrpt::io::CMemoryStream mem;
			auto archive = mrpt::serialization::archiveFrom(mem);
			original.saveState(archive);
			mem.Seek(0);
			auto& vo = resumed.emplace(f->index, options).first->second;
			vo.loadState(archive);
			EXPECT_EQ(vo.keyframeCount(), original.keyframeCount());
			EXPECT_EQ(vo.landmarkCount(), original.landmarkCount());
			EXPECT_EQ(savedState(vo), savedState(original)) << "a reloaded state saves the same bytes";
		}
	}
	ASSERT_EQ(resumed.size(), saveAfter.size()) << "the rawlog is too short";
	for (const std::size_t saved : saveAfter)
	{
		// The resumed frames exercised tracking and the bundle adjustment (the
		// motion gate may bridge a frame: one of frames 256-295 it does).
		EXPECT_GE(tracked[saved], resumedFrames - 2) << saved;
		EXPECT_GE(keyframes[saved], 3u) << saved;
	}
	EXPECT_EQ(savedState(resumed.at(saveAfter.back())), savedState(original)) << "the same state at the end";
	const auto a = resumed.at(saveAfter.back()).trajectory(), b = original.trajectory();
	ASSERT_EQ(a.size(), b.size());
	for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i], b[i]) << "trajectory pose " << i;
}
}  // namespace

TEST(VisualOdometryState, ResumedRunGivesBitIdenticalPoses)
{
	// After frame 70 and after frame 150: by then the window has been
	// forgetting landmarks for a while.
	expectResumedRunsBitIdentical(odometry::TOdometryOptions{}, {70, 150});
}

TEST(VisualOdometryState, ResumedRunWithLoopClosureGivesBitIdenticalPoses)
{
	// From frame 249 on, new keyframes see the place of the first ones again:
	// the state carries loop constraints (loop closing is on by default) and
	// every frame's pose.
	expectResumedRunsBitIdentical(odometry::TOdometryOptions{}, {255});
}

TEST(VisualOdometryState, TruncatedOrOtherVersionStreamIsRefused)
{
	odometry::VisualOdometry source({});
	io::RawlogFrameReader reader(test::bonnRawlog());
	ASSERT_TRUE(source.process(*reader.next()->observation).keyframe);
	const auto bytes = savedState(source);

	odometry::VisualOdometry target({});
	for (const std::size_t size : {std::size_t(1), std::size_t(100), bytes.size() / 2, bytes.size() - 1})
	{
		const std::vector<std::uint8_t> truncated(bytes.begin(), bytes.begin() + size);
		EXPECT_EQ(
			loadError(target, truncated), "VisualOdometry::loadState: truncated odometry state (the stream ends early)")
			<< size << " of " << bytes.size() << " bytes";
	}
	auto otherVersion = bytes;
	otherVersion[0] = 99;
	EXPECT_NE(loadError(target, otherVersion).find("version 99"), std::string::npos);
	// A refused stream leaves the state as it was.
	EXPECT_EQ(target.keyframeCount(), 0u);
	EXPECT_EQ(target.landmarkCount(), 0u);

	EXPECT_EQ(loadError(target, bytes), "");
	EXPECT_EQ(target.keyframeCount(), 1u);
	EXPECT_EQ(target.landmarkCount(), source.landmarkCount());
}
