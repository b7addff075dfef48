#include "avm/odometry/OdometryRun.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

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
		const auto s = ms.summary();
		char text[160];
		std::snprintf(text, sizeof(text), "%s ms/frame: mean %.1f median %.1f p95 %.1f max %.1f\n", name, s.meanMs,
			s.medianMs, s.p95Ms, s.maxMs);
		return std::string(text);
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
			out << "index,timestamp,ms,cpu_ms,tracked,keyframe,inliers,reprojection_rmse_px,person_boxes,status\n";
			char line[128];
			for (const auto& f : frames)
			{
				std::snprintf(line, sizeof(line), "%zu,%.6f,%.3f,%.3f,%d,%d,%zu,%.3f,%zu,", f.index, f.timestamp,
					f.milliseconds, f.cpuMilliseconds, int(f.estimate.tracked), int(f.estimate.keyframe),
					f.estimate.inliers, f.estimate.reprojectionRmse, f.personBoxes);
				out << line << '"' << f.estimate.status << "\"\n";
			}
			if (!out) throw std::runtime_error(csv.string() + ": cannot write");
		});
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
