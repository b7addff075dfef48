#include "ScreenGrab.h"

#include <mrpt/img/CImage.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

// Xlib last: its macros (None, Status, Bool…) clash with other headers.
#include <X11/Xlib.h>
#include <X11/Xutil.h>

namespace avm::viewer
{
namespace
{
struct Rect
{
	int x0, y0, x1, y1;
};

/** Windows below `w` (depth first) whose WM_NAME starts with `prefix`. */
void findWindows(Display* d, Window root, Window w, const std::string& prefix, std::vector<Rect>& out)
{
	char* name = nullptr;
	if (XFetchName(d, w, &name) && name)
	{
		const bool match = std::string(name).rfind(prefix, 0) == 0;
		XFree(name);
		XWindowAttributes a;
		if (match && XGetWindowAttributes(d, w, &a) && a.map_state == IsViewable)
		{
			int x = 0, y = 0;
			Window child;
			XTranslateCoordinates(d, w, root, 0, 0, &x, &y, &child);
			out.push_back({x, y, x + a.width, y + a.height});
			return;
		}
	}
	Window rootRet, parent, *children = nullptr;
	unsigned n = 0;
	if (!XQueryTree(d, w, &rootRet, &parent, &children, &n)) return;
	for (unsigned i = 0; i < n; ++i) findWindows(d, root, children[i], prefix, out);
	if (children) XFree(children);
}

int shiftOf(unsigned long mask)
{
	int s = 0;
	while (mask && !(mask & 1)) mask >>= 1, ++s;
	return s;
}
}  // namespace

void saveXScreenshot(const std::string& titlePrefix, const std::filesystem::path& png)
{
	Display* d = XOpenDisplay(nullptr);
	if (!d) throw std::runtime_error("screenshot: cannot open the X display (DISPLAY unset?)");
	const Window root = DefaultRootWindow(d);
	XWindowAttributes ra;
	XGetWindowAttributes(d, root, &ra);
	std::vector<Rect> found;
	findWindows(d, root, root, titlePrefix, found);
	Rect r{0, 0, ra.width, ra.height};
	if (!found.empty())
	{
		r = found.front();
		for (const auto& f : found)
			r = {std::min(r.x0, f.x0), std::min(r.y0, f.y0), std::max(r.x1, f.x1), std::max(r.y1, f.y1)};
		r = {std::max(0, r.x0), std::max(0, r.y0), std::min(ra.width, r.x1), std::min(ra.height, r.y1)};
	}
	const int w = r.x1 - r.x0, h = r.y1 - r.y0;
	XImage* img = w > 0 && h > 0 ? XGetImage(d, root, r.x0, r.y0, w, h, AllPlanes, ZPixmap) : nullptr;
	if (!img)
	{
		XCloseDisplay(d);
		throw std::runtime_error("screenshot: XGetImage failed");
	}
	const int rs = shiftOf(img->red_mask), gs = shiftOf(img->green_mask), bs = shiftOf(img->blue_mask);
	const auto rm = img->red_mask >> rs, gm = img->green_mask >> gs, bm = img->blue_mask >> bs;
	mrpt::img::CImage out(w, h, mrpt::img::CH_RGB);
	for (int y = 0; y < h; ++y)
		for (int x = 0; x < w; ++x)
		{
			const unsigned long p = XGetPixel(img, x, y);
			auto* px = out.ptr<std::uint8_t>(x, y);  // B, G, R
			px[0] = static_cast<std::uint8_t>(((p >> bs) & bm) * 255 / std::max(1ul, bm));
			px[1] = static_cast<std::uint8_t>(((p >> gs) & gm) * 255 / std::max(1ul, gm));
			px[2] = static_cast<std::uint8_t>(((p >> rs) & rm) * 255 / std::max(1ul, rm));
		}
	XDestroyImage(img);
	XCloseDisplay(d);
	if (!out.saveToFile(png.string())) throw std::runtime_error(png.string() + ": cannot write the screenshot");
}
}  // namespace avm::viewer
