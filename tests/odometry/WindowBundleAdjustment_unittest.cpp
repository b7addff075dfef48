// What holds the window bundle adjustment in place, on a synthetic scene:
// three keyframes 10 cm apart that see the same 300 points exactly. After a
// loop, the place's points the newest keyframe matched are anchored (held
// where the keyframe map has them). A few of them do not fix a pose, and the
// window then turned about them (on the whole Bonn sequence it ran away by up
// to 15 cm a keyframe after a loop): the oldest pose holds it unless some
// keyframe sees as many anchored points as a tracked pose needs.
#include <gtest/gtest.h>

#include "CameraCentre.h"
#include "backend/CeresBackend.h"

using namespace avm::odometry;
using namespace avm::odometry::detail;
using avm::test::centreOf;

namespace
{
const avm::io::DepthCamera kCamera{542.8, 542.6, 315.6, 237.8, 640, 480, true};
constexpr int kKeyframes = 3;

/** T_cw of an optical camera (z forward) whose centre is at (x, 0, 0). */
Eigen::Isometry3d opticalCameraAt(double x)
{
	Eigen::Isometry3d T_wc = Eigen::Isometry3d::Identity();
	T_wc.translation() = Eigen::Vector3d(x, 0, 0);
	return T_wc.inverse();
}

struct Scene
{
	std::deque<Keyframe> window;
	std::vector<Eigen::Isometry3d> truth;
	LandmarkMap landmarks;
	int nextId = 0;

	Scene()
	{
		for (int k = 0; k < kKeyframes; ++k)
		{
			window.push_back(Keyframe{k, {}, 0});
			truth.push_back(opticalCameraAt(0.1 * k));
		}
		// A wall 2-3 m away, seen whole by every keyframe.
		for (int i = 0; i < 20; ++i)
			for (int j = 0; j < 15; ++j)
			{
				const Eigen::Vector3d p(-0.9 + 0.1 * i, -0.6 + 0.08 * j, 2.0 + 0.05 * ((i + j) % 20));
				const int id = addLandmark(p, false);
				for (auto& kf : window) observe(kf, id, p);
			}
	}

	int addLandmark(const Eigen::Vector3d& held, bool anchored)
	{
		const int id = nextId++;
		landmarks[id] = Landmark{held, {}, anchored};
		return id;
	}

	void observe(Keyframe& kf, int id, const Eigen::Vector3d& seen) const
	{
		const Eigen::Vector3d pc = truth[std::size_t(kf.id)] * seen;
		kf.observations.push_back(Observation{id, int(kf.observations.size()), kCamera.opticalPixelOf(pc), pc.z()});
	}

	/** `count` points the newest keyframe sees where they are, anchored `offset` away from there. */
	void anchorPlace(int count, const Eigen::Vector3d& offset)
	{
		for (int i = 0; i < count; ++i)
		{
			const Eigen::Vector3d seen(-0.5 + 0.05 * i, 0.3 - 0.1 * (i % 4), 2.5 + 0.1 * (i % 3));
			observe(window.back(), addLandmark(seen + offset, true), seen);
		}
	}
};
}  // namespace

TEST(WindowBundleAdjustment, AFewAnchoredPointsLeaveTheOldestPoseHoldingTheWindow)
{
	// Five points of a joined place 5 cm from where the window sees them:
	// moving the whole window 5 cm would fit them exactly.
	Scene scene;
	scene.anchorPlace(5, Eigen::Vector3d(0.05, 0, 0));
	TOdometryOptions options;
	ASSERT_GT(options.min_inliers, 5);
	std::vector<Eigen::Isometry3d> poses = scene.truth;
	CeresBackend(options).bundleAdjust(scene.window, poses, scene.landmarks, kCamera);
	EXPECT_LT((centreOf(poses.front()) - centreOf(scene.truth.front())).norm(), 1e-9);
	for (int k = 1; k < kKeyframes; ++k)
		EXPECT_LT((centreOf(poses[std::size_t(k)]) - centreOf(scene.truth[std::size_t(k)])).norm(), 0.01) << k;
}

TEST(WindowBundleAdjustment, AsManyAnchoredPointsAsAPoseNeedsHoldTheWindowWhereThePlaceIs)
{
	// The window drifted 3 cm from the place its newest keyframe sees again:
	// the place's points bring every pose back, the oldest too.
	Scene scene;
	TOdometryOptions options;
	scene.anchorPlace(options.min_inliers, Eigen::Vector3d::Zero());
	std::vector<Eigen::Isometry3d> poses;
	Eigen::Isometry3d drift = Eigen::Isometry3d::Identity();
	drift.translation() = Eigen::Vector3d(0, 0.03, 0);
	for (const auto& T : scene.truth) poses.push_back(T * drift);
	for (auto& [id, lm] : scene.landmarks)
		if (!lm.anchored) lm.position = drift.inverse() * lm.position;
	options.ba_iterations = 20;
	CeresBackend(options).bundleAdjust(scene.window, poses, scene.landmarks, kCamera);
	for (int k = 0; k < kKeyframes; ++k)
		EXPECT_LT((centreOf(poses[std::size_t(k)]) - centreOf(scene.truth[std::size_t(k)])).norm(), 0.002) << k;
}
