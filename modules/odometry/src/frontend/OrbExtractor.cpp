#include "OrbExtractor.h"

#include <opencv2/imgproc.hpp>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace avm::odometry::detail
{
namespace
{
constexpr int kEdgeThreshold = 19, kPatchSize = 31, kHarrisBlock = 7;
constexpr int kPatchColumns = OrbExtractor::kPatchColumns;
constexpr float kHarrisK = 0.04f;

/** How many of `features` ORB gives each level: a share falling by 1/scale
 *  a level, the rounding left to the last (OpenCV 4.6, orb.cpp). */
std::vector<int> featuresPerLevel(int features, double scale, int levels)
{
	std::vector<int> perLevel(std::size_t(levels), 0);
	const float factor = float(1.0 / scale);
	float desired = float(features) * (1 - factor) / (1 - float(std::pow(double(factor), double(levels))));
	int sum = 0;
	for (int level = 0; level + 1 < levels; ++level)
	{
		perLevel[std::size_t(level)] = cvRound(desired);
		sum += perLevel[std::size_t(level)];
		desired *= factor;
	}
	perLevel.back() = std::max(features - sum, 0);
	return perLevel;
}

/** ORB's Harris score of the pixel (x, y): Sobel-like gradients summed over
 *  a 7x7 block, in integers, then ORB's float expression in its order. */
float harrisScore(const cv::Mat& image, int x, int y)
{
	constexpr int r = kHarrisBlock / 2;
	const int step = int(image.step);
	int a = 0, b = 0, c = 0;
	for (int i = 0; i < kHarrisBlock; ++i)
	{
		const std::uint8_t* row = image.ptr<std::uint8_t>(y - r + i) + (x - r);
		for (int j = 0; j < kHarrisBlock; ++j)
		{
			const std::uint8_t* p = row + j;
			const int Ix = (p[1] - p[-1]) * 2 + (p[-step + 1] - p[-step - 1]) + (p[step + 1] - p[step - 1]);
			const int Iy = (p[step] - p[-step]) * 2 + (p[step - 1] - p[-step - 1]) + (p[step + 1] - p[-step + 1]);
			a += Ix * Ix;
			b += Iy * Iy;
			c += Ix * Iy;
		}
	}
	const float scale = 1.f / ((1 << 2) * kHarrisBlock * 255.f);
	const float scale4 = scale * scale * scale * scale;
	return ((float)a * b - (float)c * c - kHarrisK * ((float)a + b) * ((float)a + b)) * scale4;
}

#if defined(__SSE2__)
/** The pixels p[-16 .. 15], one 16-bit lane each. */
struct PixelLanes
{
	__m128i lanes[4];
};
PixelLanes widen(const std::uint8_t* p)
{
	const __m128i zero = _mm_setzero_si128();
	const __m128i left = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p - kPatchColumns / 2));
	const __m128i right = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
	return {{_mm_unpacklo_epi8(left, zero), _mm_unpackhi_epi8(left, zero), _mm_unpacklo_epi8(right, zero),
		_mm_unpackhi_epi8(right, zero)}};
}

/** The lanes weighted and summed, in four 32-bit partial sums. */
__m128i dot(const PixelLanes& pixels, const std::array<std::int16_t, kPatchColumns>& weights)
{
	__m128i sum = _mm_setzero_si128();
	for (int i = 0; i < 4; ++i)
		sum = _mm_add_epi32(sum,
			_mm_madd_epi16(pixels.lanes[i], _mm_loadu_si128(reinterpret_cast<const __m128i*>(weights.data() + 8 * i))));
	return sum;
}

int sumLanes(__m128i s)
{
	s = _mm_add_epi32(s, _mm_shuffle_epi32(s, _MM_SHUFFLE(1, 0, 3, 2)));
	s = _mm_add_epi32(s, _mm_shuffle_epi32(s, _MM_SHUFFLE(2, 3, 0, 1)));
	return _mm_cvtsi128_si32(s);
}
#endif
}  // namespace

