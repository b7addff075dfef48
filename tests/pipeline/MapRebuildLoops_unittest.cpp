// [pipeline] rebuild_map after loop closures: sub300 played forward, then
// backward, as one rawlog. Label long: the release pass only (the rebuild
// itself runs under the sanitizers in MapRebuild_unittest.cpp and the
// checkpoint tests; two runs of 599 frames take minutes there).
#include <gtest/gtest.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <iostream>
#include <vector>

#include "DefaultIni.h"
#include "TestData.h"
#include "avm/io/ProgramMain.h"
#include "avm/io/RawlogFrameReader.h"
#include "avm/pipeline/MappingPipeline.h"

using namespace avm;
namespace fs = std::filesystem;

namespace
{
/** The Bonn frames 0..last played forward, then backward to frame 0, as one
 *  rawlog (timestamps at the sequence's mean rate; ground truth kept): the
 *  camera shows its start again. Colour stays in the fixture's images folder. */
fs::path writeForwardBackwardRawlog(const fs::path& dir, std::size_t last)
{
	io::RawlogFrameReader reader(test::bonnRawlog(), /*loadImages=*/false);
	std::vector<io::RgbdFrame> frames;
	while (auto f = reader.next())
		if (f->index <= last) frames.push_back(std::move(*f));
	const double t0 = frames.front().timestamp();
	const double dt = (frames.back().timestamp() - t0) / double(frames.size() - 1);
	std::vector<const io::RgbdFrame*> order;
	for (const auto& f : frames) order.push_back(&f);
	for (auto it = frames.rbegin() + 1; it != frames.rend(); ++it) order.push_back(&*it);

	const auto rawlog = dir / "forward_backward.rawlog";
	fs::create_directory_symlink(io::imagesDirectoryOf(test::bonnRawlog()), dir / "forward_backward_Images");
	mrpt::io::CFileOutputStream file(rawlog.string());
	auto out = mrpt::serialization::archiveFrom(file);
	for (std::size_t i = 0; i < order.size(); ++i)
	{
		auto obs = *order[i]->observation;
		obs.timestamp = mrpt::Clock::fromDouble(t0 + double(i) * dt);
		io::writeFrame(out, obs, order[i]->groundTruth.value());
	}
	return rawlog;
}
}  // namespace

// After loops closed, the map is made at the corrected poses: it is no longer
// the map the run inserted at the drifted ones.
TEST(PipelineMapRebuild, AfterALoopClosesTheMapFollowsTheCorrectedTrajectory)
{
	const auto dir = test::scratchDir("pipeline-map-rebuild-loops");
	const auto rawlog = writeForwardBackwardRawlog(dir, 299);
	const auto runWith = [&](const std::string& when)
	{
		auto ini = test::defaultIni();
		ini.write("pipeline", "picture_size", "0");
		ini.write("pipeline", "checkpoint_interval_s", "0");
		ini.write("odometry", "loop_closure", "true");
		// The loop check with half the default's loop error: with the default
		// the drift of these 599 frames stays within the loops' own error and
		// nothing closes; what is tested is the map after a loop has closed.
		ini.write("odometry", "loop_sigma", "0.01");
		ini.write("pipeline", "rebuild_map", when);
		io::useImagesFolderOf(rawlog);
		pipeline::MappingPipeline p(ini, AVM_SOURCE_DIR);
		const auto out = dir / when;
		const auto summary = p.run(rawlog, out);
		EXPECT_EQ(summary.frames, 599u);
		std::cout << "rebuild_map = " << when << ": " << summary.loopsClosed << " loops closed, ATE "
				  << summary.ateRmse.value_or(-1) << " m";
		if (summary.mapRebuild)
			std::cout << "; map rebuilt, " << summary.mapRebuild->frames << " frames in " << summary.mapRebuild->seconds
					  << " s";
		std::cout << "\n";
		return std::pair{out, summary};
	};
	const auto [drifted, open] = runWith("never");
	const auto [corrected, closed] = runWith("after_loops");
	EXPECT_EQ(open.loopsClosed, closed.loopsClosed);
	ASSERT_GE(closed.loopsClosed, 1u);
	ASSERT_TRUE(closed.mapRebuild);
	EXPECT_EQ(closed.mapRebuild->frames, closed.frames);
	EXPECT_EQ(test::fileBytes(drifted / "trajectory.txt"), test::fileBytes(corrected / "trajectory.txt"));
	EXPECT_NE(test::fileBytes(drifted / "map_low.bt"), test::fileBytes(corrected / "map_low.bt"));
}
