// The pose graph of loop closing on synthetic chains: a loop's correction is
// spread along the path that drifted, a consistent graph stays where it is,
// and the anchor holds.
#include <gtest/gtest.h>

#include "CameraCentre.h"
#include "backend/PoseGraph.h"

using namespace avm::odometry::detail;
using avm::test::centreOf;

namespace
{
/** T_cw of a camera at (x, 0, 0) looking along the world's x axis, turned by yaw [rad]. */
Eigen::Isometry3d cameraAt(double x, double yaw = 0)
{
	Eigen::Isometry3d T_wc = Eigen::Isometry3d::Identity();
	T_wc.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
	T_wc.translation() = Eigen::Vector3d(x, 0, 0);
	return T_wc.inverse();
}

PoseGraphEdge edge(int from, int to, const std::map<int, Eigen::Isometry3d>& poses, double sigma, bool robust = false)
{
	PoseGraphEdge e;
	e.from = from;
	e.to = to;
	e.T_to_from = poses.at(to) * poses.at(from).inverse();
	e.sigmaTranslation = e.sigmaRotation = sigma;
	e.robust = robust;
	return e;
}
}  // namespace

TEST(PoseGraph, ALoopSpreadsTheDriftAlongTheChain)
{
	// Ten cameras 1 m apart; the odometry measured 1.01 m steps (1 % drift),
	// a loop from the first to the last says 9 m.
	std::map<int, Eigen::Isometry3d> drifted, truth;
	for (int i = 0; i < 10; ++i)
	{
		drifted[i] = cameraAt(1.01 * i, 0.002 * i);
		truth[i] = cameraAt(1.0 * i);
	}
	std::vector<PoseGraphEdge> edges;
	for (int i = 0; i + 1 < 10; ++i) edges.push_back(edge(i, i + 1, drifted, 0.01));
	edges.push_back(edge(0, 9, truth, 0.001, true));
	const auto result = optimisePoseGraph(drifted, edges, 0, 50);
	ASSERT_TRUE(result.usable);
	EXPECT_LT(result.finalCost, result.initialCost);
	EXPECT_NEAR((centreOf(result.poses.at(9)) - centreOf(truth.at(9))).norm(), 0, 0.002);
	EXPECT_EQ(result.poses.at(0).matrix(), drifted.at(0).matrix()) << "the anchor moved";
	// Each step takes its share: none keeps the whole error.
	for (int i = 0; i + 1 < 10; ++i)
	{
		const double step = (centreOf(result.poses.at(i + 1)) - centreOf(result.poses.at(i))).norm();
		EXPECT_NEAR(step, 1.0, 0.002) << "step " << i;
	}
}

TEST(PoseGraph, AConsistentGraphStaysWhereItIs)
{
	std::map<int, Eigen::Isometry3d> poses;
	for (int i = 0; i < 6; ++i) poses[i] = cameraAt(0.3 * i, 0.1 * i);
	std::vector<PoseGraphEdge> edges;
	for (int i = 0; i + 1 < 6; ++i) edges.push_back(edge(i, i + 1, poses, 0.01));
	edges.push_back(edge(1, 5, poses, 0.02, true));
	PoseGraphEdge missing = edges.front();
	missing.to = 42;  // a keyframe no longer in the map: left out
	edges.push_back(missing);
	const auto result = optimisePoseGraph(poses, edges, 0, 20);
	ASSERT_TRUE(result.usable);
	for (const auto& [id, T] : poses)
		EXPECT_LT((result.poses.at(id).matrix() - T.matrix()).cwiseAbs().maxCoeff(), 1e-9) << "node " << id;
}
