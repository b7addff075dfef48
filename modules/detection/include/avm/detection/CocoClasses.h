// The 80 class names of COCO in the order detectors trained on it number them.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace avm::detection
{
const std::vector<std::string>& cocoClassNames();
/** The id of a COCO class name (exact, lower case, e.g. "person" -> 0). */
std::optional<int> cocoClassId(const std::string& name);
/** The COCO name of an id, "class<id>" for an id outside the table. */
std::string cocoClassName(int id);
}  // namespace avm::detection
