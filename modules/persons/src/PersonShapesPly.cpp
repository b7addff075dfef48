#include "avm/persons/PersonShapesPly.h"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace avm::persons
{
namespace
{
/** The header personShapesPlyText() writes, but for the comment and the count. */
const char* const kProperties[] = {"property float x", "property float y", "property float z", "property uchar red",
	"property uchar green", "property uchar blue", "property uint person"};
}  // namespace

std::string personShapesPlyText(const std::vector<PersonTrack>& tracks, const mrpt::img::TColor& colour)
{
	std::size_t points = 0;
	for (const auto& t : tracks) points += t.shape.size();
	std::ostringstream out;
	out << "ply\nformat ascii 1.0\n"
		<< "comment avm-map: each person's last shape, one point per voxel of the high-resolution tree, world frame "
		   "[m]; person = the id in persons.csv\n"
		<< "element vertex " << points << "\n";
	for (const auto& p : kProperties) out << p << "\n";
	out << "end_header\n";
	for (const auto& t : tracks)
		for (const auto& p : t.shape)
		{
			char line[128];
			std::snprintf(line, sizeof(line), "%.4f %.4f %.4f %u %u %u %u\n", p.x, p.y, p.z, unsigned(colour.R),
				unsigned(colour.G), unsigned(colour.B), t.id);
			out << line;
		}
	return out.str();
}

std::vector<PersonShape> readPersonShapesPly(const std::filesystem::path& file)
{
	std::ifstream in(file);
	if (!in) throw std::runtime_error(file.string() + ": cannot open");
	std::size_t lineNo = 0;
	std::string line;
	const auto fail = [&](const std::string& what)
	{
		throw std::runtime_error(
			file.string() + ":" + std::to_string(lineNo) + ": not a person_shapes.ply of avm-map: " + what);
	};
	const auto next = [&]
	{
		if (!std::getline(in, line)) fail("it ends early");
		++lineNo;
		if (!line.empty() && line.back() == '\r') line.pop_back();
	};
	next();
	if (line != "ply") fail("no 'ply' line");
	next();
	if (line != "format ascii 1.0") fail("expected 'format ascii 1.0'");
	do next();
	while (line.rfind("comment", 0) == 0);
	std::size_t count = 0;
	if (std::sscanf(line.c_str(), "element vertex %zu", &count) != 1) fail("expected 'element vertex N'");
	for (const auto& p : kProperties)
	{
		next();
		if (line != p) fail(std::string("expected '") + p + "'");
	}
	next();
	if (line != "end_header") fail("expected 'end_header'");

	std::vector<PersonShape> shapes;
	for (std::size_t i = 0; i < count; ++i)
	{
		next();
		mrpt::math::TPoint3Df p;
		unsigned r = 0, g = 0, b = 0, id = 0;
		char rest = 0;
		if (std::sscanf(line.c_str(), "%f %f %f %u %u %u %u %c", &p.x, &p.y, &p.z, &r, &g, &b, &id, &rest) != 7 ||
			r > 255 || g > 255 || b > 255)
			fail("expected 'x y z red green blue person'");
		if (shapes.empty() || shapes.back().id != id)
			shapes.push_back({id, mrpt::img::TColor(uint8_t(r), uint8_t(g), uint8_t(b)), {}});
		shapes.back().points.push_back(p);
	}
	return shapes;
}
}  // namespace avm::persons
