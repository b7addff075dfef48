// The live view of a run (avm-map --gui) as an observer of it
// (avm/pipeline/FrameObserver.h): MapView shown the map before each frame's
// insertion, at most gui_fps times a second. Space pauses the run between two
// frames; closing the window ends it as Ctrl-C does.
#pragma once

#include <mrpt/img/TCamera.h>
#include <mrpt/system/CTicTac.h>

#include <atomic>
#include <filesystem>
#include <optional>
#include <string>

#include "avm/pipeline/FrameObserver.h"
#include "avm/viewer/MapView.h"

namespace avm::viewer
{
class LiveView : public pipeline::FrameObserver
{
   public:
	/** Opens the view's window; throws when it cannot (no display). `stop`
	 *  (may be null) also ends the wait at the end. */
	LiveView(const TViewerOptions& options, const std::atomic<bool>* stop);

	/** After the outputs, save the X server's picture of the view to this
	 *  PNG (a run with a scripted end, for tests and documentation). */
	void setScreenshot(const std::filesystem::path& png) { m_screenshot = png; }
	/** Once the outputs are written, keep showing the finished map until the
	 *  user closes the window or presses a key (or `stop` is set), as MRPT's
	 *  apps do; off by default, so that a program that maps never blocks on a
	 *  user unless it asks to. */
	void setWaitsAtEnd(bool wait) { m_waitsAtEnd = wait; }

	bool betweenFrames(pipeline::RunState& /*run*/) override { return m_view.waitWhilePaused(); }
	void onFrameMapped(const pipeline::MappedFrame& frame) override;
	void onRunFinished(const pipeline::FinishedRun& run) override;
	bool showsFeatures() const override { return true; }

   private:
	MapView m_view;
	const std::atomic<bool>* m_stop;
	std::filesystem::path m_screenshot;  // "" = none
	bool m_waitsAtEnd = false;
	std::optional<std::size_t> m_firstFrameShown;  // the fps: frames mapped since
	mrpt::system::CTicTac m_shownFor;
	std::optional<mrpt::img::TCamera> m_intrinsics;  // of the last frame shown: the final view's frustum
};
}  // namespace avm::viewer
