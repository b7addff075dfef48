// Which frames the detector runs on ([pipeline] detection_schedule).
//
// fixed: every detect_every_n-th frame. on_change: the detector looks again
// where what it last saw may hold a person it has not found:
//   - something moved: the frame's depth, seen from the detector's last frame
//     at the camera's predicted pose, differs on detect_moved_share of the
//     image (someone walking in, or a person it found walking on: their boxes
//     mask the odometry and must follow them; people standing or lying
//     still do not call it),
//   - the camera turned: detect_new_view_share of the image is new to it,
// at most every detect_every_n-th frame and at least every
// detect_max_interval-th. The decision reads only the frame and the poses of
// earlier frames, never the time, so the same rawlog runs the detector on
// the same frames.
#pragma once

#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "avm/pipeline/MappingPipeline.h"

namespace avm::pipeline::detail
{
class DetectionScheduler
{
   public:
	/** `options` must outlive the scheduler. */
	explicit DetectionScheduler(const TPipelineOptions& options);

	/** Whether the detector runs on frame `frameIndex` (its observation
	 *  `obs`), and what made it run (a RunSummary::detectionsStartedBy name).
	 *  `poses`: the camera poses of the frames mapped so far, by index. */
	std::optional<std::string> due(std::size_t frameIndex, const mrpt::obs::CObservation3DRangeScan& obs,
		const std::map<std::size_t, mrpt::poses::CPose3D>& poses);

	/** A new session: the detector's last frame is the earlier session's, not
	 *  this camera's. */
	void forgetLastLook() { m_lastLook.reset(); }

	void saveState(mrpt::serialization::CArchive& out) const;
	void loadState(mrpt::serialization::CArchive& in);

   private:
	/** The detector's last frame: its index and its depth on the sample grid. */
	struct Look
	{
		std::size_t frame = 0;
		int cols = 0, rows = 0;
		std::vector<float> depth;  //!< [m] along the optical axis, 0 = none; row-major
	};
	/** What changed since the last look, as shares of the image. */
	struct Change
	{
		double moved = 0, newView = 0;
	};

	/** on_change, detect_every_n frames or more after the last look: why
	 *  the detector looks again at `now`, if it must. */
	std::optional<std::string> lookAgain(const Look& now, const mrpt::obs::CObservation3DRangeScan& obs,
		const std::map<std::size_t, mrpt::poses::CPose3D>& poses) const;
	Change changeSinceLook(
		const Look& now, const mrpt::obs::CObservation3DRangeScan& obs, const mrpt::poses::CPose3D& lookToNow) const;
	static Look sample(std::size_t frameIndex, const mrpt::obs::CObservation3DRangeScan& obs);

	const TPipelineOptions& m_options;
	std::optional<Look> m_lastLook;
};
}  // namespace avm::pipeline::detail
