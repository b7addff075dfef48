// A pixel on a depth discontinuity, by one rule: visual odometry takes no
// feature there (its depth may be the foreground's, the background's or, for
// a mixed pixel, neither), and avm-trail sorts a person's silhouette pixels
// with it.
#pragma once

namespace avm::io
{
/** Whether pixel (u, v) of a `cols` x `rows` depth image lies on a depth
 *  discontinuity: its 3x3 neighbourhood leaves the image, holds a pixel
 *  without depth (not > 0), or spans more than `ratio` times the pixel's
 *  depth. `depthAt(u, v)` gives a pixel's depth, in any one unit. */
template <class DepthAt>
bool onDepthEdge(const DepthAt& depthAt, int u, int v, int cols, int rows, double ratio)
{
	if (u < 1 || v < 1 || u >= cols - 1 || v >= rows - 1) return true;
	const auto d = depthAt(u, v);
	auto lo = d, hi = d;
	for (int dv = -1; dv <= 1; ++dv)
		for (int du = -1; du <= 1; ++du)
		{
			const auto n = depthAt(u + du, v + dv);
			if (!(n > 0)) return true;
			lo = n < lo ? n : lo;
			hi = n > hi ? n : hi;
		}
	return hi - lo > ratio * d;
}
}  // namespace avm::io
