#include "avm/odometry/VisualOdometry.h"

#include <mrpt/core/bits_math.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/CTimeLogger.h>

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdint>
#include <deque>
#include <stdexcept>

#include "avm/io/RgbdFrame.h"
#include "backend/CeresBackend.h"
#include "frontend/FeatureFrontend.h"

namespace avm::odometry
{
using namespace detail;

namespace
{
Eigen::Isometry3d toIsometry(const mrpt::poses::CPose3D& p)
{
	Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
	const auto& R = p.getRotationMatrix();
	for (int r = 0; r < 3; ++r)
	{
		for (int c = 0; c < 3; ++c) T.linear()(r, c) = R(r, c);
		T.translation()[r] = p.translation()[r];
	}
	return T;
}

mrpt::poses::CPose3D toPose(const Eigen::Isometry3d& T)
{
	mrpt::math::CMatrixDouble33 R;
	for (int r = 0; r < 3; ++r)
		for (int c = 0; c < 3; ++c) R(r, c) = T.linear()(r, c);
	const Eigen::Vector3d t = T.translation();
	return mrpt::poses::CPose3D(R, mrpt::math::CVectorFixedDouble<3>({t.x(), t.y(), t.z()}));
}

/** Checked before the front end builds its detector from them. */
const TOdometryOptions& validated(const TOdometryOptions& o)
{
	o.validate();
	return o;
}

double rotationAngleDeg(const Eigen::Matrix3d& R) { return mrpt::RAD2DEG(Eigen::AngleAxisd(R).angle()); }

// --- the saveState stream: raw little-endian values, doubles bit-exact.
/** Layout version of the stream; change it with the layout. */
constexpr std::uint8_t stateVersion = 1;

std::runtime_error badState(const std::string& why) { return std::runtime_error("VisualOdometry::loadState: " + why); }

template <typename T>
void write(mrpt::serialization::CArchive& out, const T* values, std::size_t n)
{
	out.WriteBufferFixEndianness(values, n);
}

/** Reads n values. MRPT throws when no byte is left but returns a short
 *  count when only some are: both are a truncated stream. */
template <typename T>
void read(mrpt::serialization::CArchive& in, T* values, std::size_t n)
{
	std::size_t bytes = 0;
	try
	{
		bytes = in.ReadBufferFixEndianness(values, n);
	}
	catch (const std::exception&)
	{
	}
	if (bytes != n * sizeof(T)) throw badState("truncated odometry state (the stream ends early)");
}

template <typename T>
T read(mrpt::serialization::CArchive& in)
{
	T value;
	read(in, &value, 1);
	return value;
}

void writePose(mrpt::serialization::CArchive& out, const Eigen::Isometry3d& T) { write(out, T.matrix().data(), 16); }

Eigen::Isometry3d readPose(mrpt::serialization::CArchive& in)
{
	Eigen::Isometry3d T;
	read(in, T.matrix().data(), 16);
	if (!T.matrix().allFinite()) throw badState("corrupt odometry state (a pose is not finite)");
	return T;
}
}  // namespace

struct VisualOdometry::Impl
{
	explicit Impl(const TOdometryOptions& o, const mrpt::poses::CPose3D& initial)
		: options(validated(o)), frontend(options), backend(options), T_cw(toIsometry(initial).inverse())
	{
		if (!io::isFinite(initial)) throw std::invalid_argument("VisualOdometry: the initial pose is not finite");
	}
	// CTimeLogger prints its table when destroyed with data; the owner asks for it instead.
	~Impl() { stageTimer.clear(true); }
	Impl(const Impl&) = delete;
	Impl& operator=(const Impl&) = delete;

	TOdometryOptions options;
	FeatureFrontend frontend;
	CeresBackend backend;
	Eigen::Isometry3d T_cw;  //!< latest pose (world -> camera)
	/** Camera motion of the last frame, T_cw(k) * T_cw(k-1)^-1, for the prediction. */
	Eigen::Isometry3d velocity = Eigen::Isometry3d::Identity();
	LandmarkMap landmarks;
	std::deque<Keyframe> window;
	int nextLandmarkId = 0;
	mrpt::system::CTimeLogger stageTimer{true, "avm odometry stages"};
	bool reportFeatures = false;
	std::vector<cv::Point2f> lastFeatures, lastMaskedFeatures;  // when reportFeatures

