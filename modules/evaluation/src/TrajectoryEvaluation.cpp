#include "avm/evaluation/TrajectoryEvaluation.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/bits_math.h>

// GCC 12 reports a false -Wmaybe-uninitialized inside Eigen's fixed-size JacobiSVD.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <Eigen/Dense>
#include <Eigen/Geometry>
#pragma GCC diagnostic pop

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <numeric>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "avm/io/IniKeys.h"

namespace avm::evaluation
{
io::IniKeys<TEvaluationOptions> TEvaluationOptions::iniKeys()
{
	using O = TEvaluationOptions;
	const io::IniRule<double> positiveSeconds{[](double v) { return v > 0; }, "must be a positive number of seconds"};
	const io::IniRule<std::int64_t> count{[](std::int64_t v) { return v >= 0; }, "must be >= 0"};
	io::IniKeys<O> keys;
	keys.number("max_time_difference", &O::maxTimeDifference, "s",
			"an estimated pose is matched with the ground-truth pose nearest in time at most this far", positiveSeconds)
		.number<std::int64_t>("first_frame", &O::firstFrame, "", "index of the first estimated pose evaluated", count)
		.number<std::int64_t>(
			"max_frames", &O::maxFrames, "", "estimated poses evaluated from first_frame; 0 = all", count)
		.number("rpe_delta", &O::rpeDelta, "s", "time step of the relative pose error", positiveSeconds);
	return keys;
}

std::vector<std::pair<std::size_t, std::size_t>> associateByTimestamp(
	const io::Trajectory& estimate, const io::Trajectory& groundTruth, double maxTimeDifference)
{
	std::vector<std::pair<std::size_t, std::size_t>> pairs;
	for (std::size_t i = 0; i < estimate.size(); ++i)
	{
		const double t = estimate[i].timestamp;
		const auto it = std::lower_bound(groundTruth.begin(), groundTruth.end(), t,
			[](const io::TimedPose& p, double time) { return p.timestamp < time; });
		std::size_t best = groundTruth.size();
		double bestDt = maxTimeDifference;
		for (auto c : {it, it == groundTruth.begin() ? it : std::prev(it)})
		{
			if (c == groundTruth.end()) continue;
			const double dt = std::abs(c->timestamp - t);
			if (dt <= bestDt)
			{
				bestDt = dt;
				best = static_cast<std::size_t>(c - groundTruth.begin());
			}
		}
		if (best < groundTruth.size()) pairs.emplace_back(i, best);
	}
	return pairs;
}

mrpt::poses::CPose3D alignRigid(
	const std::vector<mrpt::math::TPoint3D>& src, const std::vector<mrpt::math::TPoint3D>& dst)
{
	if (src.size() != dst.size() || src.size() < 3)
		throw std::invalid_argument("alignRigid: needs at least 3 point pairs of equal count");
	Eigen::Matrix3Xd a(3, src.size()), b(3, dst.size());
	for (std::size_t i = 0; i < src.size(); ++i)
	{
		a.col(i) << src[i].x, src[i].y, src[i].z;
		b.col(i) << dst[i].x, dst[i].y, dst[i].z;
	}
	const Eigen::Matrix4d T = Eigen::umeyama(a, b, /*with_scaling=*/false);
	mrpt::math::CMatrixDouble44 m;
	for (int r = 0; r < 4; ++r)
		for (int c = 0; c < 4; ++c) m(r, c) = T(r, c);
	return mrpt::poses::CPose3D(m);
}

PoseError poseError(const mrpt::poses::CPose3D& estimate, const mrpt::poses::CPose3D& truth)
{
	const auto err = estimate - truth;
	const auto R = err.getRotationMatrix();
	const double c = std::clamp((R(0, 0) + R(1, 1) + R(2, 2) - 1.0) / 2.0, -1.0, 1.0);
	return {err.translation().norm(), mrpt::RAD2DEG(std::acos(c))};
}

ErrorStatistics statisticsOf(std::vector<double> errors)
{
	ErrorStatistics s;
	s.count = errors.size();
	if (errors.empty()) return s;
	double sq = 0, sum = 0;
	for (double e : errors)
	{
		sq += e * e;
		sum += e;
		s.max = std::max(s.max, e);
	}
	s.rmse = std::sqrt(sq / errors.size());
	s.mean = sum / errors.size();
	std::sort(errors.begin(), errors.end());
	const std::size_t n = errors.size();
	s.median = n % 2 ? errors[n / 2] : 0.5 * (errors[n / 2 - 1] + errors[n / 2]);
	return s;
}

std::vector<double> cameraAcceleration(const io::Trajectory& poses)
{
	constexpr double kMinStep = 1e-3;  // [s]
	const auto velocity = [&](std::size_t a, std::size_t b)
	{
		return (poses[b].pose.translation() - poses[a].pose.translation()) *
			   (1.0 / (poses[b].timestamp - poses[a].timestamp));
	};
	std::vector<double> out;
	std::optional<std::size_t> before;
	std::size_t at = 0;
	for (std::size_t next = 1; next < poses.size(); ++next)
	{
		if (poses[next].timestamp - poses[at].timestamp < kMinStep) continue;
		if (before)
		{
			const double halfSpan = 0.5 * (poses[next].timestamp - poses[*before].timestamp);
			out.push_back((velocity(at, next) - velocity(*before, at)).norm() / halfSpan);
		}
		before = at;
		at = next;
	}
	return out;
}

TrajectoryErrors evaluateTrajectory(
	const io::Trajectory& estimate, const io::Trajectory& groundTruth, const TEvaluationOptions& options)
{
	options.validate("evaluation");
	TrajectoryErrors out;
	const std::size_t first = std::min(options.firstFrame, estimate.size());
	const std::size_t last =
		options.maxFrames == 0 ? estimate.size() : std::min(estimate.size(), first + options.maxFrames);
	const auto range = io::inTimeOrder(io::Trajectory(estimate.begin() + first, estimate.begin() + last));
	out.evaluatedPoses = range.size();

	const auto truth = io::inTimeOrder(groundTruth);
	const auto pairs = associateByTimestamp(range, truth, options.maxTimeDifference);
	out.matchedPairs = pairs.size();
	if (pairs.size() < 3)
		throw std::runtime_error(
			"only " + std::to_string(pairs.size()) +
			" estimated poses match a ground-truth timestamp (need 3; check --max-dt and the time base)");

	// ATE, RPE and acceleration all read the matched poses, in pairs: the
	// estimate's k-th with the ground truth's k-th.
	io::Trajectory matchedEstimate, matchedTruth;
	std::vector<mrpt::math::TPoint3D> est, gt;
	for (const auto& [i, j] : pairs)
	{
		matchedEstimate.push_back(range[i]);
		matchedTruth.push_back(truth[j]);
		est.push_back(range[i].pose.translation());
		gt.push_back(truth[j].pose.translation());
	}
	out.alignment = alignRigid(est, gt);
	std::vector<double> ate;
	for (std::size_t k = 0; k < est.size(); ++k)
	{
		mrpt::math::TPoint3D aligned;
		out.alignment.composePoint(est[k], aligned);
		ate.push_back((aligned - gt[k]).norm());
	}
	out.ate = statisticsOf(std::move(ate));

	// RPE over pairs (k, l) with the first l whose time is >= t_k + delta; the
	// error is divided by the actual time step so it reads per second.
	std::vector<double> rpeT, rpeR;
	for (std::size_t k = 0, l = 0; k < matchedEstimate.size(); ++k)
	{
		const double tk = matchedEstimate[k].timestamp;
		l = std::max(l, k + 1);
		while (l < matchedEstimate.size() && matchedEstimate[l].timestamp < tk + options.rpeDelta) ++l;
		if (l >= matchedEstimate.size()) break;
		const double dt = matchedEstimate[l].timestamp - tk;
		const auto err =
			poseError(matchedEstimate[l].pose - matchedEstimate[k].pose, matchedTruth[l].pose - matchedTruth[k].pose);
		rpeT.push_back(err.metres / dt);
		rpeR.push_back(err.degrees / dt);
	}
	std::vector<double> stepErrors;
	for (std::size_t k = 1; k < matchedEstimate.size(); ++k)
		stepErrors.push_back(poseError(
			matchedEstimate[k].pose - matchedEstimate[k - 1].pose, matchedTruth[k].pose - matchedTruth[k - 1].pose)
								 .metres);
	out.frameToFrame = statisticsOf(std::move(stepErrors));
	out.rpeTranslation = statisticsOf(std::move(rpeT));
	out.rpeRotation = statisticsOf(std::move(rpeR));
	out.acceleration = statisticsOf(cameraAcceleration(matchedEstimate));
	out.groundTruthAcceleration = statisticsOf(cameraAcceleration(matchedTruth));
	return out;
}

std::string formatReport(const TrajectoryErrors& e)
{
	std::ostringstream s;
	s << std::fixed;
	const auto line = [&](const char* name, const ErrorStatistics& st, const char* unit, int precision)
	{
		s << std::setprecision(precision) << name << " rmse " << st.rmse << " mean " << st.mean << " median "
		  << st.median << " max " << st.max << " " << unit << " (" << st.count << ")\n";
	};
	s << "poses evaluated: " << e.evaluatedPoses << ", matched with ground truth: " << e.matchedPairs << "\n";
	line("ATE       ", e.ate, "m", 4);
	line("RPE trans ", e.rpeTranslation, "m/s", 4);
	line("RPE rot   ", e.rpeRotation, "deg/s", 3);
	line("step trans", e.frameToFrame, "m", 4);
	line("accel     ", e.acceleration, "m/s^2", 3);
	line("accel gt  ", e.groundTruthAcceleration, "m/s^2", 3);
	return s.str();
}
}  // namespace avm::evaluation

template struct avm::io::CIniKeyOptions<avm::evaluation::TEvaluationOptions>;
