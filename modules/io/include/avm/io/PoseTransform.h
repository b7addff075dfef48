// A pose's transforms for loops over many points: CPose3D's composePoint,
// inverseComposePoint and inverseRotateVector with MRPT 2.5's sums, term for
// term and in its order, so that they give the same bits (avm and MRPT are
// both built without -march flags: nothing contracts a product and a sum
// into one rounding). The pose's rotation and translation are copied, and
// its inverse made, once: MRPT's calls pass three optional Jacobians for
// every point, and inverseComposePoint inverts the pose again for every point.
#pragma once

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/math/TPoint3D.h>
#include <mrpt/poses/CPose3D.h>

namespace avm::io
{
class PoseTransform
{
   public:
	explicit PoseTransform(const mrpt::poses::CPose3D& pose) : m_R(pose.getRotationMatrix()), m_t(pose.m_coords)
	{
		// mrpt::math::homogeneousMatrixInverse's translation.
		const double tx = -m_t[0], ty = -m_t[1], tz = -m_t[2];
		for (int i = 0; i < 3; i++) m_tInverse[i] = tx * m_R(0, i) + ty * m_R(1, i) + tz * m_R(2, i);
	}

	/** pose.composePoint(local): the point in the frame the pose is given in. */
	mrpt::math::TPoint3D compose(const mrpt::math::TPoint3D& l) const
	{
		return {m_R(0, 0) * l.x + m_R(0, 1) * l.y + m_R(0, 2) * l.z + m_t[0],
			m_R(1, 0) * l.x + m_R(1, 1) * l.y + m_R(1, 2) * l.z + m_t[1],
			m_R(2, 0) * l.x + m_R(2, 1) * l.y + m_R(2, 2) * l.z + m_t[2]};
	}

	/** pose.inverseComposePoint(global): the point in the pose's own frame. */
	mrpt::math::TPoint3D inverseCompose(const mrpt::math::TPoint3D& g) const
	{
		return {m_tInverse[0] + m_R(0, 0) * g.x + m_R(1, 0) * g.y + m_R(2, 0) * g.z,
			m_tInverse[1] + m_R(0, 1) * g.x + m_R(1, 1) * g.y + m_R(2, 1) * g.z,
			m_tInverse[2] + m_R(0, 2) * g.x + m_R(1, 2) * g.y + m_R(2, 2) * g.z};
	}

	/** pose.inverseRotateVector(global): a direction in the pose's own frame. */
	mrpt::math::TPoint3D inverseRotate(const mrpt::math::TPoint3D& g) const
	{
		return {m_R(0, 0) * g.x + m_R(1, 0) * g.y + m_R(2, 0) * g.z,
			m_R(0, 1) * g.x + m_R(1, 1) * g.y + m_R(2, 1) * g.z, m_R(0, 2) * g.x + m_R(1, 2) * g.y + m_R(2, 2) * g.z};
	}

   private:
	mrpt::math::CMatrixDouble33 m_R;
	mrpt::math::CVectorFixedDouble<3> m_t, m_tInverse;
};
}  // namespace avm::io
