// The live view's text over the 3D view, laid out for the window's width: the
// status lines at the bottom, the keys and what is shown at the top. A line
// too long for the window is broken between its fields (two spaces apart), so
// no text runs past the right edge, however many stage times or notes a line
// holds and however narrow the window is made.
#pragma once

#include <mrpt/opengl/opengl_fonts.h>

#include <cstddef>
#include <string>
#include <vector>

#include "avm/viewer/MapSnapshot.h"
#include "avm/viewer/MapView.h"

namespace avm::viewer
{
/** [px] How wide `text` is drawn as a text message in `font`: MRPT's vector
 *  font extent (CText::computeTextExtension) in units of the font's height
 *  (40 characters of the mono font at 14 px: 522.6 px by this, 520 px on an
 *  Xvfb screen). */
double textWidthPx(const std::string& text, const mrpt::opengl::TFontParams& font);

/** `lines` as drawn from `marginPx` off the left edge of a window `widthPx`
 *  wide in `font`: a line that would come within `marginPx` of the right edge
 *  is broken before the field that would pass it (fields are two spaces
 *  apart; the lines after the first of a broken line start with two spaces),
 *  a field too wide on its own at its last space that fits, and a word too
 *  wide on its own is cut. */
std::vector<std::string> fitToWidth(
	const std::vector<std::string>& lines, double widthPx, const mrpt::opengl::TFontParams& font, double marginPx);

/** One text message of the view (COpenGLViewport::addTextMessage): x, y in
 *  pixels, y >= 0 from the bottom edge, y < 0 from the top. A message id
 *  always has the same place, so that the view only changes its text. */
struct StatusMessage
{
	std::size_t id = 0;
	double x = 0, y = 0;
	std::string text;
	mrpt::opengl::TFontParams font;
};

/** [px] Where the text starts, off the window's left edge, and the least room kept on its right. */
constexpr double kStatusMargin = 8;

/** The view's text for snapshot `s` with toggles `t` in a window `widthPx`
 *  wide: statusLines(s) (with "[paused]") at the bottom, its first line
 *  highest, and the keys and what is shown at the top, each fitted to the
 *  width (fitToWidth). */
std::vector<StatusMessage> statusMessages(const MapSnapshot& s, const ViewToggles& t, bool paused, double widthPx);
}  // namespace avm::viewer
