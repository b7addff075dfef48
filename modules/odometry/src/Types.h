// Internal data shared by the front end and the back end. Poses are T_cw
// (world to camera optical frame), the form projection uses.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <array>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "avm/io/DepthCamera.h"

namespace avm::odometry::detail
{
/** Reprojection error [px] of a world point seen at a pixel, from pose T_cw;
 *  infinite behind the camera. */
inline double reprojectionError(
	const Eigen::Isometry3d& T_cw, const Eigen::Vector3d& world, const Eigen::Vector2d& pixel, const io::DepthCamera& K)
{
	const Eigen::Vector3d pc = T_cw * world;
	if (pc.z() <= 1e-6) return std::numeric_limits<double>::infinity();
	return (K.opticalPixelOf(pc) - pixel).norm();
}

/** 256 bits, as ORB computes them. */
using OrbDescriptor = std::array<std::uint8_t, 32>;

/** Bits in which two descriptors differ, by the compiler's popcount: one
 *  instruction a 64-bit word where the target has one (x86-64 with popcnt,
 *  ARMv8's cnt), else a library call. */
inline int hammingByPopcount(const std::uint8_t* a, const std::uint8_t* b)
{
	int bits = 0;
	for (std::size_t i = 0; i < OrbDescriptor().size(); i += sizeof(std::uint64_t))
	{
		std::uint64_t x, y;
		std::memcpy(&x, a + i, sizeof x);
		std::memcpy(&y, b + i, sizeof y);
		bits += __builtin_popcountll(x ^ y);
	}
	return bits;
}

/** Bits in which two descriptors differ: the same count as
 *  cv::hal::normHamming, without its per-call trace region (in the projection
 *  search's profile that cost as much as the count). By popcount where the
 *  build targets an instruction for it; else, as x86-64's baseline has none,
 *  each byte's bits summed in parallel in SSE2's two 128-bit registers (a
 *  third of the scalar version's instructions), else in 64-bit words. The
 *  projection search picks the popcount instruction at run time
 *  (FeatureFrontend.cpp). */
inline int hamming(const std::uint8_t* a, const std::uint8_t* b)
{
#if defined(__POPCNT__) || defined(__aarch64__)
	return hammingByPopcount(a, b);
#elif defined(__SSE2__)
	const __m128i m1 = _mm_set1_epi8(0x55), m2 = _mm_set1_epi8(0x33), m4 = _mm_set1_epi8(0x0F);
	// Each byte's count (<= 8) of one register, the two registers' added (<= 16), then all bytes.
	const auto bytes = [&](const std::uint8_t* p, const std::uint8_t* q)
	{
		__m128i x = _mm_xor_si128(
			_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)), _mm_loadu_si128(reinterpret_cast<const __m128i*>(q)));
		x = _mm_sub_epi8(x, _mm_and_si128(_mm_srli_epi64(x, 1), m1));
		x = _mm_add_epi8(_mm_and_si128(x, m2), _mm_and_si128(_mm_srli_epi64(x, 2), m2));
		return _mm_and_si128(_mm_add_epi8(x, _mm_srli_epi64(x, 4)), m4);
	};
	const __m128i x = _mm_sad_epu8(_mm_add_epi8(bytes(a, b), bytes(a + 16, b + 16)), _mm_setzero_si128());
	return _mm_cvtsi128_si32(x) + _mm_extract_epi16(x, 4);
#else
	int bits = 0;
	for (std::size_t i = 0; i < OrbDescriptor().size(); i += sizeof(std::uint64_t))
	{
		std::uint64_t x, y;
		std::memcpy(&x, a + i, sizeof x);
		std::memcpy(&y, b + i, sizeof y);
		x ^= y;
		x -= (x >> 1) & 0x5555555555555555ULL;
		x = (x & 0x3333333333333333ULL) + ((x >> 2) & 0x3333333333333333ULL);
		x = (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0FULL;
		bits += int((x * 0x0101010101010101ULL) >> 56);
	}
	return bits;
#endif
}

/** Row `row` of a descriptor matrix (CV_8U, 32 bytes a row). */
inline OrbDescriptor descriptorRow(const cv::Mat& descriptors, int row)
{
	OrbDescriptor d;
	std::memcpy(d.data(), descriptors.ptr(row), d.size());
	return d;
}

/** Features of one frame; every one has a valid depth. */
struct FrameFeatures
{
	std::vector<cv::KeyPoint> keypoints;
	cv::Mat descriptors;                  //!< one ORB descriptor (CV_8U, 32 bytes) per row
	std::vector<Eigen::Vector3d> points;  //!< [m] back-projected in the camera optical frame
	io::DepthCamera K;  //!< the registered depth and intensity images' camera, used in its optical frame
	cv::Size imageSize;

	const std::uint8_t* descriptorData(int i) const { return descriptors.ptr<std::uint8_t>(i); }
	OrbDescriptor descriptor(int i) const { return descriptorRow(descriptors, i); }
};

struct Landmark
{
	Eigen::Vector3d position;  //!< [m] world
	OrbDescriptor descriptor;  //!< from the latest keyframe that saw it
	/** A point of the keyframe map a loop joined: the window's adjustment
	 *  holds it where the map has it, so the local map stays in the old map's frame. */
	bool anchored = false;
};

/** A landmark seen at a pixel with a measured depth. */
struct Observation
{
	int landmark = -1;
	int feature = -1;  //!< the feature of its frame (FrameFeatures) it is
	Eigen::Vector2d pixel;
	double depth = 0;  //!< [m]
};

struct Match
{
	int feature = -1;
	int landmark = -1;
};
}  // namespace avm::odometry::detail
