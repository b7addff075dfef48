#include "avm/io/RgbdFrame.h"

#include <mrpt/core/bits_math.h>
#include <mrpt/system/datetime.h>

#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace avm::io
{
double RgbdFrame::timestamp() const { return observation ? mrpt::Clock::toDouble(observation->timestamp) : 0.0; }

mrpt::poses::CPose3D opticalToSensorPose()
{
	using mrpt::DEG2RAD;
	return mrpt::poses::CPose3D(0, 0, 0, DEG2RAD(90.0), DEG2RAD(-90.0), 0);
}

cv::Mat depthInMetres(const mrpt::obs::CObservation3DRangeScan& obs)
{
	if (!obs.hasRangeImage) throw std::runtime_error("observation has no depth image");
	const auto& r = obs.rangeImage;
	if (r.rows() == 0 || r.cols() == 0) return cv::Mat(static_cast<int>(r.rows()), static_cast<int>(r.cols()), CV_32F);
	// The matrix is row-major and contiguous: one vectorised conversion, each
	// value the float product of the 16-bit count and the unit, as a loop gives.
	const cv::Mat counts(
		static_cast<int>(r.rows()), static_cast<int>(r.cols()), CV_16U, const_cast<std::uint16_t*>(r.data()));
	cv::Mat depth;
	counts.convertTo(depth, CV_32F, obs.rangeUnits);
	return depth;
}

cv::Mat colourImage(const mrpt::obs::CObservation3DRangeScan& obs)
{
	if (!obs.hasIntensityImage) throw std::runtime_error("observation has no colour image");
	obs.intensityImage.forceLoad();
	cv::Mat img = obs.intensityImage.asCvMat<cv::Mat>(mrpt::img::SHALLOW_COPY);
	if (img.type() == CV_8UC1)
	{
		cv::Mat bgr;
		cv::merge(std::vector<cv::Mat>{img, img, img}, bgr);
		return bgr;
	}
	if (img.type() != CV_8UC3) throw std::runtime_error("colour image is not 8-bit RGB or grey");
	return img;
}

bool isFinite(const mrpt::poses::CPose3D& pose)
{
	for (int i = 0; i < 3; ++i)
		if (!std::isfinite(pose.m_coords[i])) return false;
	const auto& R = pose.getRotationMatrix();
	for (int r = 0; r < 3; ++r)
		for (int c = 0; c < 3; ++c)
			if (!std::isfinite(R(r, c))) return false;
	return true;
}
}  // namespace avm::io
