#include "SwishLayer.h"

#include <opencv2/dnn.hpp>
#include <opencv2/dnn/all_layers.hpp>
#include <opencv2/dnn/layer.details.hpp>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <vector>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define AVM_SWISH_AVX2 1
#endif

namespace avm::detection::detail
{
namespace
{
float swishOf(float x) { return x / (1.f + std::exp(-x)); }

#ifdef AVM_SWISH_AVX2
/** e^x of eight floats x <= 0: x = n ln2 + r with |r| <= ln2 / 2, e^r by
 *  Cephes' degree-6 polynomial, 2^n put into the exponent bits; 0 below the
 *  smallest normal float's logarithm. */
__attribute__((target("avx2,fma"))) __m256 expOfNonPositive(__m256 x)
{
	const __m256 lowest = _mm256_set1_ps(-87.3365447505531f);
	const __m256 underflows = _mm256_cmp_ps(x, lowest, _CMP_LT_OQ);
	x = _mm256_max_ps(x, lowest);
	const __m256 n = _mm256_floor_ps(_mm256_fmadd_ps(x, _mm256_set1_ps(1.44269504088896341f), _mm256_set1_ps(0.5f)));
	// ln2 in two parts, so that n ln2 is subtracted exactly.
	x = _mm256_fnmadd_ps(n, _mm256_set1_ps(0.693359375f), x);
	x = _mm256_fnmadd_ps(n, _mm256_set1_ps(-2.12194440e-4f), x);
	__m256 p = _mm256_set1_ps(1.9875691500e-4f);
	for (const float c : {1.3981999507e-3f, 8.3334519073e-3f, 4.1665795894e-2f, 1.6666665459e-1f, 5.0000001201e-1f})
		p = _mm256_fmadd_ps(p, x, _mm256_set1_ps(c));
	const __m256 er = _mm256_add_ps(_mm256_fmadd_ps(p, _mm256_mul_ps(x, x), x), _mm256_set1_ps(1.f));
	const __m256i twoToN = _mm256_slli_epi32(_mm256_add_epi32(_mm256_cvttps_epi32(n), _mm256_set1_epi32(127)), 23);
	return _mm256_andnot_ps(underflows, _mm256_mul_ps(er, _mm256_castsi256_ps(twoToN)));
}

/** x / (1 + e^-x) of eight floats, as x / (1 + e^-|x|) for x >= 0 and
 *  x e^x / (1 + e^x) below: e^-|x| cannot overflow, so a large negative x
 *  gives zero, not x over infinity. */
__attribute__((target("avx2,fma"))) __m256 swish8(__m256 x)
{
	const __m256 e = expOfNonPositive(_mm256_or_ps(x, _mm256_set1_ps(-0.f)));
	const __m256 numerator = _mm256_blendv_ps(x, _mm256_mul_ps(x, e), x);
	return _mm256_div_ps(numerator, _mm256_add_ps(_mm256_set1_ps(1.f), e));
}

/** The floats past the last whole eight go through swish8 too: OpenCV hands
 *  the layer slices whose bounds follow its threads, and a value must not
 *  depend on where a slice ends. */
__attribute__((target("avx2,fma"))) void swishAvx2(const float* src, float* dst, int n)
{
	int i = 0;
	for (; i + 8 <= n; i += 8) _mm256_storeu_ps(dst + i, swish8(_mm256_loadu_ps(src + i)));
	if (i == n) return;
	alignas(32) float rest[8] = {};
	std::copy(src + i, src + n, rest);
	_mm256_store_ps(rest, swish8(_mm256_load_ps(rest)));
	std::copy(rest, rest + (n - i), dst + i);
}

bool hasAvx2()
{
	static const bool has = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
	return has;
}
#endif

class SwishLayer : public cv::dnn::ActivationLayer
{
   public:
	explicit SwishLayer(const cv::dnn::LayerParams& params) { setParamsFrom(params); }

	static cv::Ptr<cv::dnn::Layer> create(cv::dnn::LayerParams& params) { return cv::makePtr<SwishLayer>(params); }

	/** The output has the input's shape and may be computed in place. */
	bool getMemoryShapes(const std::vector<cv::dnn::MatShape>& inputs, int requiredOutputs,
		std::vector<cv::dnn::MatShape>& outputs, std::vector<cv::dnn::MatShape>& internals) const override
	{
		cv::dnn::Layer::getMemoryShapes(inputs, requiredOutputs, outputs, internals);
		return true;
	}

	/** Where OpenCV did not fuse the layer into a convolution. */
	void forward(
		cv::InputArrayOfArrays inputsArray, cv::OutputArrayOfArrays outputsArray, cv::OutputArrayOfArrays) override
	{
		std::vector<cv::Mat> inputs, outputs;
		inputsArray.getMatVector(inputs);
		outputsArray.getMatVector(outputs);
		for (std::size_t i = 0; i < inputs.size(); ++i)
		{
			CV_Assert(inputs[i].type() == CV_32F && inputs[i].isContinuous() && outputs[i].isContinuous());
			swish(inputs[i].ptr<float>(), outputs[i].ptr<float>(), static_cast<int>(inputs[i].total()));
		}
	}

	/** Fused into a convolution: channels cn0 to cn1, `len` floats of each,
	 *  the channels planeSize floats apart. */
	void forwardSlice(const float* src, float* dst, int len, std::size_t planeSize, int cn0, int cn1) const override
	{
		for (int c = cn0; c < cn1; ++c, src += planeSize, dst += planeSize) swish(src, dst, len);
	}
};
}  // namespace

void swish(const float* src, float* dst, int n)
{
#ifdef AVM_SWISH_AVX2
	if (hasAvx2()) return swishAvx2(src, dst, n);
#endif
	for (int i = 0; i < n; ++i) dst[i] = swishOf(src[i]);
}

void registerSwishLayer()
{
	static std::once_flag registered;
	std::call_once(registered, [] { cv::dnn::LayerFactory::registerLayer(kSwishLayerType, SwishLayer::create); });
}
}  // namespace avm::detection::detail
