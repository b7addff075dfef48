// A building mapped over several runs on the real Bonn sequence cut in three
// (frames 0-99 with ground truth, 100-199 and 200-299 without, as a real next
// run has none; the first mapped by avm-map: ctest fixtures bonn_sessions):
// each next run is placed in the map of the run before by place recognition,
// maps on in its world, keeps its persons and keyframes, gives the same bytes
// twice and after a kill, and hands itself on to the next; a bad earlier run
// is named in one line and nothing is written.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <atomic>
#include <fstream>
#include <set>
#include <string>

#include "CoveredLens.h"
#include "TestData.h"
#include "avm/evaluation/TrajectoryEvaluation.h"
#include "avm/io/RawlogFrameReader.h"
#include "avm/io/RunFolder.h"
#include "avm/io/Trajectory.h"
#include "avm/persons/PersonsCsv.h"
#include "avm/pipeline/CheckpointWriter.h"
#include "avm/pipeline/MappingPipeline.h"

using namespace avm;
namespace fs = std::filesystem;

namespace
{
const fs::path kSessions = AVM_SESSION_RAWLOGS;
const fs::path kFirst = kSessions / "first";

fs::path part(int k) { return kSessions / ("part" + std::to_string(k) + ".rawlog"); }

using Progress = std::function<void(double, std::size_t)>;

/** `previous` continued with `rawlog` into `out` as avm-map does without -c:
 *  with previous's configuration and checkpoints. */
pipeline::RunSummary continueRun(const fs::path& previous, const fs::path& rawlog, const fs::path& out,
	const std::atomic<bool>* stop = nullptr, const Progress& progress = {}, std::size_t maxFrames = 0)
{
	io::useImagesFolderOf(rawlog);
	mrpt::config::CConfigFileMemory ini(pipeline::readSessionRun(previous).ini);
	ini.write("pipeline", "max_frames", std::to_string(maxFrames));
	pipeline::MappingPipeline p(ini, AVM_SOURCE_DIR);
	pipeline::CheckpointWriter checkpoints(out, p.options().checkpointIntervalSeconds);
	p.addObserver(checkpoints);
	return p.continueRun(previous, rawlog, out, stop, progress);
}

/** The sub300 sequence's ground truth (the bonn_rawlog fixture's). */
io::Trajectory groundTruth()
{
	return io::readTumTrajectory(fs::path(AVM_BONN_RAWLOG).replace_extension().string() + "_groundtruth.txt");
}

double ateOf(const fs::path& run)
{
	return evaluation::evaluateTrajectory(io::readTumTrajectory(io::RunFolder(run).trajectory()), groundTruth(), {})
		.ate.rmse;
}

std::size_t linesOf(const fs::path& file)
{
	std::ifstream in(file);
	return std::count(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>(), '\n');
}

const char* const kSessionFiles[] = {"trajectory.txt", "trajectory_status.txt", "detections.txt", "persons.csv",
	"person_shapes.ply", "map_low.bt", "map_high.bt", "keyframes.simplemap"};
}  // namespace

