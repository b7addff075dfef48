#include "avm/io/Trajectory.h"

#include <mrpt/math/CQuaternion.h>
#include <mrpt/poses/CPose3DQuat.h>

// GCC 12 reports a false -Wmaybe-uninitialized inside Eigen's fixed-size JacobiSVD.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <Eigen/Dense>
#include <Eigen/Geometry>
#pragma GCC diagnostic pop
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "TextLines.h"
#include "avm/io/AtomicFile.h"

namespace avm::io
{
namespace fs = std::filesystem;

namespace
{
Eigen::Quaterniond quaternionOf(const mrpt::poses::CPose3D& p)
{
	const auto& R = p.getRotationMatrix();
	Eigen::Matrix3d m;
	for (int r = 0; r < 3; ++r)
		for (int c = 0; c < 3; ++c) m(r, c) = R(r, c);
	return Eigen::Quaterniond(m).normalized();
}

mrpt::poses::CPose3D poseOf(const Eigen::Vector3d& t, const Eigen::Quaterniond& q)
{
	return mrpt::poses::CPose3D(
		mrpt::poses::CPose3DQuat(t.x(), t.y(), t.z(), mrpt::math::CQuaternionDouble(q.w(), q.x(), q.y(), q.z())));
}
}  // namespace

std::vector<std::size_t> timeOrder(const Trajectory& poses)
{
	std::vector<std::size_t> order(poses.size());
	std::iota(order.begin(), order.end(), std::size_t{0});
	std::stable_sort(order.begin(), order.end(),
		[&](std::size_t a, std::size_t b) { return poses[a].timestamp < poses[b].timestamp; });
	return order;
}

Trajectory inTimeOrder(const Trajectory& poses)
{
	Trajectory out;
	out.reserve(poses.size());
	for (const auto i : timeOrder(poses)) out.push_back(poses[i]);
	return out;
}

Trajectory readTumTrajectory(const fs::path& file)
{
	Trajectory out;
	detail::forEachDataLine(file,
		[&](std::istream& ss, std::size_t lineNo)
		{
			double v[8];
			for (double& x : v)
			{
				// strtod, unlike operator>>, reads "nan" and "inf", so they are
				// reported as such rather than as a malformed line.
				std::string token;
				char* end = nullptr;
				if (!(ss >> token) || (x = std::strtod(token.c_str(), &end), *end != '\0'))
					detail::failAt(file, lineNo, "expected 'timestamp tx ty tz qx qy qz qw'");
			}
			if (!std::all_of(std::begin(v), std::end(v), [](double x) { return std::isfinite(x); }))
				detail::failAt(file, lineNo, "non-finite value");
			Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
			if (std::abs(q.norm() - 1.0) > 1e-2)
				detail::failAt(file, lineNo, "quaternion is not of unit norm (" + std::to_string(q.norm()) + ")");
			// Equal times are two estimates of one instant: sessions cut from one
			// recording that overlap each place the frames they share.
			if (!out.empty() && v[0] < out.back().timestamp) detail::failAt(file, lineNo, "timestamps out of order");
			out.push_back({v[0], poseOf({v[1], v[2], v[3]}, q.normalized())});
		});
	return out;
}

std::string toTumLine(const TimedPose& p)
{
	const auto q = quaternionOf(p.pose);
	char buf[256];
	std::snprintf(buf, sizeof(buf), "%.6f %.6f %.6f %.6f %.7f %.7f %.7f %.7f", p.timestamp, p.pose.x(), p.pose.y(),
		p.pose.z(), q.x(), q.y(), q.z(), q.w());
	return buf;
}

void writeTumTrajectory(const fs::path& file, const Trajectory& poses, const std::string& header)
{
	writeFileAtomically(file,
		[&](const fs::path& tmp)
		{
			std::ofstream out(tmp);
			if (!out) throw std::runtime_error(file.string() + ": cannot write trajectory");
			out << "# " << (header.empty() ? "trajectory" : header) << "\n";
			out << "# timestamp tx ty tz qx qy qz qw\n";
			for (const auto& p : poses) out << toTumLine(p) << "\n";
			if (!out.flush()) throw std::runtime_error(file.string() + ": write failed");
		});
}

std::optional<mrpt::poses::CPose3D> interpolatePose(const Trajectory& poses, double t, double maxGap)
{
	if (poses.empty() || t < poses.front().timestamp || t > poses.back().timestamp) return {};
	const auto after = std::lower_bound(
		poses.begin(), poses.end(), t, [](const TimedPose& p, double time) { return p.timestamp < time; });
	if (after->timestamp == t) return after->pose;
	const auto before = std::prev(after);
	const double gap = after->timestamp - before->timestamp;
	if (gap > maxGap) return {};
	const double a = (t - before->timestamp) / gap;
	const Eigen::Vector3d t0(before->pose.x(), before->pose.y(), before->pose.z());
	const Eigen::Vector3d t1(after->pose.x(), after->pose.y(), after->pose.z());
	const auto q = quaternionOf(before->pose).slerp(a, quaternionOf(after->pose));
	return poseOf((1 - a) * t0 + a * t1, q);
}

mrpt::poses::CPose3D rigidTransformFromMatrix(const double (&m)[16])
{
	for (double x : m)
		if (!std::isfinite(x)) throw std::runtime_error("transform matrix has a non-finite value");
	Eigen::Matrix3d A;
	for (int r = 0; r < 3; ++r)
		for (int c = 0; c < 3; ++c) A(r, c) = m[4 * r + c];
	const Eigen::JacobiSVD<Eigen::Matrix3d> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
	// Its success first: on a failure JacobiSVD leaves the singular values unset.
	if (svd.info() != Eigen::Success || svd.singularValues().minCoeff() < 1e-6)
		throw std::runtime_error("transform matrix has a degenerate rotation block");
	const Eigen::Matrix3d R = svd.matrixU() * svd.matrixV().transpose();
	if (R.determinant() < 0) throw std::runtime_error("transform matrix is a reflection");
	return poseOf({m[3], m[7], m[11]}, Eigen::Quaterniond(R));
}

mrpt::poses::CPose3D readRigidTransformFile(const fs::path& file)
{
	std::ifstream in(file);
	if (!in) throw std::runtime_error(file.string() + ": cannot open transform file");
	double m[16];
	for (double& x : m)
		if (!(in >> x)) throw std::runtime_error(file.string() + ": expected a 4x4 matrix (16 numbers)");
	try
	{
		return rigidTransformFromMatrix(m);
	}
	catch (const std::exception& e)
	{
		throw std::runtime_error(file.string() + ": " + e.what());
	}
}
}  // namespace avm::io
