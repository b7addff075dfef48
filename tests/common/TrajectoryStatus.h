// What a run's trajectory_status.txt says of each pose, as the tests read it.
#pragma once

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "TestData.h"

namespace avm::test
{
/** The `tracked` column of a trajectory_status.txt, one per pose line; -1
 *  for a line that is not `timestamp tracked`. */
inline std::vector<int> trackedFlagsIn(const std::filesystem::path& statusTxt)
{
	std::istringstream status(fileBytes(statusTxt));
	std::vector<int> tracked;
	for (std::string line; std::getline(status, line);)
	{
		if (line.empty() || line[0] == '#') continue;
		double timestamp = 0;
		int t = -1;
		tracked.push_back(std::sscanf(line.c_str(), "%lf %d", &timestamp, &t) == 2 ? t : -1);
	}
	return tracked;
}
}  // namespace avm::test
