#include "KeyframeSimplemap.h"

#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/obs/T3DPointsProjectionParams.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>

#include <stdexcept>
#include <string>

#include "avm/io/AtomicFile.h"

namespace avm::pipeline::detail
{
namespace
{
/** One pixel in kPointDecimation along rows and columns becomes a 3D point:
 *  about 19,000 points of a 640x480 frame, enough for a 5 cm map at the
 *  camera's range and a quarter of the file a point per pixel would make. */
constexpr int kPointDecimation = 4;
}  // namespace

std::size_t writeKeyframeSimplemap(const std::filesystem::path& file,
	const std::optional<std::filesystem::path>& earlier, const io::Trajectory& trajectory,
	const std::vector<bool>& keyframes, std::size_t firstPose,
	const std::function<std::optional<io::RgbdFrame>()>& nextFrame)
{
	mrpt::maps::CSimpleMap map;
	if (earlier && !map.loadFromFile(earlier->string()))
		throw std::runtime_error(earlier->string() + ": cannot read the earlier sessions' keyframes");
	for (std::size_t pose = firstPose; pose < trajectory.size(); ++pose)
	{
		if (!keyframes.at(pose)) continue;
		// The trajectory has the mapped frames in order, with the timestamps
		// the same reader gave them.
		std::optional<io::RgbdFrame> frame;
		while ((frame = nextFrame()) && frame->timestamp() != trajectory[pose].timestamp)
		{
		}
		if (!frame)
			throw std::runtime_error(file.string() + ": the rawlog ended before the keyframe of time " +
									 std::to_string(trajectory[pose].timestamp));
		auto& obs = *frame->observation;
		mrpt::obs::T3DPointsProjectionParams projection;
		projection.decimation = kPointDecimation;
		obs.unprojectInto(obs, projection);
		auto observations = mrpt::obs::CSensoryFrame::Create();
		observations->insert(frame->observation);
		map.insert(mrpt::poses::CPose3DPDFGaussian::Create(trajectory[pose].pose), observations);
	}
	io::writeFileAtomically(file,
		[&](const std::filesystem::path& tmp)
		{
			if (!map.saveToFile(tmp.string())) throw std::runtime_error(file.string() + ": cannot write");
		});
	return map.size();
}
}  // namespace avm::pipeline::detail
