// PoseTransform gives MRPT's bits: the map's and the person layer's points,
// and so their voxels, are the ones CPose3D's calls would give.
#include <gtest/gtest.h>
#include <mrpt/random/RandomGenerators.h>

#include "avm/io/PoseTransform.h"

namespace
{
TEST(PoseTransform, TransformsToMrptsBits)
{
	mrpt::random::CRandomGenerator random(7);
	for (int pose = 0; pose < 200; pose++)
	{
		const auto u = [&](double a) { return random.drawUniform(-a, a); };
		const mrpt::poses::CPose3D p(u(20), u(20), u(5), u(M_PI), u(M_PI / 2), u(M_PI));
		const avm::io::PoseTransform t(p);
		for (int point = 0; point < 50; point++)
		{
			const mrpt::math::TPoint3D x(u(10), u(10), u(10));
			const auto composed = p.composePoint(x), inverse = p.inverseComposePoint(x);
			const auto ours = t.compose(x), oursInverse = t.inverseCompose(x);
			const auto rotated = p.inverseRotateVector(x), oursRotated = t.inverseRotate(x);
			for (int i = 0; i < 3; i++)
			{
				// Bit for bit, not near: EXPECT_EQ on the doubles.
				EXPECT_EQ(ours[i], composed[i]) << "pose " << p << " point " << x;
				EXPECT_EQ(oursInverse[i], inverse[i]) << "pose " << p << " point " << x;
				EXPECT_EQ(oursRotated[i], rotated[i]) << "pose " << p << " vector " << x;
			}
		}
	}
}
}  // namespace
