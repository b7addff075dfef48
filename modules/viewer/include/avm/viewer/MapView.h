// avm::viewer::MapView — the live view of a run in MRPT's own windows: a
// mrpt::gui::CDisplayWindow3D with both trees, the regions, the person tracks,
// the trajectory and the camera frustum, and a mrpt::gui::CDisplayWindow with
// the colour image and the person boxes.
//
// The view has a thread of its own that reads the keys and draws: show() only
// hands a snapshot over (the latest wins) and returns, so a pipeline is never
// held up by drawing; it is drawn at most `gui_fps` times a second.
//
// A pipeline's loop, per frame:
//     view.waitWhilePaused();                      // returns at once unless paused
//     if (!view.isOpen()) stop the run as Ctrl-C does;
//     if (view.due()) { auto s = snapshotOf(map, view.snapshotOptions()); ...; view.show(std::move(s)); }
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "avm/viewer/MapSnapshot.h"
#include "avm/viewer/TViewerOptions.h"

namespace avm::viewer
{
/** What is shown; the keys change it. */
struct ViewToggles
{
	bool lowTree = true;     //!< 'l'
	bool highTree = true;    //!< 'h'
	bool freeSpace = false;  //!< 'f'
	bool features = false;   //!< 'm' odometry features in the image (masked ones in red)
};

class MapView
{
   public:
	/** Opens the 3D window (the image window opens with the first snapshot
	 *  that has an image). Throws std::runtime_error when no window can be
	 *  opened (no display). */
	explicit MapView(const TViewerOptions& options);
	/** Closes the windows. */
	~MapView();
	MapView(const MapView&) = delete;
	MapView& operator=(const MapView&) = delete;

	/** True when the last show() was at least 1/gui_fps ago (and the view
	 *  is open): take snapshots only then. */
	bool due() const;
	/** Hands the snapshot to the view's thread and returns (never draws on
	 *  the caller's thread). A snapshot not drawn yet is replaced. */
	void show(MapSnapshot snapshot);
	/** What snapshotOf() should take for this view (free space once 'f' is on). */
	SnapshotOptions snapshotOptions() const;

	/** False once the user closed the 3D window (or close() was called). */
	bool isOpen() const;
	/** Space pressed (and not pressed again). */
	bool paused() const;
	/** Returns at once when not paused. While paused, blocks until space
	 *  resumes, 'n' allows one step (the view stays paused), or the window
	 *  closes. Returns isOpen(). */
	bool waitWhilePaused();
	/** Blocks until the last snapshot given to show() is drawn (or the
	 *  timeout passes, or the window closes); true when it was drawn. */
	bool waitUntilDrawn(double timeoutSeconds);
	/** Blocks until the user closes the window. */
	void waitUntilClosed();
	/** The run is over: shows `final` with "finished" in the status line and
	 *  the window title, then blocks until the user closes the window, presses
	 *  a key other than the view's own (f l h m r still change what is shown),
	 *  or `*stop` becomes true (Ctrl-C), as MRPT's apps wait at their end. */
	void showFinished(MapSnapshot final, const std::atomic<bool>* stop);
	void close();

	/** Saves what the X server shows of the view's windows (found by their
	 *  title; the whole screen when not found) as a PNG: the screen as it
	 *  is, unlike the GL read-back of getLastWindowImage(), which returns
	 *  black under Xvfb. Call after waitUntilDrawn(); `settleSeconds` lets
	 *  the GL thread paint first. Throws std::runtime_error on failure. */
	void saveScreenshot(const std::filesystem::path& png, double settleSeconds = 1.0) const;

	ViewToggles toggles() const;
	const TViewerOptions& options() const { return m_options; }

   private:
	struct Windows;
	void loop();
	void handleKey(int key);
	void draw(const MapSnapshot& s, bool resetCamera);

	TViewerOptions m_options;
	std::unique_ptr<Windows> m_windows;
	mutable std::mutex m_mutex;
	std::condition_variable m_changed;
	std::optional<MapSnapshot> m_pending;
	std::shared_ptr<const MapSnapshot> m_current;  //!< the snapshot on screen
	std::uint64_t m_given = 0, m_drawn = 0;        //!< snapshots given to show() / drawn
	std::chrono::steady_clock::time_point m_lastDraw{}, m_lastShown{};
	ViewToggles m_toggles;
	bool m_redraw = false, m_resetCamera = true, m_paused = false, m_closed = false;
	bool m_finished = false, m_endKey = false;  //!< showFinished() called; a key ended it
	double m_framedExtent = 0;                  //!< [m] diagonal of the map the camera last framed (view thread only)
	int m_steps = 0;
	std::atomic<bool> m_stop{false};
	std::thread m_thread;
};
/** Ends a program that opened a view: flushes the standard streams and
 *  exits with `status` without running static destructors. A complete
 *  avm-map --gui run, every output written, once aborted at exit with
 *  "free(): invalid pointer" on a loaded 2-core machine, most likely MRPT
 *  2.5.8's wxWidgets thread still tearing its windows down while static
 *  objects were destroyed. Outputs are
 *  flushed to the disk when written (io::writeFileAtomically), so nothing is
 *  lost by skipping the destructors. Not for runs without a view: the leak
 *  checks of the sanitizer builds run at exit. */
[[noreturn]] void exitAfterView(int status);
}  // namespace avm::viewer
