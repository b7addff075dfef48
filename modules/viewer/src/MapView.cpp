#include "avm/persons/PersonColour.h"
#include "avm/viewer/MapView.h"

#include <mrpt/gui/CDisplayWindow.h>
#include <mrpt/gui/CDisplayWindow3D.h>
#include <mrpt/opengl/CBox.h>
#include <mrpt/opengl/CFrustum.h>
#include <mrpt/opengl/CGridPlaneXY.h>
#include <mrpt/opengl/COctoMapVoxels.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CSphere.h>
#include <mrpt/opengl/CText.h>
#include <mrpt/opengl/stock_objects.h>
#include <mrpt/system/CObserver.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <set>
#include <stdexcept>
#include <string>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "CViewVoxels.h"
#include "ScreenGrab.h"
#include "avm/io/RgbdFrame.h"
#include "avm/maps/MapColours.h"
#include "avm/viewer/StatusText.h"

namespace avm::viewer
{
namespace
{
using Clock = std::chrono::steady_clock;

// The trees, regions, trajectory and persons as in map.3Dscene and the
// pictures (avm/maps/MapColours.h, avm/persons/PersonColour.h).
using persons::kPersonColour;
const mrpt::img::TColor kCameraColour(20, 20, 20), kGridColour(190, 190, 190);
const mrpt::img::TColorf kBackground(0.97f, 0.97f, 0.97f);
const mrpt::img::TColor kFeatureColour(0, 200, 0), kMaskedFeatureColour(255, 0, 0);

enum VoxelSet : unsigned
{
	LowOccupied,
	HighOccupied,
	LowFree,
	HighFree,
	PersonShapes,  //!< each person's last shape, at the high resolution
	VoxelSetCount
};

mrpt::math::TBoundingBox occupiedBox(const MapSnapshot& s)
{
	mrpt::math::TBoundingBox box({0, 0, 0}, {0, 0, 0});
	bool first = true;
	const auto extend = [&](const mrpt::math::TPoint3D& p)
	{
		if (first)
			box = mrpt::math::TBoundingBox(p, p), first = false;
		else
			box.updateWithPoint(p);
	};
	for (const auto* set : {&s.lowOccupied, &s.highOccupied})
		for (const auto& v : *set) extend(mrpt::math::TPoint3D(v.centre.x, v.centre.y, v.centre.z));
	for (const auto& p : s.trajectory) extend(p.translation());
	return box;
}

mrpt::img::CImage annotatedImage(const MapSnapshot& s, bool features)
{
	mrpt::img::CImage img = s.image.makeDeepCopy();
	if (!img.isColor()) img = img.colorImage();
	for (const auto& b : s.imageBoxes)
	{
		img.rectangle(int(b.x0), int(b.y0), int(b.x1), int(b.y1), kPersonColour, 3);
		char text[64];
		if (b.personId)
			std::snprintf(text, sizeof(text), "person %u %.2f", b.personId, b.score);
		else
			std::snprintf(text, sizeof(text), "person %.2f", b.score);
		img.textOut(int(b.x0) + 4, std::max(0, int(b.y0) - 14), text, kPersonColour);
	}
	if (features)
	{
		for (const auto& f : s.features) img.drawMark(int(f.x), int(f.y), kFeatureColour, '+', 4);
		for (const auto& f : s.maskedFeatures) img.drawMark(int(f.x), int(f.y), kMaskedFeatureColour, 'x', 4);
	}
	return img;
}

/** Refills `voxels` with the snapshot's: one set per tree and occupancy,
 *  shown as toggled, and the persons' last shapes. */
void fillVoxels(CViewVoxels& voxels, const MapSnapshot& s, const ViewToggles& t, const mrpt::math::TBoundingBox& box)
{
	using mrpt::opengl::COctoMapVoxels;
	const auto fill = [&](VoxelSet set, const std::vector<SnapshotVoxel>& from, const mrpt::img::TColor& c)
	{
		voxels.clearVoxels(set);
		for (const auto& v : from) voxels.push_back_Voxel(set, COctoMapVoxels::TVoxel(v.centre, v.size, c));
	};
	fill(LowOccupied, s.lowOccupied, kLowColour);
	fill(HighOccupied, s.highOccupied, kHighColour);
	fill(LowFree, s.lowFree, kLowFreeColour);
	fill(HighFree, s.highFree, kHighFreeColour);
	voxels.clearVoxels(PersonShapes);
	for (const auto& p : s.persons)
		for (const auto& v : p.shape)
			voxels.push_back_Voxel(
				PersonShapes, COctoMapVoxels::TVoxel(v, static_cast<float>(s.highResolution), p.shapeColour));
	voxels.showVoxels(LowOccupied, t.lowTree);
	voxels.showVoxels(LowFree, t.lowTree && t.freeSpace);
	voxels.showVoxels(HighOccupied, t.highTree);
	voxels.showVoxels(HighFree, t.highTree && t.freeSpace);
	voxels.enableCubeTransparency(t.freeSpace);
	voxels.setBoundingBox(box.min, box.max);
}

/** The regions' boxes and the persons (a dot and the id) into `objects`. */
void insertRegionsAndPersons(mrpt::opengl::CSetOfObjects& objects, const MapSnapshot& s)
{
	using namespace mrpt::opengl;
	for (const auto& r : s.regions)
	{
		for (const auto& b : r.boxes)
		{
			auto cube = CBox::Create(b.min, b.max, true /*wireframe*/, 2.0f);
			cube->setColor_u8(kRegionColour);
			cube->setBoxBorderColor(kRegionColour);  // what MRPT 2.5.8 draws a wireframe box with
			objects.insert(cube);
		}
	}
	for (const auto& p : s.persons)
	{
		auto dot = CSphere::Create(0.12f, 12);
		dot->setLocation(p.position);
		dot->setColor_u8(kPersonColour);
		objects.insert(dot);
		auto label = CText::Create("person " + std::to_string(p.id));
		label->setFont("sans", 18);
		label->setLocation(p.position.x, p.position.y, p.position.z + 0.15);
		label->setColor_u8(kPersonColour);
		objects.insert(label);
	}
}

/** The camera's path and, when known, its frustum and axes into `objects`. */
void insertCameraPath(mrpt::opengl::CSetOfObjects& objects, const MapSnapshot& s)
{
	using namespace mrpt::opengl;
	if (s.trajectory.size() > 1)
	{
		auto lines = CSetOfLines::Create();
		for (std::size_t i = 1; i < s.trajectory.size(); ++i)
		{
			const auto a = s.trajectory[i - 1].translation(), b = s.trajectory[i].translation();
			lines->appendLine(a.x, a.y, a.z, b.x, b.y, b.z);
		}
		lines->setLineWidth(3);
		lines->setColor_u8(kTrajectoryColour);
		objects.insert(lines);
	}
	if (s.camera)
	{
		// CFrustum looks along +X; the camera pose is the optical frame (z
		// forward).
		auto frustum = s.intrinsics ? CFrustum::Create(*s.intrinsics, 1e-3)
									: CFrustum::Create(0.05f, 0.5f, 60.0f, 45.0f, 2.0f, true, false);
		frustum->setPose(*s.camera + io::opticalToSensorPose());
		frustum->setColor_u8(kCameraColour);
		objects.insert(frustum);
		auto axes = stock_objects::CornerXYZSimple(0.2f, 2.0f);
		axes->setPose(*s.camera);
		objects.insert(axes);
	}
}

/** What the 3D view shows of a snapshot besides the voxels: a floor grid
 *  under the map, the regions, persons and the camera. */
mrpt::opengl::CSetOfObjects::Ptr sceneOf(const MapSnapshot& s, const mrpt::math::TBoundingBox& box)
{
	using namespace mrpt::opengl;
	auto objects = CSetOfObjects::Create();
	{
		const double margin = 1.0;
		auto grid = CGridPlaneXY::Create(float(box.min.x - margin), float(box.max.x + margin),
			float(box.min.y - margin), float(box.max.y + margin), float(box.min.z), 1.0f);
		grid->setColor_u8(kGridColour);
		objects->insert(grid);
	}
	insertRegionsAndPersons(*objects, s);
	insertCameraPath(*objects, s);
	return objects;
}

/** The status lines, the keys and what is shown, over the 3D view, fitted to
 *  its width [px]. */
void writeStatusText(
	mrpt::opengl::COpenGLViewport& vp, const MapSnapshot& s, const ViewToggles& t, bool isPaused, double widthPx)
{
	// A message is added once and then only its text changes: adding it again
	// drops its text object on this thread, which leaks its OpenGL buffers
	// (see GlThreadRelease). A place a narrower window no longer needs is blanked.
	std::set<std::size_t> written;
	for (const auto& m : statusMessages(s, t, isPaused, widthPx))
	{
		if (!vp.updateTextMessage(m.id, m.text)) vp.addTextMessage(m.x, m.y, m.text, m.id, m.font);
		written.insert(m.id);
	}
	std::vector<std::size_t> unused;
	for (const auto& [id, message] : vp.getTextMessages().messages)
		if (!written.count(id) && !message.text.empty()) unused.push_back(id);
	for (const auto id : unused) vp.updateTextMessage(id, "");
}

/** Points the view at the middle of `box`, from the side the camera path
 *  starts on, far enough to see all of it. */
void frameBox(mrpt::gui::CDisplayWindow3D& win, const MapSnapshot& s, const mrpt::math::TBoundingBox& box)
{
	const auto c = (box.min + box.max) * 0.5;
	const double radius = std::max(1.0, (box.max - box.min).norm() / 2);
	double azimuth = -90;
	if (!s.trajectory.empty())
	{
		const auto d = s.trajectory.front().translation() - c;
		if (std::hypot(d.x, d.y) > 1e-6) azimuth = mrpt::RAD2DEG(std::atan2(d.y, d.x));
	}
	win.setCameraPointingToPoint(float(c.x), float(c.y), float(c.z));
	win.setCameraZoom(float(2.2 * radius));
	win.setCameraAzimuthDeg(float(azimuth));
	win.setCameraElevationDeg(35.0f);
}

/** Lets the objects taken off the scene go on the GL thread, after a render.
 *  MRPT 2.5.8 frees an object's OpenGL buffers only on the thread that made
 *  them (the window's GL thread, at the object's first render) and silently
 *  leaks them on any other (Buffer::RAII_Impl::destroy); a view that dropped
 *  its old scene on its own thread leaked every redraw's voxels, so its
 *  memory grew with the run. */
class GlThreadRelease : public mrpt::system::CObserver
{
   public:
	explicit GlThreadRelease(unsigned width) : m_width(width) {}
	void add(mrpt::opengl::CRenderizable::Ptr object)
	{
		std::lock_guard lock(m_mutex);
		m_objects.push_back(std::move(object));
	}
	/** [px] The viewport's width at its last render (the window's, resized
	 *  or not): its render state is the GL thread's, so it is read here. */
	unsigned width() const { return m_width; }

