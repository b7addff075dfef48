#include "ReprojectionCost.h"

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

namespace avm::odometry::detail
{
namespace
{
Eigen::Matrix3d skew(const Eigen::Vector3d& v)
{
	Eigen::Matrix3d m;
	m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
	return m;
}

}  // namespace

/** What the residual needs of a pose's angle-axis alone: the point-free terms
 *  of ceres::AngleAxisRotatePoint and of the rotation's derivatives. Every
 *  residual of a frame's refinement is evaluated at the same pose, and working
 *  these out for each (two sines and cosines, a few 3x3 products) was most of
 *  the residual's time. The point's terms below are computed as before, in the
 *  same order: the numbers are the same to the bit. */
struct RotationTerms
{
	std::array<double, 3> angleAxis{};
	// ceres::AngleAxisRotatePoint's: its first-order branch within double epsilon of no rotation.
	bool ceresSmall = true;
	double costheta = 1, sintheta = 0, w[3] = {0, 0, 0};
	// The derivatives' (Rodrigues' formula; its first order in the same place).
	bool small = true;
	double c = 1, s = 0, theta = 0;
	Eigen::Vector3d axis = Eigen::Vector3d::Zero();
	Eigen::Matrix3d dAxis = Eigen::Matrix3d::Zero(), rotation = Eigen::Matrix3d::Identity();

	explicit RotationTerms(const double* aa) : angleAxis{aa[0], aa[1], aa[2]}
	{
		const double theta2Ceres = aa[0] * aa[0] + aa[1] * aa[1] + aa[2] * aa[2];
		ceresSmall = !(theta2Ceres > std::numeric_limits<double>::epsilon());
		if (!ceresSmall)
		{
			const double thetaCeres = std::sqrt(theta2Ceres);
			costheta = std::cos(thetaCeres);
			sintheta = std::sin(thetaCeres);
			const double inverse = 1.0 / thetaCeres;
			for (int i = 0; i < 3; ++i) w[i] = aa[i] * inverse;
		}
		const Eigen::Vector3d v(aa[0], aa[1], aa[2]);
		const double theta2 = v.squaredNorm();
		small = theta2 <= std::numeric_limits<double>::epsilon();
		if (small)
		{
			rotation = Eigen::Matrix3d::Identity() + skew(v);
			return;
		}
		theta = std::sqrt(theta2);
		c = std::cos(theta);
		s = std::sin(theta);
		axis = v / theta;
		// dtheta = w^T daa and dw = (I - w w^T) / theta daa.
		dAxis = (Eigen::Matrix3d::Identity() - axis * axis.transpose()) / theta;
		rotation = c * Eigen::Matrix3d::Identity() + s * skew(axis) + (1 - c) * axis * axis.transpose();
	}

	/** R(aa) p, as ceres::AngleAxisRotatePoint gives it. */
	void rotate(const double* p, double* out) const
	{
		if (ceresSmall)
		{
			const double* aa = angleAxis.data();
			const double cross[3] = {
				aa[1] * p[2] - aa[2] * p[1], aa[2] * p[0] - aa[0] * p[2], aa[0] * p[1] - aa[1] * p[0]};
			for (int i = 0; i < 3; ++i) out[i] = p[i] + cross[i];
			return;
		}
		const double cross[3] = {w[1] * p[2] - w[2] * p[1], w[2] * p[0] - w[0] * p[2], w[0] * p[1] - w[1] * p[0]};
		const double tmp = (w[0] * p[0] + w[1] * p[1] + w[2] * p[2]) * (1.0 - costheta);
		for (int i = 0; i < 3; ++i) out[i] = p[i] * costheta + cross[i] * sintheta + w[i] * tmp;
	}

