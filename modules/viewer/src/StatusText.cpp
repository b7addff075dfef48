#include "avm/viewer/StatusText.h"

#include <mrpt/opengl/CText.h>

#include <algorithm>

namespace avm::viewer
{
namespace
{
const std::string kFieldGap = "  ", kIndent = "  ";

const char* kKeysHelp = "space pause/resume  n step  f free space  l low tree  h high tree  m features  r reset view";

/** The fields of `line`: its pieces between two spaces, empty ones dropped. */
std::vector<std::string> fieldsOf(const std::string& line)
{
	std::vector<std::string> fields;
	for (std::size_t from = 0; from <= line.size();)
	{
		const auto at = std::min(line.find(kFieldGap, from), line.size());
		if (at > from) fields.push_back(line.substr(from, at - from));
		from = at + kFieldGap.size();
	}
	return fields;
}

mrpt::opengl::TFontParams font(float heightPx, float grey)
{
	mrpt::opengl::TFontParams f;
	f.color = mrpt::img::TColorf(grey, grey, grey);
	f.vfont_scale = heightPx;
	f.draw_shadow = true;
	f.shadow_color = mrpt::img::TColorf(1.0f, 1.0f, 1.0f);
	return f;
}
}  // namespace

double textWidthPx(const std::string& text, const mrpt::opengl::TFontParams& font)
{
	mrpt::opengl::CText measured(text);
	measured.setFont(font.vfont_name, static_cast<int>(font.vfont_scale));
	return measured.computeTextExtension().first * font.vfont_scale;
}

std::vector<std::string> fitToWidth(
	const std::vector<std::string>& lines, double widthPx, const mrpt::opengl::TFontParams& font, double marginPx)
{
	const double room = widthPx - 2 * marginPx;
	const auto fits = [&](const std::string& text) { return textWidthPx(text, font) <= room; };
	std::vector<std::string> out;
	for (const auto& line : lines)
	{
		if (fits(line))
		{
			out.push_back(line);
			continue;
		}
		const std::size_t first = out.size();
		std::string current;
		for (const auto& field : fieldsOf(line))
		{
			const std::string joined = current + kFieldGap + field;
			if (!current.empty() && fits(joined))
			{
				current = joined;
				continue;
			}
			if (!current.empty()) out.push_back(current);
			current = (out.size() > first ? kIndent : "") + field;
			while (!fits(current))
			{
				// The longest start that fits, ended at a space if one is in it.
				std::size_t cut = current.size();
				while (cut > 1 && !fits(current.substr(0, cut))) --cut;
				const auto space = current.find_last_of(' ', cut);
				const bool atSpace = space != std::string::npos && space >= cut / 2;
				out.push_back(current.substr(0, atSpace ? space : cut));
				// Cut inside a word: the rest of that word goes, the words after it stay.
				const auto next = atSpace ? space : current.find(' ', cut);
				const std::string rest = next == std::string::npos ? std::string() : current.substr(next + 1);
				current = rest.empty() ? rest : kIndent + rest;
			}
		}
		if (!current.empty()) out.push_back(current);
	}
	return out;
}

std::vector<StatusMessage> statusMessages(const MapSnapshot& s, const ViewToggles& t, bool paused, double widthPx)
{
	// Bottom: the status lines, 22 px apart, the last line lowest. Top: the
	// keys, then what is shown, 24 px apart. Ids by place: 100 + the line
	// from the bottom, 200 + the line from the top.
	const auto statusFont = font(14, 0.1f), helpFont = font(12, 0.35f);
	auto lines = statusLines(s);
	if (paused) lines[0] += "  [paused]";
	std::vector<StatusMessage> out;
	const auto bottom = fitToWidth({lines[0], lines[1]}, widthPx, statusFont, kStatusMargin);
	for (std::size_t k = 0; k < bottom.size(); ++k)
	{
		const std::size_t fromBottom = bottom.size() - 1 - k;
		out.push_back({100 + fromBottom, kStatusMargin, 8.0 + 22.0 * double(fromBottom), bottom[k], statusFont});
	}
	const std::string shown = std::string("low ") + (t.lowTree ? "on" : "off") + "  high " +
							  (t.highTree ? "on" : "off") + "  free " +
							  (t.freeSpace ? (s.hasFreeSpace ? "on" : "from the next snapshot") : "off");
	const auto top = fitToWidth({kKeysHelp, shown}, widthPx, helpFont, kStatusMargin);
	for (std::size_t k = 0; k < top.size(); ++k)
		out.push_back({200 + k, kStatusMargin, -22.0 - 24.0 * double(k), top[k], helpFont});
	return out;
}
}  // namespace avm::viewer
