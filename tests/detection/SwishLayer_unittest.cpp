// The Swish layer's arithmetic against x / (1 + e^-x) in double precision:
// its exp is a polynomial of its own (SwishLayer.h), so every range of inputs
// a network gives, and some it should not, is checked here; the layer inside
// YOLOX-Nano is checked against the model as exported in DnnGraph_unittest.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "SwishLayer.h"

using avm::detection::detail::swish;

namespace
{
double exactSwish(double x) { return x / (1.0 + std::exp(-x)); }

std::vector<float> swishOf(const std::vector<float>& x)
{
	std::vector<float> y(x.size());
	swish(x.data(), y.data(), static_cast<int>(x.size()));
	return y;
}
}  // namespace

TEST(SwishLayer, IsWithinAMillionthOfTheExactValue)
{
	std::vector<float> x;
	for (int i = -200000; i <= 200000; ++i) x.push_back(static_cast<float>(i) * 5e-4f);  // -100 to 100
	for (const float v : {0.f, -0.f, 1e-30f, -1e-30f, 1e-40f, 87.f, 88.f, 89.f, -87.f, -88.f, -89.f, 1e30f, -1e30f})
		x.push_back(v);
	const auto y = swishOf(x);
	double worst = 0;
	for (std::size_t i = 0; i < x.size(); ++i)
	{
		const double exact = exactSwish(x[i]), error = std::abs(y[i] - exact);
		worst = std::max(worst, error / std::max(std::abs(exact), 1e-30));
		// Below -87, where e^x is no longer a normal float, the layer gives
		// zero (as libm's expf(-x) overflowing to infinity gives it from -89).
		ASSERT_LE(error, 1e-6 * std::abs(exact) + (x[i] < -87.f ? 1e-35 : 0.0))
			<< "swish(" << x[i] << ") = " << y[i] << ", exactly " << exact;
	}
	EXPECT_GT(worst, 0.0);  // floats: not the double values themselves
}

TEST(SwishLayer, EveryLengthAndInPlace)
{
	for (int n = 0; n <= 19; ++n)
	{
		std::vector<float> x(static_cast<std::size_t>(n));
		for (int i = 0; i < n; ++i) x[std::size_t(i)] = 0.37f * static_cast<float>(i) - 3.f;
		const auto y = swishOf(x);
		for (int i = 0; i < n; ++i)
			EXPECT_NEAR(y[std::size_t(i)], exactSwish(x[std::size_t(i)]), 1e-6) << "element " << i << " of " << n;
		swish(x.data(), x.data(), n);
		EXPECT_EQ(x, y) << n << " floats in place";
	}
}

// OpenCV hands a fused activation slices whose bounds follow its threads: a
// value computed alone, at the end of a slice or inside one must be the same.
TEST(SwishLayer, AValueDoesNotDependOnTheSliceItIsIn)
{
	std::vector<float> x(37);
	for (std::size_t i = 0; i < x.size(); ++i) x[i] = 0.61f * static_cast<float>(i) - 11.f;
	const auto whole = swishOf(x);
	for (std::size_t i = 0; i < x.size(); ++i)
	{
		float alone = 0;
		swish(&x[i], &alone, 1);
		EXPECT_EQ(alone, whole[i]) << "x = " << x[i];
	}
}

TEST(SwishLayer, NotANumberAndInfinity)
{
	const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
	const auto y = swishOf({nan, inf, 1.f, nan, 2.f, 3.f, 4.f, 5.f, nan});
	EXPECT_TRUE(std::isnan(y[0]));
	EXPECT_EQ(y[1], inf);
	EXPECT_TRUE(std::isnan(y[3]));
	EXPECT_TRUE(std::isnan(y[8]));  // past the last whole eight
}
