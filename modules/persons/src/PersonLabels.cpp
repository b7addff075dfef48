#include "avm/persons/PersonLabels.h"

#include <stdexcept>

namespace avm::persons
{
namespace
{
using mrpt::obs::TPixelLabelInfo;
using mrpt::obs::TPixelLabelInfoBase;

template <unsigned BYTES>
const TPixelLabelInfo<BYTES>* typed(const TPixelLabelInfoBase& labels)
{
	return dynamic_cast<const TPixelLabelInfo<BYTES>*>(&labels);
}

/** Appends each pixel of `bits[k]` to out[k].pixels, reading every pixel's
 *  bit field once. */
template <unsigned BYTES>
bool collect(const TPixelLabelInfoBase& base, const std::vector<unsigned>& bits, std::vector<LabelPixels>& out)
{
	const auto* labels = typed<BYTES>(base);
	if (!labels) return false;
	using Mask = typename TPixelLabelInfo<BYTES>::bitmask_t;
	Mask any = 0;
	for (const auto bit : bits) any |= static_cast<Mask>(Mask(1) << bit);
	const auto& m = labels->pixelLabels;
	const int rows = static_cast<int>(m.rows()), cols = static_cast<int>(m.cols());
	for (int r = 0; r < rows; ++r)
		for (int c = 0; c < cols; ++c)
		{
			const Mask v = m(r, c);
			if (!(v & any)) continue;
			for (std::size_t k = 0; k < bits.size(); ++k)
				if (v & static_cast<Mask>(Mask(1) << bits[k]))
					out[k].pixels.push_back(static_cast<std::uint32_t>(r * cols + c));
		}
	return true;
}

/** The 4-connected blobs of `pixels` (raster order) in a rows x cols image. */
std::vector<PixelSet> blobsOf(const PixelSet& pixels, int rows, int cols)
{
	std::vector<std::uint8_t> state(static_cast<std::size_t>(rows) * cols);  // 1 = unvisited pixel, 2 = visited
	for (const auto i : pixels) state[i] = 1;
	std::vector<PixelSet> blobs;
	PixelSet stack;
	for (const auto start : pixels)
	{
		if (state[start] != 1) continue;
		PixelSet blob;
		stack.assign(1, start);
		state[start] = 2;
		while (!stack.empty())
		{
			const auto i = stack.back();
			stack.pop_back();
			blob.push_back(i);
			const int r = static_cast<int>(i / cols), c = static_cast<int>(i % cols);
			const int nb[4][2] = {{r - 1, c}, {r + 1, c}, {r, c - 1}, {r, c + 1}};
			for (const auto& [nr, nc] : nb)
			{
				if (nr < 0 || nc < 0 || nr >= rows || nc >= cols) continue;
				const auto j = static_cast<std::uint32_t>(nr * cols + nc);
				if (state[j] != 1) continue;
				state[j] = 2;
				stack.push_back(j);
			}
		}
		blobs.push_back(std::move(blob));
	}
	return blobs;
}
}  // namespace

bool isPersonLabel(const std::string& name, const std::string& label)
{
	return name == label || name.rfind(label + "/", 0) == 0;
}

LabelImageSize labelImageSize(const TPixelLabelInfoBase& labels)
{
	const auto size = [](const auto* l) {
		return LabelImageSize{static_cast<int>(l->pixelLabels.rows()), static_cast<int>(l->pixelLabels.cols())};
	};
	if (const auto* l = typed<1>(labels)) return size(l);
	if (const auto* l = typed<2>(labels)) return size(l);
	if (const auto* l = typed<4>(labels)) return size(l);
	if (const auto* l = typed<8>(labels)) return size(l);
	throw std::runtime_error("pixelLabels: unknown label type of " + std::to_string(labels.BITFIELD_BYTES) + " bytes");
}

std::vector<LabelPixels> readPersonLabels(const mrpt::obs::CObservation3DRangeScan& obs, const std::string& label)
{
	std::vector<LabelPixels> out;
	if (!obs.hasPixelLabels()) return out;
	const auto& labels = *obs.pixelLabels;
	std::vector<unsigned> bits;
	for (const auto& [bit, name] : labels.pixelLabelNames)
		if (isPersonLabel(name, label))
		{
			bits.push_back(static_cast<unsigned>(bit));
			out.push_back({name != label, {}});
		}
	if (bits.empty()) return out;
	if (!(collect<1>(labels, bits, out) || collect<2>(labels, bits, out) || collect<4>(labels, bits, out) ||
			collect<8>(labels, bits, out)))
		labelImageSize(labels);  // throws: a label type of unknown width
	return out;
}

std::vector<PixelSet> personPixelsFromLabels(
	const mrpt::obs::CObservation3DRangeScan& obs, const std::string& label, std::size_t minPixels)
{
	std::vector<PixelSet> persons;
	if (!obs.hasPixelLabels() || !obs.hasRangeImage) return persons;
	const int rows = static_cast<int>(obs.rangeImage.rows()), cols = static_cast<int>(obs.rangeImage.cols());
	const auto size = labelImageSize(*obs.pixelLabels);
	if (size.rows != rows || size.cols != cols) return persons;

	const auto enoughDepth = [&](const PixelSet& pixels)
	{
		std::size_t withDepth = 0;
		for (const auto i : pixels) withDepth += obs.rangeImage(i / cols, i % cols) != 0;
		return withDepth >= minPixels;
	};
	for (auto& l : readPersonLabels(obs, label))
	{
		if (l.onePerson)
		{
			if (enoughDepth(l.pixels)) persons.push_back(std::move(l.pixels));
			continue;
		}
		for (auto& blob : blobsOf(l.pixels, rows, cols))
			if (enoughDepth(blob)) persons.push_back(std::move(blob));
	}
	return persons;
}
}  // namespace avm::persons