	OdometryEstimate process(const mrpt::obs::CObservation3DRangeScan& obs, const std::vector<cv::Rect>& boxes);
	/** A keyframe at T from the frame's matched inliers and new landmarks for
	 *  the unmatched features; runs the window bundle adjustment. */
	void addKeyframe(const FrameFeatures& f, const std::vector<Match>& inliers, const Eigen::Isometry3d& T);
	void forgetUnobservedLandmarks();
	OdometryEstimate lost(const FrameFeatures& f, const std::string& why);
	void saveState(mrpt::serialization::CArchive& out) const;
	void loadState(mrpt::serialization::CArchive& in);
};

OdometryEstimate VisualOdometry::Impl::lost(const FrameFeatures& f, const std::string& why)
{
	OdometryEstimate e;
	T_cw = velocity * T_cw;  // bridged by the constant-velocity model
	e.status = "lost: " + why + "; pose bridged by the motion model";
	// Start a new local map here when the frame can carry one, so the next
	// frame tracks again; otherwise keep the old map and try again next frame.
	if (int(f.keypoints.size()) >= options.min_inliers)
	{
		window.clear();
		landmarks.clear();
		addKeyframe(f, {}, T_cw);
		e.keyframe = true;
		e.status += "; re-initialised";
	}
	e.pose = toPose(T_cw.inverse());
	return e;
}

OdometryEstimate VisualOdometry::Impl::process(
	const mrpt::obs::CObservation3DRangeScan& obs, const std::vector<cv::Rect>& boxes)
{
	if (!obs.hasRangeImage) throw std::invalid_argument("VisualOdometry: observation without a range image");
	cv::Mat grey;
	cv::cvtColor(io::colourImage(obs), grey, cv::COLOR_BGR2GRAY);
	const cv::Mat depth = io::depthInMetres(obs);
	if (depth.size() != grey.size())
		throw std::invalid_argument("VisualOdometry: depth and colour images differ in size (not registered)");
	const Intrinsics K{obs.cameraParams.fx(), obs.cameraParams.fy(), obs.cameraParams.cx(), obs.cameraParams.cy()};

	const auto f = [&] {
		mrpt::system::CTimeLoggerEntry t(stageTimer, "1 features");
		return frontend.extract(grey, depth, K, options.mask_people ? boxes : std::vector<cv::Rect>{});
	}();
	if (reportFeatures)
	{
		cv::KeyPoint::convert(f.keypoints, lastFeatures);
		cv::KeyPoint::convert(
			frontend.maskedKeypoints(grey, depth, options.mask_people ? boxes : std::vector<cv::Rect>{}),
			lastMaskedFeatures);
	}
	if (window.empty())
	{
		if (int(f.keypoints.size()) < options.min_inliers)
		{
			OdometryEstimate e;
			e.pose = toPose(T_cw.inverse());
			e.status = "lost: not initialised, " + std::to_string(f.keypoints.size()) + " features with depth";
			return e;
		}
		addKeyframe(f, {}, T_cw);
		OdometryEstimate e;
		e.pose = toPose(T_cw.inverse());
		e.tracked = e.keyframe = true;
		e.status = "initialised";
		return e;
	}
	if (int(f.keypoints.size()) < options.min_inliers)
		return lost(f, std::to_string(f.keypoints.size()) + " features with depth (no depth or no texture)");

	const Eigen::Isometry3d predicted = velocity * T_cw;
	mrpt::system::CTimeLoggerEntry matchTimer(stageTimer, "2 matching + PnP");
	auto matches = frontend.matchByProjection(f, landmarks, predicted);
	auto pnp = frontend.solvePnp(f, landmarks, matches, predicted);
	if (!pnp)
	{
		matches = frontend.matchByDescriptor(f, landmarks);
		pnp = frontend.solvePnp(f, landmarks, matches, T_cw);
	}
	matchTimer.stop();
	if (!pnp) return lost(f, std::to_string(matches.size()) + " matches, PnP found no consistent pose");

	Eigen::Isometry3d T = pnp->T_cw;
	const auto observationsOf = [&](const std::vector<Match>& ms) {
		std::vector<Observation> obsList;
		for (const auto& m : ms)
			obsList.push_back(
				{m.landmark, Eigen::Vector2d(f.keypoints[m.feature].pt.x, f.keypoints[m.feature].pt.y),
				 f.points[m.feature].z()});
		return obsList;
	};
	{
		mrpt::system::CTimeLoggerEntry t(stageTimer, "3 pose refinement");
		backend.refinePose(T, observationsOf(pnp->inliers), landmarks, K);
	}

	// Inliers at the refined pose among all matches.
	std::vector<Match> inliers;
	double sq = 0;
	for (const auto& m : matches)
	{
		const double err = reprojectionError(
			T, landmarks.at(m.landmark).position,
			Eigen::Vector2d(f.keypoints[m.feature].pt.x, f.keypoints[m.feature].pt.y), K);
		if (err > options.ransac_reprojection) continue;
		inliers.push_back(m);
		sq += err * err;
	}
	if (int(inliers.size()) < options.min_inliers || !T.matrix().allFinite())
		return lost(f, std::to_string(inliers.size()) + " inliers after refinement");

	OdometryEstimate e;
	e.tracked = true;
	e.inliers = inliers.size();
	e.reprojectionRmse = std::sqrt(sq / inliers.size());
	e.status = "tracking";

	// Keyframe when the camera moved or turned enough, or sees too little of
	// the last keyframe's landmarks.
	// Overlap: inliers relative to the most the last keyframe's map gave any frame.
	auto& last = window.back();
	const Eigen::Isometry3d rel = T * last.T_cw.inverse();
	last.bestInliers = std::max(last.bestInliers, inliers.size());
	const double overlap = double(inliers.size()) / double(last.bestInliers);
	const Eigen::Isometry3d previous = T_cw;
	if (rel.translation().norm() > options.keyframe_translation ||
		rotationAngleDeg(rel.rotation()) > options.keyframe_rotation || overlap < options.keyframe_overlap)
	{
		addKeyframe(f, inliers, T);
		T = window.back().T_cw;  // as the bundle adjustment left it
		e.keyframe = true;
	}
	velocity = T * previous.inverse();
	T_cw = T;
	e.pose = toPose(T_cw.inverse());
	return e;
}

void VisualOdometry::Impl::addKeyframe(const FrameFeatures& f, const std::vector<Match>& inliers, const Eigen::Isometry3d& T)
{
	Keyframe kf;
	kf.T_cw = T;
	std::vector<bool> matched(f.keypoints.size(), false);
	for (const auto& m : inliers)
	{
		matched[m.feature] = true;
		landmarks.at(m.landmark).descriptor = f.descriptor(m.feature);
		kf.observations.push_back(
			{m.landmark, Eigen::Vector2d(f.keypoints[m.feature].pt.x, f.keypoints[m.feature].pt.y),
			 f.points[m.feature].z()});
	}
	const Eigen::Isometry3d T_wc = T.inverse();
	for (std::size_t i = 0; i < f.keypoints.size(); ++i)
	{
		if (matched[i]) continue;
		const int id = nextLandmarkId++;
		landmarks[id] = Landmark{T_wc * f.points[i], f.descriptor(int(i))};
		kf.observations.push_back(
			{id, Eigen::Vector2d(f.keypoints[i].pt.x, f.keypoints[i].pt.y), f.points[i].z()});
	}
	window.push_back(std::move(kf));
	while (window.size() > std::size_t(std::max(1, options.window_size))) window.pop_front();
	forgetUnobservedLandmarks();
	if (options.window_size >= 2)
	{
		mrpt::system::CTimeLoggerEntry t(stageTimer, "4 window bundle adjustment");
		backend.bundleAdjust(window, landmarks, f.K);
	}
}

void VisualOdometry::Impl::forgetUnobservedLandmarks()
{
	std::unordered_map<int, bool> seen;
	for (const auto& kf : window)
		for (const auto& o : kf.observations) seen[o.landmark] = true;
	for (auto it = landmarks.begin(); it != landmarks.end();)
		it = seen.count(it->first) ? std::next(it) : landmarks.erase(it);
}

void VisualOdometry::Impl::saveState(mrpt::serialization::CArchive& out) const
{
	out << stateVersion;
	writePose(out, T_cw);
	writePose(out, velocity);
	out << std::int32_t(nextLandmarkId);
	// In id order, so that one state always gives the same bytes.
	std::vector<int> ids;
	ids.reserve(landmarks.size());
	for (const auto& [id, lm] : landmarks) ids.push_back(id);
	std::sort(ids.begin(), ids.end());
	out << std::uint32_t(ids.size());
	for (const int id : ids)
	{
		const Landmark& lm = landmarks.at(id);
		out << std::int32_t(id);
		write(out, lm.position.data(), 3);
		write(out, lm.descriptor.data(), lm.descriptor.size());
	}
	out << std::uint32_t(window.size());
	for (const auto& kf : window)
	{
		writePose(out, kf.T_cw);
		out << std::uint64_t(kf.bestInliers) << std::uint32_t(kf.observations.size());
		for (const auto& o : kf.observations)
		{
			out << std::int32_t(o.landmark);
			write(out, o.pixel.data(), 2);
			out << o.depth;
		}
	}
}

void VisualOdometry::Impl::loadState(mrpt::serialization::CArchive& in)
{
	// Everything is read and checked before any of it replaces the state.
	if (const auto version = read<std::uint8_t>(in); version != stateVersion)
		throw badState(
			"odometry state of version " + std::to_string(version) + ", this build reads version " +
			std::to_string(stateVersion));
	const Eigen::Isometry3d pose = readPose(in), motion = readPose(in);
	const int nextId = read<std::int32_t>(in);
	LandmarkMap map;
	for (auto n = read<std::uint32_t>(in); n > 0; --n)
	{
		const int id = read<std::int32_t>(in);
		Landmark lm;
		read(in, lm.position.data(), 3);
		read(in, lm.descriptor.data(), lm.descriptor.size());
		if (id < 0 || id >= nextId || !lm.position.allFinite() || !map.emplace(id, lm).second)
			throw badState("corrupt odometry state (landmark " + std::to_string(id) + ")");
	}
	std::deque<Keyframe> keyframes;
	for (auto n = read<std::uint32_t>(in); n > 0; --n)
	{
		Keyframe& kf = keyframes.emplace_back();
		kf.T_cw = readPose(in);
		kf.bestInliers = read<std::uint64_t>(in);
		for (auto m = read<std::uint32_t>(in); m > 0; --m)
		{
			Observation& o = kf.observations.emplace_back();
			o.landmark = read<std::int32_t>(in);
			read(in, o.pixel.data(), 2);
			o.depth = read<double>(in);
			if (!map.count(o.landmark))
				throw badState(
					"corrupt odometry state (a keyframe observes the unknown landmark " + std::to_string(o.landmark) +
					")");
		}
	}
	T_cw = pose;
	velocity = motion;
	nextLandmarkId = nextId;
	landmarks = std::move(map);
	window = std::move(keyframes);
}

VisualOdometry::VisualOdometry(const TOdometryOptions& options, const mrpt::poses::CPose3D& initialPose)
	: m_impl(std::make_unique<Impl>(options, initialPose))
{
}
VisualOdometry::~VisualOdometry() = default;
VisualOdometry::VisualOdometry(VisualOdometry&&) noexcept = default;
VisualOdometry& VisualOdometry::operator=(VisualOdometry&&) noexcept = default;

OdometryEstimate VisualOdometry::process(
	const mrpt::obs::CObservation3DRangeScan& obs, const std::vector<cv::Rect>& personBoxes)
{
	auto e = m_impl->process(obs, personBoxes);
	if (m_impl->reportFeatures)
	{
		e.features = std::move(m_impl->lastFeatures);
		e.maskedFeatures = std::move(m_impl->lastMaskedFeatures);
	}
	return e;
}
void VisualOdometry::reportFeatures(bool on) { m_impl->reportFeatures = on; }
void VisualOdometry::saveState(mrpt::serialization::CArchive& out) const { m_impl->saveState(out); }
void VisualOdometry::loadState(mrpt::serialization::CArchive& in) { m_impl->loadState(in); }
const TOdometryOptions& VisualOdometry::options() const { return m_impl->options; }
std::size_t VisualOdometry::keyframeCount() const { return m_impl->window.size(); }
std::size_t VisualOdometry::landmarkCount() const { return m_impl->landmarks.size(); }
std::string VisualOdometry::stageTimesText() const { return m_impl->stageTimer.getStatsAsText(); }
}  // namespace avm::odometry
