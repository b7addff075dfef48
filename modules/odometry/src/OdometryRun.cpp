#include "avm/odometry/OdometryRun.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

#include <mrpt/math/CQuaternion.h>

#include "avm/io/AtomicFile.h"
#include "avm/io/IniOptions.h"
#include "avm/io/RawlogFrameReader.h"
#include "avm/io/ThreadCpuTime.h"
#include "avm/io/TimingSummary.h"
#include "avm/persons/PersonLabels.h"

namespace avm::odometry
{
io::Trajectory OdometryRun::trajectory() const
{
	io::Trajectory t;
	for (const auto& f : frames) t.push_back({f.timestamp, f.estimate.pose});
	return t;
}

std::size_t OdometryRun::lostFrames() const
{
	return std::count_if(frames.begin(), frames.end(), [](const FrameRecord& f) { return !f.estimate.tracked; });
}

std::size_t OdometryRun::keyframes() const
{
	return std::count_if(frames.begin(), frames.end(), [](const FrameRecord& f) { return f.estimate.keyframe; });
}

std::string OdometryRun::timingSummary() const
{
	const auto line = [&](const char* name, double FrameRecord::*field)
	{
		io::TimingSamples ms;
		for (const auto& f : frames) ms.add(f.*field);
		return std::string(name) + " ms/frame: " + io::describeTimes(ms.summary()) + "\n";
	};
	return "frames " + std::to_string(frames.size()) + ", lost " + std::to_string(lostFrames()) + ", keyframes " +
		   std::to_string(keyframes()) + "\n" + line("wall", &FrameRecord::milliseconds) +
		   line("cpu ", &FrameRecord::cpuMilliseconds);
}

void OdometryRun::writeFrameStats(const std::filesystem::path& csv) const
{
	io::writeFileAtomically(csv,
		[&](const std::filesystem::path& tmp)
		{
			std::ofstream out(tmp);
			out << "index,timestamp,ms,cpu_ms,tracked,keyframe,inliers,reprojection_rmse_px,spread,centre_sigma_m,"
				   "prediction_sigma_m,motion_chi2,person_boxes,status\n";
			char line[256];
			for (const auto& f : frames)
			{
				const TrackQuality& q = f.estimate.quality;
				std::snprintf(line, sizeof(line), "%zu,%.6f,%.3f,%.3f,%d,%d,%zu,%.3f,%.3f,%.5f,%.5f,%.2f,%zu,", f.index,
					f.timestamp, f.milliseconds, f.cpuMilliseconds, int(f.estimate.tracked), int(f.estimate.keyframe),
					f.estimate.inliers, f.estimate.reprojectionRmse, q.spread, q.centreSigma, q.predictionSigma,
					q.motionChi2, f.personBoxes);
				out << line << '"' << f.estimate.status << "\"\n";
			}
			if (!out) throw std::runtime_error(csv.string() + ": cannot write");
		});
}

LoopAccuracy loopAccuracy(
	const LoopReport& loop, const mrpt::poses::CPose3D& truthOld, const mrpt::poses::CPose3D& truthNew)
{
	const mrpt::poses::CPose3D truth = truthNew - truthOld;
	return {evaluation::poseError(loop.measured, truth), evaluation::poseError(loop.tracked, truth)};
}

namespace
{
/** The accuracy of the loop verified at frame f, when both its frames have ground truth. */
std::optional<LoopAccuracy> accuracyOf(const OdometryRun& run, const FrameRecord& f)
{
	const auto& old = run.frames.at(f.estimate.loop->candidateFrame);
	if (!f.groundTruth || !old.groundTruth) return std::nullopt;
	return loopAccuracy(*f.estimate.loop, *old.groundTruth, *f.groundTruth);
}

std::string poseColumns(const mrpt::poses::CPose3D& p)
{
	mrpt::math::CQuaternionDouble q;
	p.getAsQuaternion(q);
	char text[160];
	std::snprintf(
		text, sizeof(text), "%.6f,%.6f,%.6f,%.7f,%.7f,%.7f,%.7f", p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.r());
	return text;
}
}  // namespace

void OdometryRun::writeLoops(const std::filesystem::path& csv) const
{
	io::writeFileAtomically(csv,
		[&](const std::filesystem::path& tmp)
		{
			std::ofstream out(tmp);
			out << "frame,timestamp,candidate_frame,candidate_timestamp,inliers,closed,"
				   "measured_x,measured_y,measured_z,measured_qx,measured_qy,measured_qz,measured_qw,"
				   "tracked_x,tracked_y,tracked_z,tracked_qx,tracked_qy,tracked_qz,tracked_qw,"
				   "measured_error_m,measured_error_deg,tracked_error_m,tracked_error_deg\n";
			for (std::size_t i = 0; i < frames.size(); ++i)
			{
				const auto& f = frames[i];
				if (!f.estimate.loop) continue;
				const LoopReport& loop = *f.estimate.loop;
				char line[160];
				std::snprintf(line, sizeof(line), "%zu,%.6f,%zu,%.6f,%zu,%d,", i, f.timestamp, loop.candidateFrame,
					frames.at(loop.candidateFrame).timestamp, loop.inliers, int(f.estimate.loopClosed));
				out << line << poseColumns(loop.measured) << ',' << poseColumns(loop.tracked) << ',';
				if (const auto a = accuracyOf(*this, f))
				{
					std::snprintf(line, sizeof(line), "%.5f,%.4f,%.5f,%.4f", a->measured.metres, a->measured.degrees,
						a->tracked.metres, a->tracked.degrees);
					out << line;
				}
				else
					out << ",,,";
				out << '\n';
			}
			if (!out) throw std::runtime_error(csv.string() + ": cannot write");
		});
}

std::vector<LoopAccuracy> OdometryRun::loopAccuracies() const
{
	std::vector<LoopAccuracy> out;
	for (const auto& f : frames)
		if (f.estimate.loop)
			if (const auto a = accuracyOf(*this, f)) out.push_back(*a);
	return out;
}

std::string OdometryRun::loopSummary() const
{
	const auto verified =
		std::count_if(frames.begin(), frames.end(), [](const FrameRecord& f) { return bool(f.estimate.loop); });
	const auto closed =
		std::count_if(frames.begin(), frames.end(), [](const FrameRecord& f) { return f.estimate.loopClosed; });
	if (verified == 0) return {};
	std::string text = "loops " + std::to_string(verified) + " verified, " + std::to_string(closed) + " closed\n";
	const auto accuracies = loopAccuracies();
	if (accuracies.empty()) return text;
	const auto line = [&](const char* name, evaluation::PoseError LoopAccuracy::*which)
	{
		std::vector<double> metres, degrees;
		for (const auto& a : accuracies) metres.push_back((a.*which).metres), degrees.push_back((a.*which).degrees);
		const auto m = evaluation::statisticsOf(metres), d = evaluation::statisticsOf(degrees);
		char out[160];
		std::snprintf(out, sizeof(out), "  %s: mean %.2f cm %.2f deg, max %.2f cm %.2f deg\n", name, 100 * m.mean,
			d.mean, 100 * m.max, d.max);
		return std::string(out);
	};
	return text + "loop poses against ground truth, relative to the old keyframe (" +
		   std::to_string(accuracies.size()) + " loops):\n" + line("measured", &LoopAccuracy::measured) +
		   line("tracked ", &LoopAccuracy::tracked);
}

OdometryRun runOdometry(const std::filesystem::path& rawlog, const TOdometryOptions& options,
	const PersonBoxSource& personBoxes, std::size_t maxFrames, const std::function<void(std::size_t)>& progress)
{
	io::RawlogFrameReader reader(rawlog);
	OdometryRun run;
	std::optional<VisualOdometry> vo;
	while (auto frame = reader.next())
	{
		if (maxFrames && run.frames.size() >= maxFrames) break;
		if (!vo) vo.emplace(options, frame->groundTruth.value_or(mrpt::poses::CPose3D()));
		FrameRecord rec;
		rec.index = frame->index;
		rec.timestamp = frame->timestamp();
		rec.groundTruth = frame->groundTruth;
		const auto boxes = personBoxes ? personBoxes(*frame) : std::vector<cv::Rect>{};
		rec.personBoxes = boxes.size();
		const auto start = std::chrono::steady_clock::now();
		const double cpuStart = io::threadCpuMs();
		rec.estimate = vo->process(*frame->observation, boxes);
		rec.cpuMilliseconds = io::threadCpuMs() - cpuStart;
		rec.milliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
		run.frames.push_back(std::move(rec));
		if (progress) progress(run.frames.size());
	}
	if (vo)
	{
		// The poses as the closed loops corrected them, one per frame.
		const auto corrected = vo->trajectory();
		for (std::size_t i = 0; i < run.frames.size(); ++i) run.frames[i].estimate.pose = corrected[i];
		run.stageTimes = vo->stageTimesText();
	}
	return run;
}

std::vector<cv::Rect> personBoxesFromLabels(const mrpt::obs::CObservation3DRangeScan& obs)
{
	std::vector<cv::Rect> boxes;
	const int cols = static_cast<int>(obs.rangeImage.cols());
	// Every labelled pixel counts, with depth or not: the box masks features,
	// and a person's pixels without depth still carry moving texture.
	for (const auto& person : persons::personPixelsFromLabels(obs, persons::kPersonLabel, 0))
	{
		int u0 = cols, v0 = std::numeric_limits<int>::max(), u1 = -1, v1 = -1;
		for (const auto i : person)
		{
			const int v = static_cast<int>(i) / cols, u = static_cast<int>(i) % cols;
			u0 = std::min(u0, u), u1 = std::max(u1, u);
			v0 = std::min(v0, v), v1 = std::max(v1, v);
		}
		if (u1 >= 0) boxes.emplace_back(u0, v0, u1 - u0 + 1, v1 - v0 + 1);
	}
	return boxes;
}

TOdometryOptions loadOdometryOptions(
	const std::filesystem::path& ini, const std::string& section, std::vector<std::string>& unknownKeys)
{
	return io::loadOptionsFromFile<TOdometryOptions>(ini, section, unknownKeys);
}
}  // namespace avm::odometry
