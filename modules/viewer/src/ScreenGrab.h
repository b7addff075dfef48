// What the X server shows, as a PNG (Xlib's XGetImage on the root window):
// the screen as it is, GL output included, which MRPT's GL read-back
// (CDisplayWindow3D::getLastWindowImage) does not give under Xvfb.
#pragma once

#include <filesystem>
#include <string>

namespace avm::viewer
{
/** Saves the part of the screen covered by the viewable top-level windows
 *  whose title starts with `titlePrefix` (the whole screen when there is
 *  none). Throws std::runtime_error when there is no X display or the PNG
 *  cannot be written. */
void saveXScreenshot(const std::string& titlePrefix, const std::filesystem::path& png);
}  // namespace avm::viewer
