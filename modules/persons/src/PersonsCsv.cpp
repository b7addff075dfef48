#include "avm/persons/PersonsCsv.h"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace avm::persons
{
namespace
{
constexpr const char* kHeader =
	"id,first_frame,last_frame,first_time,last_time,x,y,z,box_min_x,box_min_y,box_min_z,box_max_x,box_max_y,"
	"box_max_z,detections,state";
}  // namespace

std::string personsCsvText(const std::vector<PersonTrack>& tracks)
{
	std::ostringstream out;
	out << kHeader << "\n";
	for (const auto& t : tracks)
	{
		char line[512];
		std::snprintf(line, sizeof(line), "%u,%zu,%zu,%.6f,%.6f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%zu,%s\n",
			t.id, t.firstFrame, t.lastFrame, t.firstTime, t.lastTime, t.position.x, t.position.y, t.position.z,
			t.box.min.x, t.box.min.y, t.box.min.z, t.box.max.x, t.box.max.y, t.box.max.z, t.sightings,
			t.still ? "still" : "moving");
		out << line;
	}
	return out.str();
}

std::vector<PersonTrack> readPersonsCsv(const std::filesystem::path& file)
{
	std::ifstream in(file);
	if (!in) throw std::runtime_error(file.string() + ": cannot read");
	std::vector<PersonTrack> tracks;
	std::string line;
	if (!std::getline(in, line) || line != kHeader)
		throw std::runtime_error(file.string() + ":1: not the persons.csv header");
	for (std::size_t lineNo = 2; std::getline(in, line); ++lineNo)
	{
		if (line.empty()) continue;
		PersonTrack t;
		char end = 0, state[8] = {};
		const int read = std::sscanf(line.c_str(),
			"%u,%zu,%zu,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%zu,%7[a-z]%c", &t.id, &t.firstFrame, &t.lastFrame,
			&t.firstTime, &t.lastTime, &t.position.x, &t.position.y, &t.position.z, &t.box.min.x, &t.box.min.y,
			&t.box.min.z, &t.box.max.x, &t.box.max.y, &t.box.max.z, &t.sightings, state, &end);
		t.still = std::string(state) == "still";
		t.bandExtent = t.box;
		if (read != 16 || (!t.still && std::string(state) != "moving"))
			throw std::runtime_error(file.string() + ":" + std::to_string(lineNo) + ": not a persons.csv line");
		tracks.push_back(t);
	}
	return tracks;
}
}  // namespace avm::persons