TEST(Sessions, ASecondRunIsPlacedInTheFirstsMapAndMapsOnInItsWorld)
{
	const auto out = test::scratchDir("sessions-second");
	const auto first = io::readTumTrajectory(io::RunFolder(kFirst).trajectory());
	ASSERT_EQ(first.size(), 100u);
	const auto s = continueRun(kFirst, part(2), out);

	ASSERT_TRUE(s.continuation);
	EXPECT_EQ(s.continuation->session, 2u);
	EXPECT_EQ(s.continuation->posesBefore, 100u);
	EXPECT_EQ(s.continuation->firstFrameIndex, 100u) << "frames are numbered on from the first run's";
	// It starts where the first run ended: its first frames see that place.
	ASSERT_TRUE(s.continuation->placedAtFrame);
	EXPECT_LE(s.continuation->unplacedFrames, 5u) << "at least 95 % of the frames placed";
	EXPECT_EQ(*s.continuation->placedAtFrame, 100u + s.continuation->unplacedFrames);
	EXPECT_EQ(s.frames, 100u - s.continuation->unplacedFrames);
	EXPECT_FALSE(s.ateRmse) << "the second rawlog has no ground truth of its own";

	// One trajectory in one world: the first run's poses unchanged, then the second's.
	const auto both = io::readTumTrajectory(io::RunFolder(out).trajectory());
	ASSERT_EQ(both.size(), 100u + s.frames);
	for (std::size_t i = 0; i < first.size(); ++i)
		ASSERT_EQ(both[i].pose.asString(), first[i].pose.asString()) << "pose " << i << " of the first run moved";
	// Single runs of the whole 300 frames are at about 0.018 m.
	EXPECT_LT(ateOf(out), 0.03) << "the two sessions under one alignment";
	const std::string log = test::fileBytes(io::RunFolder(out).log());
	EXPECT_NE(log.find("placed in the earlier sessions' map"), std::string::npos) << log;

	// Person ids go on after the first run's; its persons stay with their ids.
	const auto before = persons::readPersonsCsv(io::RunFolder(kFirst).persons());
	const auto after = persons::readPersonsCsv(io::RunFolder(out).persons());
	ASSERT_FALSE(before.empty()) << "people walk in before frame 100";
	std::uint32_t lastId = 0;
	for (const auto& p : before)
	{
		lastId = std::max(lastId, p.id);
		const auto same = std::find_if(after.begin(), after.end(), [&](const auto& q) { return q.id == p.id; });
		ASSERT_NE(same, after.end()) << "person " << p.id << " of the first run is gone";
		EXPECT_EQ(same->firstFrame, p.firstFrame);
	}
	std::size_t seenAgain = 0;
	for (const auto& p : after)
	{
		if (p.firstFrame >= 100)
		{
			EXPECT_GT(p.id, lastId) << "a person first seen in the second run";
		}
		if (p.id <= lastId && p.lastFrame >= 100) ++seenAgain;
	}
	// The people still in view when the first run ended are the same persons in the second.
	EXPECT_GE(seenAgain, 1u) << "no person of the first run was seen again as themselves";

	// The keyframes handed on: the first run's, then the second's.
	mrpt::maps::CSimpleMap firstKeyframes, keyframes;
	ASSERT_TRUE(firstKeyframes.loadFromFile(io::RunFolder(kFirst).keyframes().string()));
	ASSERT_TRUE(keyframes.loadFromFile(io::RunFolder(out).keyframes().string()));
	ASSERT_GE(firstKeyframes.size(), 3u);
	EXPECT_GT(keyframes.size(), firstKeyframes.size() + 2);
	for (std::size_t i = 0; i < firstKeyframes.size(); ++i)
		EXPECT_EQ(std::get<0>(keyframes.get(i))->getMeanVal().asString(),
			std::get<0>(firstKeyframes.get(i))->getMeanVal().asString());
}

TEST(Sessions, AContinuationGivesTheSameBytesTwiceAndAfterAStop)
{
	const auto dir = test::scratchDir("sessions-same-bytes");
	continueRun(kFirst, part(2), dir / "once");
	continueRun(kFirst, part(2), dir / "twice");
	// Stopped in the middle, and after its last frame with a detection still
	// due (frame 198's, applied at the end) when max_frames ends the run there
	// too: resumed, the same files.
	for (const std::size_t stopAfter : {40u, 100u})
	{
		const auto stoppedDir = dir / ("stopped-" + std::to_string(stopAfter));
		std::atomic<bool> stop{false};
		const auto stopped = continueRun(
			kFirst, part(2), stoppedDir, &stop, [&](double, std::size_t frames) { stop = frames >= stopAfter; },
			stopAfter == 100 ? stopAfter : 0);
		ASSERT_TRUE(stopped.interrupted);
		ASSERT_TRUE(fs::exists(io::RunFolder(stoppedDir).checkpoint()));
		EXPECT_FALSE(fs::exists(io::RunFolder(stoppedDir).session())) << "an interrupted run is no session";
		pipeline::CheckpointWriter checkpoints(stoppedDir);
		mrpt::config::CConfigFileMemory ini(checkpoints.checkpointedRun().ini);
		io::useImagesFolderOf(part(2));
		pipeline::MappingPipeline p(ini, AVM_SOURCE_DIR);
		p.addObserver(checkpoints);
		const auto resumed = p.resume(checkpoints.file(), stoppedDir);
		ASSERT_TRUE(resumed.resumedAfterFrame);
		ASSERT_TRUE(resumed.continuation);
		EXPECT_EQ(resumed.continuation->previous, kFirst);
		for (const char* name : kSessionFiles)
			EXPECT_EQ(test::fileBytes(dir / "once" / name), test::fileBytes(stoppedDir / name))
				<< name << " after a stop after " << stopAfter << " frames and a resume";
	}
	for (const char* name : kSessionFiles)
	{
		const auto once = test::fileBytes(dir / "once" / name);
		EXPECT_GT(once.size(), 100u) << name;
		EXPECT_EQ(once, test::fileBytes(dir / "twice" / name)) << name;
	}
}

