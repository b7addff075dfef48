#include "ReprojectionCost.h"

#include <ceres/rotation.h>

#include <Eigen/Geometry>
#include <limits>

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

/** d(R(aa) p)/d(aa) and R(aa), the derivatives of ceres::AngleAxisRotatePoint
 *  in each of its two branches (Rodrigues' formula; its first order within
 *  double epsilon of no rotation), which is what automatic differentiation
 *  gave before. */
void rotationDerivatives(
	const Eigen::Vector3d& aa, const Eigen::Vector3d& p, Eigen::Matrix3d& dAngleAxis, Eigen::Matrix3d& rotation)
{
	const double theta2 = aa.squaredNorm();
	if (theta2 <= std::numeric_limits<double>::epsilon())
	{
		dAngleAxis = -skew(p);
		rotation = Eigen::Matrix3d::Identity() + skew(aa);
		return;
	}
	const double theta = std::sqrt(theta2), c = std::cos(theta), s = std::sin(theta);
	const Eigen::Vector3d w = aa / theta;
	const double wp = w.dot(p);
	// result = c p + s (w x p) + (1 - c) (w . p) w, with dtheta = w^T daa and dw = (I - w w^T) / theta daa.
	const Eigen::Matrix3d dw = (Eigen::Matrix3d::Identity() - w * w.transpose()) / theta;
	const Eigen::Vector3d dTheta = -s * p + c * w.cross(p) + s * wp * w;
	dAngleAxis = dTheta * w.transpose() +
				 (-s * skew(p) + (1 - c) * w * p.transpose() + (1 - c) * wp * Eigen::Matrix3d::Identity()) * dw;
	rotation = c * Eigen::Matrix3d::Identity() + s * skew(w) + (1 - c) * w * w.transpose();
}

class PosePointCost : public ceres::SizedCostFunction<3, 6, 3>
{
   public:
	explicit PosePointCost(const ReprojectionDepthCost& cost) : m_cost(cost) {}
	bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override
	{
		m_cost.evaluate(parameters[0], parameters[1], residuals, jacobians ? jacobians[0] : nullptr,
			jacobians ? jacobians[1] : nullptr);
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
	double pc[3];
	ceres::AngleAxisRotatePoint(pose, point, pc);
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
	Eigen::Matrix3d dAngleAxis, rotation;
	rotationDerivatives(Eigen::Vector3d(pose[0], pose[1], pose[2]), Eigen::Vector3d(point[0], point[1], point[2]),
		dAngleAxis, rotation);
	if (poseJacobian)
	{
		Eigen::Map<Eigen::Matrix<double, 3, 6, Eigen::RowMajor>> J(poseJacobian);
		J.leftCols<3>() = dResidual * dAngleAxis;
		J.rightCols<3>() = dResidual;
	}
	if (pointJacobian)
	{
		Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> J(pointJacobian);
		J = dResidual * rotation;
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