std::vector<OrbExtractor::PatchRow> OrbExtractor::patchRows()
{
	// Its half-width at each row, made symmetric in rows and columns as ORB makes it.
	constexpr int half = kPatchSize / 2;
	std::vector<int> end(half + 2, 0);
	const int vmax = cvFloor(half * std::sqrt(2.f) / 2 + 1);
	const int vmin = cvCeil(half * std::sqrt(2.f) / 2);
	for (int v = 0; v <= vmax; ++v) end[std::size_t(v)] = cvRound(std::sqrt(double(half) * half - v * v));
	for (int v = half, v0 = 0; v >= vmin; --v)
	{
		while (end[std::size_t(v0)] == end[std::size_t(v0) + 1]) ++v0;
		end[std::size_t(v)] = v0;
		++v0;
	}
	std::vector<PatchRow> rows(half + 1);
	for (int v = 0; v <= half; ++v)
		for (int k = 0; k < kPatchColumns; ++k)
			if (const int u = k - kPatchColumns / 2; std::abs(u) <= end[std::size_t(v)])
			{
				rows[std::size_t(v)].column[std::size_t(k)] = std::int16_t(u);
				rows[std::size_t(v)].row[std::size_t(k)] = std::int16_t(v);
			}
	return rows;
}

OrbExtractor::OrbExtractor(int features, float scale, int levels, int fastThreshold)
	: m_fastThreshold(fastThreshold), m_patchRows(patchRows())
{
	// ORB keeps its scale factor as a double made from the float it is given.
	const double scaleFactor = scale;
	for (int level = 0; level < levels; ++level) m_levelScale.push_back(float(std::pow(scaleFactor, double(level))));
	m_levelFeatures = featuresPerLevel(features, scaleFactor, levels);
	// No edge threshold: a detected keypoint taken back to its level's pixels
	// can land a rounding inside the edge, and ORB would drop it there. The
	// descriptor's border (its rotated patch) does not depend on it.
	m_describer = cv::ORB::create(features, scale, 1, 0, 0, 2, cv::ORB::HARRIS_SCORE, kPatchSize, fastThreshold);
}

OrbExtractor::Pyramid OrbExtractor::build(const cv::Mat& grey, const cv::Mat& mask) const
{
	// As cv::ORB builds it: each level resized from the one before.
	Pyramid out;
	out.images.push_back(grey);
	for (std::size_t level = 1; level < m_levelScale.size(); ++level)
	{
		cv::Mat image;
		cv::resize(out.images.back(), image, levelSize(grey.size(), level), 0, 0, cv::INTER_LINEAR_EXACT);
		out.images.push_back(image);
	}
	return withMask(out, mask);
}

OrbExtractor::Pyramid OrbExtractor::withMask(const Pyramid& pyramid, const cv::Mat& mask) const
{
	// The mask's levels as cv::ORB makes them: kept only where they stay whole.
	Pyramid out{pyramid.images, {}};
	if (mask.empty()) return out;
	out.masks.push_back(mask);
	for (std::size_t level = 1; level < m_levelScale.size(); ++level)
	{
		cv::Mat levelMask;
		cv::resize(out.masks.back(), levelMask, levelSize(mask.size(), level), 0, 0, cv::INTER_LINEAR_EXACT);
		cv::threshold(levelMask, levelMask, 254, 0, cv::THRESH_TOZERO);
		out.masks.push_back(levelMask);
	}
	return out;
}

cv::Size OrbExtractor::levelSize(const cv::Size& full, std::size_t level) const
{
	const float scale = m_levelScale[level];
	return {cvRound(float(full.width) / scale), cvRound(float(full.height) / scale)};
}

void OrbExtractor::fastCorners(const cv::Mat& image, std::vector<cv::KeyPoint>& corners) const
{
	// The edge cull drops the corners within kEdgeThreshold pixels of the
	// border; a corner's test reads three pixels round it, and its
	// non-maximum suppression its neighbours' scores: the pixels from
	// kEdgeThreshold - 4 on give the kept corners as the whole image does,
	// in the same order, and FAST reads a tenth to a fifth fewer pixels.
	constexpr int skipped = kEdgeThreshold - 4;
	corners.clear();
	// A level too small for a test there has no corner the cull keeps.
	if (image.cols <= 2 * kEdgeThreshold || image.rows <= 2 * kEdgeThreshold) return;
	const cv::Rect inner(skipped, skipped, image.cols - 2 * skipped, image.rows - 2 * skipped);
	cv::FAST(image(inner), corners, m_fastThreshold, true, cv::FastFeatureDetector::TYPE_9_16);
	for (auto& kp : corners) kp.pt += cv::Point2f(float(skipped), float(skipped));
}

