// A finished run handed on the MRPT way: its keyframes as a CSimpleMap
// (OUTDIR/keyframes.simplemap), each keyframe's observation at its final pose,
// the input of stock observations2map for any metric map (a point map, an
// OctoMap, the adaptive map through the plugin). The observations carry their
// 3D points besides the depth image: MRPT's point maps and COctoMap insert a
// range scan from its points only.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <vector>

#include "avm/io/RgbdFrame.h"
#include "avm/io/Trajectory.h"

namespace avm::pipeline::detail
{
/** Writes `file` (atomically): the keyframes of `earlier` (the simplemap of
 *  the session this run continued; nothing for a first run), then this
 *  session's, the poses of `trajectory` from `firstPose` on whose
 *  `keyframes` flag is set, with their observations read from `nextFrame`
 *  (the rawlog again, in the run's order). Returns the keyframes written.
 *  Throws std::runtime_error naming the file it could not read or write, or
 *  when the frames end before the last keyframe. */
std::size_t writeKeyframeSimplemap(const std::filesystem::path& file,
	const std::optional<std::filesystem::path>& earlier, const io::Trajectory& trajectory,
	const std::vector<bool>& keyframes, std::size_t firstPose,
	const std::function<std::optional<io::RgbdFrame>()>& nextFrame);
}  // namespace avm::pipeline::detail
