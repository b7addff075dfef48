// SiLU, x / (1 + e^-x), as a cv::dnn activation layer of ours. OpenCV 4.6's
// own Swish layer calls libm's expf and divides one float at a time; in
// YOLOX-Nano that loop took about a third of the network's time at 256x192.
// This layer computes eight floats at a time where the CPU has AVX2 and FMA
// (a Cephes-style exp: within a millionth of the exact value), one at a time
// as OpenCV does on other CPUs. OpenCV fuses it into the convolution before
// it, as its own.
#pragma once

namespace avm::detection::detail
{
/** The layer type the graph rewrite gives SiLU's nodes. */
inline constexpr const char* kSwishLayerType = "AvmSwish";

/** Registers kSwishLayerType with cv::dnn (once a process: OpenCV's layer
 *  registry is the process's), so that a graph naming it loads. */
void registerSwishLayer();

/** dst[i] = src[i] / (1 + e^-src[i]) for i < n (dst may be src). */
void swish(const float* src, float* dst, int n);
}  // namespace avm::detection::detail