   protected:
	void OnEvent(const mrpt::system::mrptEvent& e) override
	{
		if (!e.isOfType<mrpt::opengl::mrptEventGLPostRender>()) return;
		const auto& rendered = static_cast<const mrpt::opengl::mrptEventGLPostRender&>(e);
		if (const auto w = rendered.source_viewport->getRenderMatrices().viewport_width; w > 0) m_width = w;
		std::vector<mrpt::opengl::CRenderizable::Ptr> released;
		std::lock_guard lock(m_mutex);
		released.swap(m_objects);
	}  // destroyed here, on the GL thread

   private:
	std::mutex m_mutex;
	std::vector<mrpt::opengl::CRenderizable::Ptr> m_objects;
	std::atomic<unsigned> m_width;
};
}  // namespace

struct MapView::Windows
{
	explicit Windows(unsigned width) : release(width) {}
	GlThreadRelease release;  //!< declared first: it outlives the window it observes
	mrpt::gui::CDisplayWindow3D::Ptr view3D;
	mrpt::gui::CDisplayWindow::Ptr image;       //!< opened with the first image
	CViewVoxels::Ptr voxels;                    //!< in the scene for the view's life, refilled by each draw
	mrpt::opengl::CSetOfObjects::Ptr onScreen;  //!< the scene's other objects, replaced by each draw
};

MapView::MapView(const TViewerOptions& options)
	: m_options(options), m_windows(std::make_unique<Windows>(options.width))
{
	if (!(m_options.fps > 0 && m_options.fps <= 60))
		throw std::invalid_argument("the view's fps " + std::to_string(m_options.fps) + " is out of range (0, 60]");
#ifdef __GLIBC__
	// The view's blocks of a few hundred kB to a few MB (each redraw's colour
	// image as MRPT and wxWidgets copy it, the voxels' triangle buffers) are
	// made and freed at every redraw, on three threads. glibc mmaps such
	// blocks at first, but the first free of one raises its mmap threshold
	// to that size (up to 32 MB), after which they come from the threads'
	// malloc arenas, which keep the freed space: a sub300 run held 50-60 MB
	// free in them. Fixed at glibc's own starting values, they are mmapped and
	// go back to the system when freed. This undoes, for a run with a view,
	// io::runProgram's setting for speed (keep freed blocks for reuse): with a
	// view open, memory is the scarcer of the two.
	mallopt(M_MMAP_THRESHOLD, 128 * 1024);
	mallopt(M_TRIM_THRESHOLD, 128 * 1024);
#endif
	m_windows->view3D = mrpt::gui::CDisplayWindow3D::Create(m_options.title, m_options.width, m_options.height);
	if (!m_windows->view3D || !m_windows->view3D->isOpen())
		throw std::runtime_error("cannot open the 3D window (is there a display? DISPLAY is " +
								 std::string(std::getenv("DISPLAY") ? std::getenv("DISPLAY") : "unset") + ")");
	m_windows->view3D->setPos(0, 0);
	{
		mrpt::opengl::COpenGLScene::Ptr scene;
		mrpt::gui::CDisplayWindow3DLocker lock(*m_windows->view3D, scene);
		scene->getViewport()->setCustomBackgroundColor(kBackground);
		m_windows->release.observeBegin(*scene->getViewport());
		m_windows->voxels = std::make_shared<CViewVoxels>();
		m_windows->voxels->resizeVoxelSets(VoxelSetCount);
		m_windows->voxels->showGridLines(false);
		scene->insert(m_windows->voxels);
	}
	m_thread = std::thread([this] { loop(); });
}

MapView::~MapView()
{
	m_stop = true;
	m_changed.notify_all();
	if (m_thread.joinable()) m_thread.join();
	m_windows->image.reset();
	m_windows->view3D.reset();
}

bool MapView::due() const
{
	std::lock_guard lock(m_mutex);
	return !m_closed && Clock::now() - m_lastShown >= std::chrono::duration<double>(1.0 / m_options.fps);
}

void MapView::show(MapSnapshot snapshot)
{
	std::optional<MapSnapshot> replaced;  // freed outside the lock
	{
		std::lock_guard lock(m_mutex);
		replaced.swap(m_pending);
		m_pending = std::move(snapshot);
		m_lastShown = Clock::now();
		++m_given;
	}
	m_changed.notify_all();
}

SnapshotOptions MapView::snapshotOptions() const
{
	std::lock_guard lock(m_mutex);
	SnapshotOptions o;
	o.freeSpace = m_toggles.freeSpace;
	return o;
}

bool MapView::isOpen() const
{
	std::lock_guard lock(m_mutex);
	return !m_closed;
}

bool MapView::paused() const
{
	std::lock_guard lock(m_mutex);
	return m_paused;
}

ViewToggles MapView::toggles() const
{
	std::lock_guard lock(m_mutex);
	return m_toggles;
}

bool MapView::waitWhilePaused()
{
	std::unique_lock lock(m_mutex);
	m_changed.wait(lock, [&] { return !m_paused || m_steps > 0 || m_closed; });
	if (m_paused && m_steps > 0) --m_steps;
	return !m_closed;
}

bool MapView::waitUntilDrawn(double timeoutSeconds)
{
	std::unique_lock lock(m_mutex);
	const auto target = m_given;
	return m_changed.wait_for(
			   lock, std::chrono::duration<double>(timeoutSeconds), [&] { return m_drawn >= target || m_closed; }) &&
		   m_drawn >= target;
}

void MapView::waitUntilClosed()
{
	std::unique_lock lock(m_mutex);
	m_changed.wait(lock, [&] { return m_closed; });
}

void MapView::showFinished(MapSnapshot final, const std::atomic<bool>* stop)
{
	final.status.note = "finished: a key (but f l h m r) or closing the window exits";
	{
		std::lock_guard lock(m_mutex);
		m_finished = true;
		m_paused = false;
	}
	m_windows->view3D->setWindowTitle(m_options.title + ": finished");
	show(std::move(final));
	std::unique_lock lock(m_mutex);
	while (!m_closed && !m_endKey && !(stop && stop->load())) m_changed.wait_for(lock, std::chrono::milliseconds(100));
}

void MapView::close()
{
	{
		std::lock_guard lock(m_mutex);
		m_closed = true;
	}
	m_changed.notify_all();
}

void MapView::saveScreenshot(const std::filesystem::path& png, double settleSeconds) const
{
	std::this_thread::sleep_for(std::chrono::duration<double>(settleSeconds));
	saveXScreenshot(m_options.title, png);
}

void MapView::handleKey(int key)
{
	// Under the mutex (called from loop()). Once the run has finished, the
	// keys that change what is shown still do; any other ends the view.
	const int k = std::tolower(key);
	if (m_finished && (k == 0 || std::string("flhmr").find(char(k)) == std::string::npos))
	{
		m_endKey = true;
		return;
	}
	switch (k)
	{
		case ' ':
			m_paused = !m_paused;
			m_steps = 0;
			break;
		case 'n':
			if (m_paused) ++m_steps;
			break;
		case 'f':
			m_toggles.freeSpace = !m_toggles.freeSpace;
			break;
		case 'l':
			m_toggles.lowTree = !m_toggles.lowTree;
			break;
		case 'h':
			m_toggles.highTree = !m_toggles.highTree;
			break;
		case 'm':
			m_toggles.features = !m_toggles.features;
			break;
		case 'r':
			m_resetCamera = true;
			break;
		default:
			return;
	}
	m_redraw = true;
}

void MapView::loop()
{
	const auto period = std::chrono::duration<double>(1.0 / m_options.fps);
	while (!m_stop)
	{
		std::shared_ptr<const MapSnapshot> toDraw;
		bool reset = false, closedNow = false;
		std::uint64_t given = 0;
		{
			std::unique_lock lock(m_mutex);
			m_changed.wait_for(lock, std::chrono::milliseconds(20), [&] { return m_stop.load(); });
			if (m_stop) break;
			for (auto* w : {static_cast<mrpt::gui::CBaseGUIWindow*>(m_windows->view3D.get()),
					 static_cast<mrpt::gui::CBaseGUIWindow*>(m_windows->image.get())})
				if (w && w->keyHit()) handleKey(w->getPushedKey());
			if (!m_closed && !m_windows->view3D->isOpen()) m_closed = closedNow = true;
			if (m_closed) m_pending.reset();
			const bool elapsed = Clock::now() - m_lastDraw >= period;
			if (m_pending && elapsed)
			{
				m_current = std::make_shared<const MapSnapshot>(std::move(*m_pending));
				m_pending.reset();
				toDraw = m_current;
			}
			else if (m_redraw && m_current)
				toDraw = m_current;
			if (toDraw)
			{
				reset = m_resetCamera;
				m_resetCamera = m_redraw = false;
				m_lastDraw = Clock::now();
				given = m_given;
			}
		}
		if (closedNow)
		{
			m_changed.notify_all();
			continue;
		}
		if (!toDraw) continue;
		draw(*toDraw, reset);
		{
			std::lock_guard lock(m_mutex);
			m_drawn = std::max(m_drawn, given);
		}
		m_changed.notify_all();
	}
	// The windows are closed by the destructor; a close() leaves them for it.
}

void MapView::draw(const MapSnapshot& s, bool resetCamera)
{
	const ViewToggles t = toggles();
	bool isPaused = paused();
	auto& win = *m_windows->view3D;
	const auto box = occupiedBox(s);
	const auto objects = sceneOf(s, box);
	{
		mrpt::opengl::COpenGLScene::Ptr scene;
		mrpt::gui::CDisplayWindow3DLocker lock(win, scene);
		// The viewport stays (clearing the scene would drop it, its text
		// included, on this thread); only the objects are replaced.
		auto vp = scene->getViewport();
		if (m_windows->onScreen)
		{
			vp->removeObject(m_windows->onScreen);
			m_windows->release.add(std::move(m_windows->onScreen));
		}
		vp->insert(objects);
		m_windows->onScreen = objects;
		fillVoxels(*m_windows->voxels, s, t, box);
		writeStatusText(*vp, s, t, isPaused, m_windows->release.width());
	}
	// The view frames the map as it grows (a live run starts with a few
	// voxels), until the user resets it; 'r' frames it again.
	const double extent = (box.max - box.min).norm();
	if (resetCamera || extent > 1.25 * m_framedExtent)
	{
		m_framedExtent = extent;
		frameBox(win, s, box);
	}
	win.forceRepaint();

	if (!s.image.isEmpty())
	{
		if (!m_windows->image)
		{
			m_windows->image = mrpt::gui::CDisplayWindow::Create(
				m_options.title + ": camera", s.image.getWidth(), s.image.getHeight());
			m_windows->image->setPos(int(m_options.width) + 10, 0);
		}
		m_windows->image->showImage(annotatedImage(s, t.features));
	}
}
void exitAfterView(int status)
{
	std::cout.flush();
	std::cerr.flush();
	std::fflush(nullptr);
	std::_Exit(status);
}
}  // namespace avm::viewer
