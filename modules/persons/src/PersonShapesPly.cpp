#include "avm/persons/PersonShapesPly.h"

#include <cstdio>
#include <sstream>

namespace avm::persons
{
std::string personShapesPlyText(const std::vector<PersonTrack>& tracks, const mrpt::img::TColor& colour)
{
	std::size_t points = 0;
	for (const auto& t : tracks) points += t.shape.size();
	std::ostringstream out;
	out << "ply\nformat ascii 1.0\n"
		<< "comment avm-map: each person's last shape, one point per voxel of the high-resolution tree, world frame "
		   "[m]; person = the id in persons.csv\n"
		<< "element vertex " << points << "\n"
		<< "property float x\nproperty float y\nproperty float z\n"
		<< "property uchar red\nproperty uchar green\nproperty uchar blue\n"
		<< "property uint person\nend_header\n";
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
}  // namespace avm::persons