	/** d(R(aa) p)/d(aa), what automatic differentiation of ceres::AngleAxisRotatePoint gave. */
	Eigen::Matrix3d dRotatedPoint(const Eigen::Vector3d& p) const
	{
		if (small) return -skew(p);
		const double wp = axis.dot(p);
		// result = c p + s (w x p) + (1 - c) (w . p) w
		const Eigen::Vector3d dTheta = -s * p + c * axis.cross(p) + s * wp * axis;
		return dTheta * axis.transpose() +
			   (-s * skew(p) + (1 - c) * axis * p.transpose() + (1 - c) * wp * Eigen::Matrix3d::Identity()) * dAxis;
	}
};

namespace
{
/** The terms of the last pose this thread evaluated at: a function of the
 *  angle-axis' bits alone, so whether they come from here or anew never
 *  changes a number. */
const RotationTerms& rotationTermsOf(const double* aa)
{
	thread_local RotationTerms last(std::array<double, 3>{0, 0, 0}.data());
	if (std::memcmp(last.angleAxis.data(), aa, sizeof(last.angleAxis)) != 0) last = RotationTerms(aa);
	return last;
}

/** The terms of each pose of the window this thread evaluates: Ceres orders
 *  the window's residuals by point for the Schur complement, each at another
 *  pose than the one before, and working the terms out for every residual
 *  took a tenth of the adjustment's time. A pose's parameters lie at one address
 *  through an evaluation (Ceres points them into its state vector); the terms
 *  are checked against the angle-axis' bits there, so that a reused address
 *  with other values, or a stale entry, never changes a number. */
const RotationTerms& windowRotationTermsOf(const double* aa)
{
	struct Entry
	{
		const double* address;
		RotationTerms terms;
	};
	constexpr std::size_t kPoses = 64;  // more than any window has
	thread_local std::vector<Entry> entries;
	thread_local std::size_t next = 0;
	for (auto& e : entries)
		if (e.address == aa)
		{
			if (std::memcmp(e.terms.angleAxis.data(), aa, sizeof(e.terms.angleAxis)) != 0) e.terms = RotationTerms(aa);
			return e.terms;
		}
	if (entries.size() < kPoses)
	{
		entries.push_back({aa, RotationTerms(aa)});
		return entries.back().terms;
	}
	Entry& e = entries[next];
	next = (next + 1) % kPoses;
	e = {aa, RotationTerms(aa)};
	return e.terms;
}

class PosePointCost : public ceres::SizedCostFunction<3, 6, 3>
{
   public:
	explicit PosePointCost(const ReprojectionDepthCost& cost) : m_cost(cost) {}
	bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override
	{
		m_cost.evaluate(windowRotationTermsOf(parameters[0]), parameters[0], parameters[1], residuals,
			jacobians ? jacobians[0] : nullptr, jacobians ? jacobians[1] : nullptr);
		return true;
	}

   private:
	ReprojectionDepthCost m_cost;
};

class FixedPointCost : public ceres::SizedCostFunction<3, 6>
{
   public:
	FixedPointCost(const ReprojectionDepthCost& cost, const Eigen::Vector3d& point) : m_cost(cost), m_point(point) {}
	bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override
	{
		m_cost.evaluate(parameters[0], m_point.data(), residuals, jacobians ? jacobians[0] : nullptr, nullptr);
		return true;
	}

   private:
	ReprojectionDepthCost m_cost;
	Eigen::Vector3d m_point;
};
}  // namespace

void ReprojectionDepthCost::evaluate(
	const double* pose, const double* point, double* residual, double* poseJacobian, double* pointJacobian) const
{
	evaluate(rotationTermsOf(pose), pose, point, residual, poseJacobian, pointJacobian);
}

void ReprojectionDepthCost::evaluate(const RotationTerms& terms, const double* pose, const double* point,
	double* residual, double* poseJacobian, double* pointJacobian) const
{
	double pc[3];
	terms.rotate(point, pc);
	pc[0] += pose[3];
	pc[1] += pose[4];
	pc[2] += pose[5];
	const bool clamped = pc[2] < 1e-3;
	if (clamped) pc[2] = 1e-3;  // keeps a point that slipped behind finite (and its depth still)
	double pixel[2];
	m_K.opticalPixelOf(pc, pixel);
	const double depthScale = m_depthWeight * m_K.fx / m_depth;
	residual[0] = pixel[0] - m_u;
	residual[1] = pixel[1] - m_v;
	residual[2] = depthScale * (pc[2] - m_depth);
	if (!poseJacobian && !pointJacobian) return;

	// The residual's derivative in the camera point, then the point's in the parameters.
	const double z = pc[2];
	Eigen::Matrix3d dResidual;
	dResidual << m_K.fx / z, 0, -m_K.fx * pc[0] / (z * z), 0, m_K.fy / z, -m_K.fy * pc[1] / (z * z), 0, 0, depthScale;
	if (clamped) dResidual.col(2).setZero();
	if (poseJacobian)
	{
		Eigen::Map<Eigen::Matrix<double, 3, 6, Eigen::RowMajor>> J(poseJacobian);
		J.leftCols<3>() = dResidual * terms.dRotatedPoint(Eigen::Vector3d(point[0], point[1], point[2]));
		J.rightCols<3>() = dResidual;
	}
	if (pointJacobian)
	{
		Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> J(pointJacobian);
		J = dResidual * terms.rotation;
	}
}

ceres::CostFunction* ReprojectionDepthCost::create(const Observation& obs, const io::DepthCamera& K, double depthWeight)
{
	return new PosePointCost(ReprojectionDepthCost(obs, K, depthWeight));
}

ceres::CostFunction* ReprojectionDepthCost::createFixedPoint(
	const Observation& obs, const Eigen::Vector3d& point, const io::DepthCamera& K, double depthWeight)
{
	return new FixedPointCost(ReprojectionDepthCost(obs, K, depthWeight), point);
}
}  // namespace avm::odometry::detail