std::vector<cv::KeyPoint> OrbExtractor::detect(const Pyramid& pyramid) const
{
	// ORB's detection of each level: FAST corners in the mask and away from
	// the edge; of the strongest twice the level's share, the share with the
	// best Harris score.
	std::vector<cv::KeyPoint> all, level;
	for (std::size_t l = 0; l < m_levelScale.size(); ++l)
	{
		const cv::Mat& image = pyramid.images[l];
		fastCorners(image, level);
		if (!pyramid.masks.empty()) cv::KeyPointsFilter::runByPixelsMask(level, pyramid.masks[l]);
		cv::KeyPointsFilter::runByImageBorder(level, image.size(), kEdgeThreshold);
		cv::KeyPointsFilter::retainBest(level, 2 * m_levelFeatures[l]);
		for (auto& kp : level) kp.response = harrisScore(image, cvRound(kp.pt.x), cvRound(kp.pt.y));
		cv::KeyPointsFilter::retainBest(level, m_levelFeatures[l]);
		const float scale = m_levelScale[l];
		for (auto& kp : level)
		{
			kp.octave = int(l);
			kp.size = float(kPatchSize) * scale;
			kp.pt *= scale;
		}
		all.insert(all.end(), level.begin(), level.end());
	}
	return all;
}

float OrbExtractor::orientation(const cv::Mat& image, int x, int y) const
{
	// The intensity centroid of the circular patch, a row above and below the
	// centre at a time, as the patch's 32 columns -16 .. 15 weighted by the
	// row's table (zero outside the circle). The sums are integers: in any
	// order they are ORB's.
	constexpr int half = kPatchSize / 2;
	const auto step = std::ptrdiff_t(image.step);
	const std::uint8_t* centre = image.ptr<std::uint8_t>(y) + x;
#if defined(__SSE2__)
	__m128i m10 = dot(widen(centre), m_patchRows[0].column), m01 = _mm_setzero_si128();
	for (int v = 1; v <= half; ++v)
	{
		const PixelLanes below = widen(centre + v * step), above = widen(centre - v * step);
		PixelLanes sum, difference;
		for (int i = 0; i < 4; ++i)
		{
			sum.lanes[i] = _mm_add_epi16(below.lanes[i], above.lanes[i]);
			difference.lanes[i] = _mm_sub_epi16(below.lanes[i], above.lanes[i]);
		}
		m10 = _mm_add_epi32(m10, dot(sum, m_patchRows[std::size_t(v)].column));
		m01 = _mm_add_epi32(m01, dot(difference, m_patchRows[std::size_t(v)].row));
	}
	return cv::fastAtan2(float(sumLanes(m01)), float(sumLanes(m10)));
#else
	int m10 = 0, m01 = 0;
	for (int k = 0; k < kPatchColumns; ++k)
		m10 += m_patchRows[0].column[std::size_t(k)] * centre[k - kPatchColumns / 2];
	for (int v = 1; v <= half; ++v)
		for (int k = 0; k < kPatchColumns; ++k)
		{
			const int below = centre[k - kPatchColumns / 2 + v * step],
					  above = centre[k - kPatchColumns / 2 - v * step];
			m10 += m_patchRows[std::size_t(v)].column[std::size_t(k)] * (below + above);
			m01 += m_patchRows[std::size_t(v)].row[std::size_t(k)] * (below - above);
		}
	return cv::fastAtan2(float(m01), float(m10));
#endif
}

cv::Mat OrbExtractor::describe(const Pyramid& pyramid, std::vector<cv::KeyPoint>& keypoints) const
{
	cv::Mat descriptors;
	std::vector<cv::KeyPoint> level;
	for (auto first = keypoints.begin(); first != keypoints.end();)
	{
		const int octave = first->octave;
		const auto last =
			std::find_if(first, keypoints.end(), [octave](const cv::KeyPoint& kp) { return kp.octave != octave; });
		const cv::Mat& image = pyramid.images[std::size_t(octave)];
		// The level's pixels as ORB's description computes them from the full
		// image's; its detection's were whole, which rounding gives back.
		const float toLevel = 1.f / m_levelScale[std::size_t(octave)];
		level.clear();
		for (auto kp = first; kp != last; ++kp)
		{
			cv::KeyPoint atLevel = *kp;
			atLevel.pt *= toLevel;
			atLevel.octave = 0;
			kp->angle = atLevel.angle = orientation(image, cvRound(atLevel.pt.x), cvRound(atLevel.pt.y));
			level.push_back(atLevel);
		}
		cv::Mat rows;
		m_describer->compute(image, level, rows);
		if (rows.rows != int(level.size()))
			throw std::logic_error("OrbExtractor::describe: ORB dropped a keypoint of its own detection");
		descriptors.push_back(rows);
		first = last;
	}
	return descriptors;
}
}  // namespace avm::odometry::detail
