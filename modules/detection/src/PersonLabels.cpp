#include "avm/detection/PersonLabels.h"

#include <mrpt/obs/TPixelLabelInfo.h>

#include <cmath>
#include <stdexcept>

#include "avm/io/RgbdFrame.h"

namespace avm::detection
{
namespace
{
using mrpt::obs::TPixelLabelInfoBase;

/** Rows and columns of the label matrix. */
cv::Size labelMatrixSize(const TPixelLabelInfoBase& labels)
{
	const auto size = persons::labelImageSize(labels);
	return {size.cols, size.rows};
}

/** Removes every person label (names and bits); returns the free bits. */
std::vector<uint8_t> clearPersonLabels(TPixelLabelInfoBase& labels, cv::Size size)
{
	std::vector<uint8_t> free;
	const unsigned bits = 8u * labels.BITFIELD_BYTES;
	for (unsigned i = 0; i < bits; ++i)
	{
		const auto it = labels.pixelLabelNames.find(i);
		if (it != labels.pixelLabelNames.end() && !persons::isPersonLabel(it->second)) continue;
		if (it != labels.pixelLabelNames.end())
		{
			for (int r = 0; r < size.height; ++r)
				for (int c = 0; c < size.width; ++c) labels.unsetLabel(r, c, static_cast<uint8_t>(i));
			labels.pixelLabelNames.erase(it);
		}
		free.push_back(static_cast<uint8_t>(i));
	}
	return free;
}
}  // namespace

persons::PixelSet personPixels(const Detection& person, cv::Size image)
{
	const auto& b = person.box;
	return persons::pixelsOfBox(static_cast<int>(std::floor(b.x)), static_cast<int>(std::floor(b.y)),
		static_cast<int>(std::ceil(b.x + b.width)), static_cast<int>(std::ceil(b.y + b.height)), image.width,
		image.height);
}

void writePersonLabels(mrpt::obs::CObservation3DRangeScan& obs, const std::vector<Detection>& detections)
{
	if (!obs.hasRangeImage) throw std::runtime_error("pixelLabels: the observation has no depth image");
	const cv::Size depthSize(static_cast<int>(obs.rangeImage.cols()), static_cast<int>(obs.rangeImage.rows()));
	if (!obs.pixelLabels)
	{
		obs.pixelLabels = std::make_shared<mrpt::obs::TPixelLabelInfo<1>>();
		obs.pixelLabels->setSize(depthSize.height, depthSize.width);
	}
	auto& labels = *obs.pixelLabels;
	if (const cv::Size size = labelMatrixSize(labels); size != depthSize)
		throw std::runtime_error("pixelLabels are " + std::to_string(size.width) + "x" + std::to_string(size.height) +
								 ", the depth image " + std::to_string(depthSize.width) + "x" +
								 std::to_string(depthSize.height));
	const auto free = clearPersonLabels(labels, depthSize);
	if (free.empty())
		throw std::runtime_error("pixelLabels: all " + std::to_string(8u * labels.BITFIELD_BYTES) +
								 " label bits are in use, no room for \"person\"");
	// The plain label first; each person then takes a bit of its own while
	// there are bits, and the plain label holds the rest.
	labels.setLabelName(free.front(), persons::kPersonLabel);
	std::size_t next = 1;
	for (const auto& person : personsOnly(detections))
	{
		uint8_t bit = free.front();
		if (next < free.size())
		{
			bit = free[next];
			labels.setLabelName(bit, std::string(persons::kPersonLabel) + "/" + std::to_string(next));
			++next;
		}
		for (const auto i : personPixels(person, depthSize))
			labels.setLabel(static_cast<int>(i / depthSize.width), static_cast<int>(i % depthSize.width), bit);
	}
}

cv::Mat personLabelMask(const mrpt::obs::CObservation3DRangeScan& obs)
{
	const auto labels = persons::readPersonLabels(obs);
	if (labels.empty()) return {};
	const cv::Size size = labelMatrixSize(*obs.pixelLabels);
	cv::Mat mask(size, CV_8U, cv::Scalar(0));
	for (const auto& l : labels)
		for (const auto i : l.pixels)
			mask.at<uint8_t>(static_cast<int>(i) / size.width, static_cast<int>(i) % size.width) = 255;
	return mask;
}
}  // namespace avm::detection
