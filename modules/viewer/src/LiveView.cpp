#include "avm/viewer/LiveView.h"

#include <cstdio>
#include <utility>

#include "avm/pipeline/MappingPipeline.h"

namespace avm::viewer
{
namespace
{
/** The map, the trajectory and the run's figures. */
MapSnapshot mapSnapshot(const CAdaptiveOctoMap& map, const io::Trajectory& trajectory,
	std::optional<std::size_t> switchFrame, const SnapshotOptions& options)
{
	auto s = snapshotOf(map, options);
	for (const auto& p : trajectory) s.trajectory.push_back(p.pose);
	s.status.switchFrame = switchFrame;
	return s;
}

/** What the view shows of a frame before its insertion. */
MapSnapshot frameSnapshot(const pipeline::MappedFrame& f, const SnapshotOptions& options)
{
	auto s = mapSnapshot(f.map, f.trajectory, f.switchFrame, options);
	s.status.stageMs = f.stageMeansMs;
	s.camera = f.pose;
	const auto& obs = *f.frame.observation;
	s.intrinsics = obs.cameraParamsIntensity;
	if (obs.hasIntensityImage) s.image = obs.intensityImage;
	// Drawn on the current image: they are detection_lag_frames old.
	for (const auto& p : f.latestPersons) s.imageBoxes.push_back({p.x0, p.y0, p.x1, p.y1, p.personId, p.score});
	s.status.frame = f.frame.index;
	s.features = f.features;
	s.maskedFeatures = f.maskedFeatures;
	return s;
}

/** The finished map, the camera at its last pose. */
MapSnapshot finalSnapshot(const pipeline::FinishedRun& run)
{
	SnapshotOptions all;
	all.freeSpace = true;  // taken once: 'f' can show it on the finished map
	const auto& summary = run.summary;
	auto s = mapSnapshot(run.map, run.trajectory, summary.switchFrame, all);
	s.status.stageMs = {
		{"odometry", summary.odometry.meanMs}, {"detection", summary.detection.meanMs}, {"map", summary.map.meanMs}};
	if (!s.trajectory.empty()) s.camera = s.trajectory.back();
	s.status.frame = run.lastFrame;
	return s;
}
}  // namespace

LiveView::LiveView(const TViewerOptions& options, const std::atomic<bool>* stop) : m_view(options), m_stop(stop) {}

void LiveView::onFrameMapped(const pipeline::MappedFrame& frame)
{
	if (!m_view.due()) return;
	auto s = frameSnapshot(frame, m_view.snapshotOptions());
	if (!m_firstFrameShown)
	{
		m_firstFrameShown = frame.framesMapped;
		m_shownFor.Tic();
	}
	else
		s.status.fps = double(frame.framesMapped - *m_firstFrameShown) / m_shownFor.Tac();
	m_intrinsics = frame.frame.observation->cameraParamsIntensity;
	m_view.show(std::move(s));
}

void LiveView::onRunFinished(const pipeline::FinishedRun& run)
{
	if (!m_screenshot.empty() && m_view.waitUntilDrawn(30)) m_view.saveScreenshot(m_screenshot);
	if (!m_waitsAtEnd || !m_view.isOpen()) return;
	std::printf("finished: the view stays open until it is closed or a key is pressed\n");
	std::fflush(stdout);
	auto s = finalSnapshot(run);
	s.intrinsics = m_intrinsics;
	m_view.showFinished(std::move(s), m_stop);
}
}  // namespace avm::viewer
