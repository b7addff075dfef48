#include "DetectionScheduler.h"

#include <mrpt/serialization/stl_serialization.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>

namespace avm::pipeline::detail
{
using mrpt::poses::CPose3D;

namespace
{
/** [px] between two depth samples: a person the detector finds at its
 *  256x192 input is some 30 x 60 pixels of the 640x480 frame or more, dozens
 *  of samples, while 64 times fewer pixels make the check cost little. */
constexpr int kSampleStep = 8;

/** The depth of pixel (u, v) along the optical axis [m]; 0 where none. */
float opticalDepth(const mrpt::obs::CObservation3DRangeScan& obs, int u, int v)
{
	const float metres = static_cast<float>(obs.rangeImage(v, u)) * obs.rangeUnits;
	if (obs.range_is_depth || metres <= 0) return metres;
	const auto& K = obs.cameraParams;
	const double x = (u - K.cx()) / K.fx(), y = (v - K.cy()) / K.fy();
	return static_cast<float>(metres / std::sqrt(1 + x * x + y * y));
}
}  // namespace

DetectionScheduler::DetectionScheduler(const TPipelineOptions& options) : m_options(options) {}

std::optional<std::string> DetectionScheduler::due(
	std::size_t frameIndex, const mrpt::obs::CObservation3DRangeScan& obs, const std::map<std::size_t, CPose3D>& poses)
{
	if (m_options.detectEveryN == 0) return std::nullopt;
	if (m_options.detectionSchedule == DetectionSchedule::Fixed)
		return frameIndex % m_options.detectEveryN == 0 ? std::optional<std::string>("every_n") : std::nullopt;
	const bool looked = m_lastLook && frameIndex >= m_lastLook->frame;
	if (looked && frameIndex - m_lastLook->frame < m_options.detectEveryN) return std::nullopt;
	Look now = sample(frameIndex, obs);
	auto cause = looked ? lookAgain(now, obs, poses) : std::optional<std::string>("first");
	if (cause) m_lastLook = std::move(now);
	return cause;
}

std::optional<std::string> DetectionScheduler::lookAgain(
	const Look& now, const mrpt::obs::CObservation3DRangeScan& obs, const std::map<std::size_t, CPose3D>& poses) const
{
	if (now.frame - m_lastLook->frame >= m_options.detectMaxInterval) return "interval";
	if (now.frame < 2) return "no_pose";
	const auto look = poses.find(m_lastLook->frame);
	const auto last = poses.find(now.frame - 1), beforeLast = poses.find(now.frame - 2);
	if (look == poses.end() || last == poses.end() || beforeLast == poses.end()) return "no_pose";
	// The camera where the constant-velocity model puts it: the frame's own
	// pose is the odometry's, after the detector has started.
	const CPose3D predicted = last->second + (last->second - beforeLast->second);
	const Change change = changeSinceLook(now, obs, predicted - look->second);
	if (change.moved >= m_options.detectMovedShare) return "moved";
	if (change.newView >= m_options.detectNewViewShare) return "new_view";
	return std::nullopt;
}

DetectionScheduler::Change DetectionScheduler::changeSinceLook(
	const Look& now, const mrpt::obs::CObservation3DRangeScan& obs, const CPose3D& lookToNow) const
{
	const Look& look = *m_lastLook;
	const auto& K = obs.cameraParams;
	const double fx = K.fx(), fy = K.fy(), cx = K.cx(), cy = K.cy();
	const int width = static_cast<int>(obs.rangeImage.cols()), height = static_cast<int>(obs.rangeImage.rows());
	const Eigen::Matrix3d R = lookToNow.getRotationMatrix().asEigen();
	const Eigen::Vector3d t(lookToNow.x(), lookToNow.y(), lookToNow.z());
	const double band = m_options.detectChangeDepth;
	std::size_t moved = 0, newView = 0;
	for (int r = 0; r < now.rows; ++r)
		for (int c = 0; c < now.cols; ++c)
		{
			const double z = now.depth[std::size_t(r * now.cols + c)];
			const int u = kSampleStep / 2 + c * kSampleStep, v = kSampleStep / 2 + r * kSampleStep;
			if (z <= 0) continue;
			const Eigen::Vector3d p = R * Eigen::Vector3d((u - cx) * z / fx, (v - cy) * z / fy, z) + t;
			if (p.z() <= 0)
			{
				++newView;
				continue;
			}
			const double lookU = fx * p.x() / p.z() + cx, lookV = fy * p.y() / p.z() + cy;
			if (!(lookU >= 0 && lookV >= 0 && lookU < width && lookV < height))
			{
				++newView;
				continue;
			}
			// The four samples of the look around where the point was: a
			// change only where it differs from all of them, so that a
			// sample beside a depth edge is not one.
			const double gridU = (lookU - kSampleStep / 2) / kSampleStep,
						 gridV = (lookV - kSampleStep / 2) / kSampleStep;
			const int c0 = std::clamp(int(std::floor(gridU)), 0, look.cols - 1), c1 = std::min(c0 + 1, look.cols - 1);
			const int r0 = std::clamp(int(std::floor(gridV)), 0, look.rows - 1), r1 = std::min(r0 + 1, look.rows - 1);
			bool seen = false, same = false;
			for (const int lr : {r0, r1})
				for (const int lc : {c0, c1})
					if (const double d = look.depth[std::size_t(lr * look.cols + lc)]; d > 0)
					{
						seen = true;
						same = same || std::abs(p.z() - d) <= band;
					}
			if (!seen)
				++newView;
			else if (!same)
				++moved;
		}
	const double samples = double(now.rows) * now.cols;
	return {moved / samples, newView / samples};
}

DetectionScheduler::Look DetectionScheduler::sample(
	std::size_t frameIndex, const mrpt::obs::CObservation3DRangeScan& obs)
{
	Look look;
	look.frame = frameIndex;
	look.cols = static_cast<int>(obs.rangeImage.cols()) / kSampleStep;
	look.rows = static_cast<int>(obs.rangeImage.rows()) / kSampleStep;
	look.depth.reserve(std::size_t(look.cols * look.rows));
	for (int r = 0; r < look.rows; ++r)
		for (int c = 0; c < look.cols; ++c)
			look.depth.push_back(
				opticalDepth(obs, kSampleStep / 2 + c * kSampleStep, kSampleStep / 2 + r * kSampleStep));
	return look;
}

void DetectionScheduler::saveState(mrpt::serialization::CArchive& out) const
{
	out.WriteAs<std::uint8_t>(m_lastLook.has_value());
	if (!m_lastLook) return;
	out.WriteAs<std::uint64_t>(m_lastLook->frame);
	out.WriteAs<std::int32_t>(m_lastLook->cols);
	out.WriteAs<std::int32_t>(m_lastLook->rows);
	out << m_lastLook->depth;
}

void DetectionScheduler::loadState(mrpt::serialization::CArchive& in)
{
	m_lastLook.reset();
	if (!in.ReadAs<std::uint8_t>()) return;
	Look look;
	look.frame = static_cast<std::size_t>(in.ReadAs<std::uint64_t>());
	look.cols = in.ReadAs<std::int32_t>();
	look.rows = in.ReadAs<std::int32_t>();
	in >> look.depth;
	if (look.cols <= 0 || look.rows <= 0 || look.depth.size() != std::size_t(look.cols) * std::size_t(look.rows))
		throw std::runtime_error("the detector's last frame in the run state is damaged");
	m_lastLook = std::move(look);
}
}  // namespace avm::pipeline::detail