TEST(Sessions, AChainOfThreeHoldsEveryEarlierSessionFixed)
{
	const auto dir = test::scratchDir("sessions-chain");
	continueRun(kFirst, part(2), dir / "second");
	const auto third = continueRun(dir / "second", part(3), dir / "third");
	ASSERT_TRUE(third.continuation);
	EXPECT_EQ(third.continuation->session, 3u);
	EXPECT_EQ(third.continuation->previous, dir / "second");
	EXPECT_LE(third.continuation->unplacedFrames, 5u);
	const auto second = io::readTumTrajectory(io::RunFolder(dir / "second").trajectory());
	const auto all = io::readTumTrajectory(io::RunFolder(dir / "third").trajectory());
	ASSERT_EQ(all.size(), second.size() + third.frames);
	for (std::size_t i = 0; i < second.size(); ++i)
		ASSERT_EQ(all[i].pose.asString(), second[i].pose.asString()) << "pose " << i << " of an earlier session moved";
	EXPECT_LT(ateOf(dir / "third"), 0.03) << "three sessions under one alignment";
	// The map holds what the earlier sessions saw and what this one added.
	EXPECT_GT(linesOf(io::RunFolder(dir / "third").detections()), linesOf(io::RunFolder(dir / "second").detections()));
}

// Sessions cut from one recording may be mapped in any order: a run of
// frames 100-199 continuing one of frames 200-299 is placed in it, and the
// trajectory of both lists every pose in time order, a TUM file that any tool
// reads, with the earlier run's poses as they were.
TEST(Sessions, ASessionRecordedBeforeTheOneItContinuesComesFirstInTheTrajectory)
{
	const auto dir = test::scratchDir("sessions-earlier-recording");
	{
		io::useImagesFolderOf(part(3));
		mrpt::config::CConfigFileMemory ini(pipeline::readSessionRun(kFirst).ini);
		pipeline::MappingPipeline(ini, AVM_SOURCE_DIR).run(part(3), dir / "later");
	}
	const auto s = continueRun(dir / "later", part(2), dir / "both");
	ASSERT_TRUE(s.continuation);
	EXPECT_LE(s.continuation->unplacedFrames, 5u);

	const auto later = io::readTumTrajectory(io::RunFolder(dir / "later").trajectory());
	const auto both = io::readTumTrajectory(io::RunFolder(dir / "both").trajectory());
	ASSERT_EQ(both.size(), later.size() + s.frames);
	for (std::size_t i = 1; i < both.size(); ++i) ASSERT_LT(both[i - 1].timestamp, both[i].timestamp) << "pose " << i;
	EXPECT_LT(both[s.frames - 1].timestamp, later.front().timestamp) << "this run's poses come first";
	for (std::size_t i = 0; i < later.size(); ++i)
		ASSERT_EQ(both[s.frames + i].pose.asString(), later[i].pose.asString())
			<< "pose " << i << " of the later recording moved";
	EXPECT_LT(ateOf(dir / "both"), 0.03) << "the two sessions under one alignment";

	// trajectory_status.txt follows trajectory.txt line by line.
	std::ifstream status(io::RunFolder(dir / "both").trajectoryStatus());
	std::string line;
	std::getline(status, line);  // its header
	for (const auto& pose : both)
	{
		double t = 0;
		int tracked = -1;
		ASSERT_TRUE(status >> t >> tracked);
		EXPECT_NEAR(t, pose.timestamp, 1e-6);
	}
}

