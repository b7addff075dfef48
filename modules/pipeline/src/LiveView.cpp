#include "avm/pipeline/LiveView.h"

#include <cstdio>
#include <utility>

namespace avm::pipeline
{
LiveView::LiveView(const viewer::TViewerOptions& options, const std::string& title, const std::atomic<bool>* stop)
	: m_view(
		  [&]
		  {
			  auto o = options;
			  o.title = title;
			  return o;
		  }()),
	  m_stop(stop)
{
}

void LiveView::onFrameMapped(const MappedFrame& frame)
{
	if (!m_view.due()) return;
	auto s = frame.snapshot(m_view.snapshotOptions());
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

void LiveView::onRunFinished(const FinishedRun& run)
{
	if (!m_screenshot.empty() && m_view.waitUntilDrawn(30)) m_view.saveScreenshot(m_screenshot);
	if (!m_waitsAtEnd || !m_view.isOpen()) return;
	std::printf("finished: the view stays open until it is closed or a key is pressed\n");
	std::fflush(stdout);
	auto s = run.snapshot();
	s.intrinsics = m_intrinsics;
	m_view.showFinished(std::move(s), m_stop);
}
}  // namespace avm::pipeline
