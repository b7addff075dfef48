#include "avm/detection/PersonLabels.h"

#include <mrpt/obs/TPixelLabelInfo.h>

#include <stdexcept>

#include "avm/detection/PersonRegion.h"
#include "avm/io/RgbdFrame.h"

namespace avm::detection
{
namespace
{
using mrpt::obs::TPixelLabelInfoBase;

/** The bit index of "person", adding the label if needed. */
uint8_t personLabelIndex(TPixelLabelInfoBase& labels)
{
	if (const int existing = labels.checkLabelNameExistence(kPersonLabel); existing >= 0)
		return static_cast<uint8_t>(existing);
	const unsigned bits = 8u * labels.BITFIELD_BYTES;
	for (unsigned i = 0; i < bits; ++i)
		if (!labels.pixelLabelNames.count(i))
		{
			labels.setLabelName(i, kPersonLabel);
			return static_cast<uint8_t>(i);
		}
	throw std::runtime_error("pixelLabels: all " + std::to_string(bits) + " label bits are in use, no room for \"person\"");
}

template <unsigned BYTES>
bool labelMatrixSize(const TPixelLabelInfoBase& labels, cv::Size& size)
{
	const auto* typed = dynamic_cast<const mrpt::obs::TPixelLabelInfo<BYTES>*>(&labels);
	if (typed) size = cv::Size(static_cast<int>(typed->pixelLabels.cols()), static_cast<int>(typed->pixelLabels.rows()));
	return typed != nullptr;
}

/** Rows and columns of the label matrix (MRPT's base class does not tell). */
cv::Size labelMatrixSize(const TPixelLabelInfoBase& labels)
{
	cv::Size size;
	if (labelMatrixSize<1>(labels, size) || labelMatrixSize<2>(labels, size) || labelMatrixSize<4>(labels, size) ||
		labelMatrixSize<8>(labels, size))
		return size;
	throw std::runtime_error("pixelLabels: unknown label type of " + std::to_string(labels.BITFIELD_BYTES) + " bytes");
}
}  // namespace

void writePersonLabels(
	mrpt::obs::CObservation3DRangeScan& obs, const std::vector<Detection>& persons, const TDetectorOptions& options)
{
	const cv::Mat depth = io::depthInMetres(obs);
	if (!obs.pixelLabels)
	{
		obs.pixelLabels = std::make_shared<mrpt::obs::TPixelLabelInfo<1>>();
		obs.pixelLabels->setSize(depth.rows, depth.cols);
	}
	auto& labels = *obs.pixelLabels;
	if (const cv::Size size = labelMatrixSize(labels); size != depth.size())
		throw std::runtime_error(
			"pixelLabels are " + std::to_string(size.width) + "x" + std::to_string(size.height) + ", the depth image " +
			std::to_string(depth.cols) + "x" + std::to_string(depth.rows));
	const uint8_t bit = personLabelIndex(labels);
	for (int r = 0; r < depth.rows; ++r)
		for (int c = 0; c < depth.cols; ++c) labels.unsetLabel(r, c, bit);
	for (const auto& person : personsOnly(persons))
	{
		const cv::Mat mask = personMask(person, depth, options);
		for (int r = 0; r < mask.rows; ++r)
		{
			const uint8_t* row = mask.ptr<uint8_t>(r);
			for (int c = 0; c < mask.cols; ++c)
				if (row[c]) labels.setLabel(r, c, bit);
		}
	}
}

cv::Mat personLabelMask(const mrpt::obs::CObservation3DRangeScan& obs)
{
	if (!obs.pixelLabels) return {};
	const int bit = obs.pixelLabels->checkLabelNameExistence(kPersonLabel);
	if (bit < 0) return {};
	const cv::Size size = labelMatrixSize(*obs.pixelLabels);
	const int rows = size.height, cols = size.width;
	cv::Mat mask(size, CV_8U, cv::Scalar(0));
	for (int r = 0; r < rows; ++r)
		for (int c = 0; c < cols; ++c)
			if (obs.pixelLabels->checkLabel(r, c, static_cast<uint8_t>(bit))) mask.at<uint8_t>(r, c) = 255;
	return mask;
}
}  // namespace avm::detection