TEST(Sessions, ABadEarlierRunIsNamedInOneLineAndNothingIsWritten)
{
	const auto dir = test::scratchDir("sessions-bad");
	const auto expectRefused = [&](const fs::path& previous, const fs::path& rawlog, const std::string& words,
								   const fs::path& out, const std::string& extraKey = {})
	{
		SCOPED_TRACE(words);
		try
		{
			io::useImagesFolderOf(rawlog);
			mrpt::config::CConfigFileMemory ini(pipeline::readSessionRun(kFirst).ini);
			if (!extraKey.empty()) ini.write("map_adaptiveOctoMap_00_creationOpts", extraKey, "0.1");
			pipeline::MappingPipeline(ini, AVM_SOURCE_DIR).continueRun(previous, rawlog, out);
			ADD_FAILURE() << "continued";
		}
		catch (const std::exception& e)
		{
			const std::string what = e.what();
			EXPECT_NE(what.find(words), std::string::npos) << what;
			EXPECT_EQ(what.find('\n'), std::string::npos) << what;
		}
		if (out != previous)
		{
			EXPECT_FALSE(fs::exists(io::RunFolder(out).trajectory())) << "outputs were written";
		}
		EXPECT_FALSE(fs::exists(io::RunFolder(out).checkpoint())) << "a checkpoint was left";
	};
	expectRefused(dir / "missing", part(2), (dir / "missing").string() + ": no such folder", dir / "out1");

	// An interrupted run: its folder has a checkpoint and no session.
	fs::create_directories(dir / "interrupted");
	fs::copy_file(io::RunFolder(kFirst).session(), io::RunFolder(dir / "interrupted").checkpoint());
	expectRefused(dir / "interrupted", part(2), "avm-map --resume " + (dir / "interrupted").string(), dir / "out2");

	// A session cut short while it was copied.
	fs::create_directories(dir / "damaged");
	fs::copy_file(io::RunFolder(kFirst).keyframes(), io::RunFolder(dir / "damaged").keyframes());
	const std::string whole = test::fileBytes(io::RunFolder(kFirst).session());
	std::ofstream(io::RunFolder(dir / "damaged").session(), std::ios::binary) << whole.substr(0, whole.size() / 2);
	expectRefused(dir / "damaged", part(2),
		io::RunFolder(dir / "damaged").session().string() + ": cannot continue from this session", dir / "out3");

	// A map at another resolution than the earlier run's.
	expectRefused(
		kFirst, part(2), "a continued run maps at the earlier sessions' resolutions", dir / "out4", "low_resolution");
	// The earlier run's folder as the output.
	const std::string sessionBefore = test::fileBytes(io::RunFolder(kFirst).session());
	expectRefused(kFirst, part(2), "the output folder is the run being continued", kFirst);
	EXPECT_EQ(test::fileBytes(io::RunFolder(kFirst).session()), sessionBefore) << "the earlier run was written";

	// Another camera: the same frames with another focal length.
	const auto other = dir / "other-camera.rawlog";
	const auto convert = test::runCommand(test::binary("avm-tum2rawlog").string() +
											  " -q --camera bonn --fx 500 --frames 100:109 --no-gt '" +
											  test::bonnDatasetDir().string() + "' '" + other.string() + "'",
		dir);
	ASSERT_EQ(convert.exitCode, 0) << convert.output;
	expectRefused(kFirst, other, "a continued run needs the same camera", dir / "out5");
}

// A camera whose lens stays covered never sees a place the first run saw: the
// run ends with an error, and nothing is merged or written.
TEST(Sessions, ARunNeverPlacedEndsWithAnErrorAndNoOutputs)
{
	const auto dir = test::scratchDir("sessions-never-placed");
	const auto covered = dir / "covered.rawlog";
	{
		io::useImagesFolderOf(part(2));
		io::RawlogFrameReader reader(part(2));
		mrpt::io::CFileGZOutputStream file(covered.string());
		auto out = mrpt::serialization::archiveFrom(file);
		for (int i = 0; i < 10; ++i)
		{
			auto frame = reader.next();
			ASSERT_TRUE(frame);
			test::coverLens(*frame->observation);
			out << *frame->observation;
		}
	}
	try
	{
		continueRun(kFirst, covered, dir / "out");
		FAIL() << "a run that was never placed ended without an error";
	}
	catch (const std::runtime_error& e)
	{
		const std::string what = e.what();
		EXPECT_NE(what.find(covered.string() + ": none of its 10 frames was placed"), std::string::npos) << what;
	}
	EXPECT_FALSE(fs::exists(io::RunFolder(dir / "out").trajectory()));
	EXPECT_FALSE(fs::exists(io::RunFolder(dir / "out").session()));
	EXPECT_FALSE(fs::exists(io::RunFolder(dir / "out").checkpoint()));
}
