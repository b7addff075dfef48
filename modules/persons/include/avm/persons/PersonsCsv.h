// persons.csv, the list a rescue team reads first: one line per person, a
// track confirmed by its sightings (track_min_sightings; the ids of tracks
// never confirmed are left out), with its first and last frame and time, last
// world position and box, number of sightings, and whether the person was
// still or moving at the end. Written by avm-map, read back by avm-view and
// the tests.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "avm/persons/PersonTracker.h"

namespace avm::persons
{
/** The text of persons.csv: a header line, then one line per track. */
std::string personsCsvText(const std::vector<PersonTrack>& tracks);

/** The tracks of a persons.csv (times to the µs, positions and boxes to the
 *  mm, as written). Throws std::runtime_error naming the file, and the line
 *  when it is not a persons.csv line. */
std::vector<PersonTrack> readPersonsCsv(const std::filesystem::path& file);
}  // namespace avm::persons
