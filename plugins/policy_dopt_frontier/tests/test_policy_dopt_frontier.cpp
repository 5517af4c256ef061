// dopt_frontier: the expected pose graph against a graph built by hand and the dense
// eigenvalues (graph/information.h), the nodes placed along a path, and the policy on a
// corridor, where it goes back to close loops while the nearest-frontier explorer does not.
#include <asf/errors.h>
#include <asf/exploration/expected_pose_graph.h>
#include <asf/graph/information.h>
#include <asf/policy.h>
#include <asf/framework/registry.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <cmath>
#include <map>

namespace {

constexpr double kRes = 0.05;
constexpr float kFree = 0.95f, kOccupied = 0.05f, kUnknown = 0.5f;  // p(free), MRPT
using Grid = mrpt::maps::COccupancyGridMap2D;
using Type = asf::Decision::Type;

asf::PoseEdge edge(asf::NodeId a, asf::NodeId b, const Eigen::Matrix3d& info,
                   asf::EdgeKind kind = asf::EdgeKind::ScanMatch) {
  asf::PoseEdge e;
  e.from = a;
  e.to = b;
  e.information = info;
  e.kind = kind;
  return e;
}

/// Nodes along y = 0 from x0 every `step` metres, consecutive ones joined with `info`.
asf::PoseGraph chain(int n, double x0, double step, const Eigen::Matrix3d& info, double y = 0) {
  asf::PoseGraph g;
  for (int i = 0; i < n; ++i) g.addNode(mrpt::poses::CPose2D(x0 + i * step, y, 0));
  for (int i = 0; i + 1 < n; ++i) g.addEdge(edge(i, i + 1, info));
  return g;
}

TEST(ExpectedPoseGraph, EdgeWeightIsTheGeometricMeanOfTheInformationsEigenvalues) {
  EXPECT_NEAR(asf::exploration::edgeDOptimality(Eigen::Vector3d(4, 9, 1).asDiagonal()),
              std::cbrt(36.0), 1e-12);
  // Invariant to a rotation of the frame.
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  R.topLeftCorner<2, 2>() << std::cos(0.7), -std::sin(0.7), std::sin(0.7), std::cos(0.7);
  const Eigen::Matrix3d info = R * Eigen::Vector3d(4, 9, 1).asDiagonal() * R.transpose();
  EXPECT_NEAR(asf::exploration::edgeDOptimality(info), std::cbrt(36.0), 1e-12);
  EXPECT_EQ(asf::exploration::edgeDOptimality(Eigen::Vector3d(4, 0, 1).asDiagonal()), 0.0);
  EXPECT_EQ(asf::exploration::edgeDOptimality(Eigen::Vector3d(4, -1, 1).asDiagonal()), 0.0);
}

TEST(ExpectedPoseGraph, EqualsTheGraphBuiltByHandAndItsDenseSpectrum) {
  const Eigen::Matrix3d odo = Eigen::Vector3d(4, 9, 1).asDiagonal();
  asf::PoseGraph g = chain(5, 0, 0.5, odo);  // x = 0, 0.5, ..., 2
  g.addEdge(edge(0, 4, 8 * Eigen::Matrix3d::Identity(), asf::EdgeKind::LoopClosure));
  asf::exploration::ExpectedGraphOptions o;
  o.node_spacing = 0.5;
  o.loop_radius = 1.15;
  o.loop_skip_recent = 2;
  const asf::exploration::ExpectedPoseGraph expected(g, o);
  const double w = std::cbrt(36.0);
  EXPECT_NEAR(expected.odometryWeight(), w, 1e-12);
  EXPECT_NEAR(expected.loopWeight(), 8, 1e-12);

  // Up from the newest node (2, 0): new nodes 5 (2, 0.5), 6 (2, 1.0) and 7 (2, 1.2). Node 5
  // may close a loop with nodes 0..2, the nearest within 1.15 m being node 2 (1.118 m); node 6
  // with 0..3: node 3 (1.118 m); node 7 with 0..4: none within 1.15 m (node 4: 1.2 m).
  const asf::exploration::Expectation e = expected.afterPath({{2, 0}, {2, 0.7}, {2, 1.2}});
  EXPECT_EQ(e.nodes, 3);
  EXPECT_EQ(e.loops, 2);
  asf::graph::Multigraph hand;
  hand.n = 8;
  for (int i = 0; i < 4; ++i) hand.edges.push_back({i, i + 1, 1, w});
  hand.edges.push_back({0, 4, 1, 8});
  hand.edges.push_back({4, 5, 1, w});
  hand.edges.push_back({5, 6, 1, w});
  hand.edges.push_back({6, 7, 1, w});
  hand.edges.push_back({2, 5, 1, 8});
  hand.edges.push_back({3, 6, 1, 8});
  const double dense =
      asf::graph::information(hand, Eigen::VectorXd::Ones(hand.m()), asf::graph::kCriterionD).value;
  EXPECT_NEAR(e.d_optimality, dense, 1e-9 * dense);
  // The present graph alone.
  asf::graph::Multigraph now = hand;
  now.n = 5;
  now.edges.resize(5);
  EXPECT_NEAR(expected.present(),
              asf::graph::information(now, Eigen::VectorXd::Ones(5), asf::graph::kCriterionD).value,
              1e-9);
}

TEST(ExpectedPoseGraph, TheAuthorsScalingByTheMapAroundEachExpectedNode) {
  const Eigen::Matrix3d odo = Eigen::Vector3d(4, 9, 1).asDiagonal();
  asf::PoseGraph g = chain(5, 0, 0.5, odo);
  g.addEdge(edge(0, 4, 8 * Eigen::Matrix3d::Identity(), asf::EdgeKind::LoopClosure));
  asf::exploration::ExpectedGraphOptions o;
  o.node_spacing = 0.5;
  o.loop_radius = 1.15;
  o.loop_skip_recent = 2;
  const asf::exploration::ExpectedPoseGraph expected(g, o);
  const std::vector<asf::Point2> path{{2, 0}, {2, 0.7}, {2, 1.2}};
  const double w = std::cbrt(36.0);
  // Half unknown, a fifth occupied around every node: odometry x 1.5; the loops 2-5 and 3-6
  // x 1.5 x age x 0.2, the age being (new id - old id) / nodes of the graph then.
  const asf::exploration::Expectation e = expected.afterPath(path, [](const asf::Point2&) {
    return asf::exploration::AreaShares{0.5, 0.2};
  });
  EXPECT_EQ(e.loops, 2);
  asf::graph::Multigraph hand;
  hand.n = 8;
  for (int i = 0; i < 4; ++i) hand.edges.push_back({i, i + 1, 1, w});
  hand.edges.push_back({0, 4, 1, 8});
  hand.edges.push_back({4, 5, 1, 1.5 * w});
  hand.edges.push_back({2, 5, 1, 8 * 1.5 * (5 - 2) / 6.0 * 0.2});
  hand.edges.push_back({5, 6, 1, 1.5 * w});
  hand.edges.push_back({3, 6, 1, 8 * 1.5 * (6 - 3) / 7.0 * 0.2});
  hand.edges.push_back({6, 7, 1, 1.5 * w});
  const double dense =
      asf::graph::information(hand, Eigen::VectorXd::Ones(hand.m()), asf::graph::kCriterionD).value;
  EXPECT_NEAR(e.d_optimality, dense, 1e-9 * dense);
  // Nothing to match (3 % occupied or less): no loop expected.
  const asf::exploration::Expectation bare = expected.afterPath(path, [](const asf::Point2&) {
    return asf::exploration::AreaShares{0.5, 0.03};
  });
  EXPECT_EQ(bare.loops, 0);
  EXPECT_LT(bare.d_optimality, e.d_optimality);
}

TEST(ExpectedPoseGraph, NodesEveryNodeSpacingAndOneAtTheEnd) {
  const asf::PoseGraph g = chain(3, 0, 0.5, Eigen::Matrix3d::Identity());
  asf::exploration::ExpectedGraphOptions o;
  o.node_spacing = 0.5;
  o.loop_radius = 0.1;
  const asf::exploration::ExpectedPoseGraph expected(g, o);
  EXPECT_EQ(expected.afterPath({{1, 0}, {2, 0}}).nodes, 2);  // at 0.5 and 1.0: no duplicate
  EXPECT_EQ(expected.afterPath({{1, 0}, {2.2, 0}}).nodes, 3);
  EXPECT_EQ(expected.afterPath({{1, 0}, {1.1, 0}, {1.2, 0}, {1.3, 0}}).nodes, 1);
  EXPECT_EQ(expected.afterPath({{1, 0}}).nodes, 0);
  EXPECT_EQ(expected.afterPath({}).nodes, 0);
  // A chain only gets longer: its normalised spanning-tree weight w n^(1/(n-1)) falls.
  EXPECT_LT(expected.afterPath({{1, 0}, {3, 0}}).d_optimality, expected.present());
  EXPECT_NEAR(expected.present(), std::pow(3.0, 0.5), 1e-12);
  EXPECT_THROW(asf::exploration::ExpectedPoseGraph(asf::PoseGraph{}, o), asf::InputError);
}

// ---- the policy ------------------------------------------------------------------------

std::shared_ptr<const asf::framework::PluginInfo> info(const std::string& file) {
  return asf::framework::Registry::loadFile(std::string(ASF_TEST_PLUGIN_DIR "/") + file);
}

asf::framework::PluginHandle<asf::Policy> make(const std::string& file, const std::string& name) {
  const auto i = info(file);
  auto h = asf::framework::Registry::create<asf::Policy>(i);
  h->configure(asf::Params::fromSpecs(name, i->descriptor->keys, i->descriptor->num_keys, {}),
               asf::PluginContext{});
  return h;
}

void fill(Grid& g, double x0, double y0, double x1, double y1, float p_free) {
  for (unsigned cy = 0; cy < g.getSizeY(); ++cy)
    for (unsigned cx = 0; cx < g.getSizeX(); ++cx) {
      const double x = g.idx2x(cx), y = g.idx2y(cy);
      if (x >= x0 && x <= x1 && y >= y0 && y <= y1) g.setCell(cx, cy, p_free);
    }
}

/// A corridor [0, 10] x [0, 2] driven from x = 1 to x = 8.5 (31 keyframes 0.25 m apart),
/// unknown at both ends: the left frontier is 7.9 m back along the keyframes, the right one
/// 0.8 m ahead.
struct Corridor {
  asf::TopoGraph topo;
  asf::GridMap map;
  asf::PoseGraph graph = chain(31, 1.0, 0.25, Eigen::Vector3d(400, 400, 100).asDiagonal(), 1.0);
  asf::ExplorationState s;
  Corridor() {
    auto g = std::make_shared<Grid>(0.0f, 10.0f, 0.0f, 2.0f, static_cast<float>(kRes));
    fill(*g, 0, 0, 10, 2, kOccupied);
    fill(*g, 0.1, 0.1, 9.9, 1.9, kFree);
    fill(*g, 0.1, 0.1, 0.6, 1.9, kUnknown);
    fill(*g, 9.3, 0.1, 9.9, 1.9, kUnknown);
    map.grid = g;
    map.version = 1;
    s.topo = &topo;
    s.map = &map;
    s.graph = &graph;
    s.robot = mrpt::poses::CPose2D(8.5, 1.0, 0);
  }
};

TEST(PolicyDOptFrontier, GoesBackAlongItsKeyframesToCloseLoopsWhereFrontierGoesAhead) {
  Corridor c;
  const asf::Decision nearest = make("policy_frontier.so", "frontier")->decide(c.s);
  ASSERT_EQ(nearest.type, Type::GoTo) << nearest.reason;
  EXPECT_GT(nearest.goal.x, 9) << nearest.reason;

  const asf::Decision dopt = make("policy_dopt_frontier.so", "dopt_frontier")->decide(c.s);
  ASSERT_EQ(dopt.type, Type::GoTo) << dopt.reason;
  EXPECT_LT(dopt.goal.x, 1) << dopt.reason;
  EXPECT_NE(dopt.reason.find("D-optimal of 2 frontiers"), std::string::npos) << dopt.reason;
  EXPECT_EQ(dopt.reason.find(" 0 loops expected"), std::string::npos) << dopt.reason;

  // Without loop closures to expect, the longer way only lengthens a chain: ahead it goes.
  auto p = make("policy_dopt_frontier.so", "dopt_frontier");
  const auto i = info("policy_dopt_frontier.so");
  p->configure(asf::Params::fromSpecs("dopt_frontier", i->descriptor->keys, i->descriptor->num_keys,
                                      {{"loop_radius", "0"}}),
               asf::PluginContext{});
  const asf::Decision no_loops = p->decide(c.s);
  ASSERT_EQ(no_loops.type, Type::GoTo) << no_loops.reason;
  EXPECT_GT(no_loops.goal.x, 9) << no_loops.reason;
  EXPECT_NE(no_loops.reason.find(" 0 loops expected"), std::string::npos) << no_loops.reason;
}

TEST(PolicyDOptFrontier, WithoutAPoseGraphTheNearestFrontierIsTaken) {
  Corridor c;
  c.s.graph = nullptr;
  const asf::Decision d = make("policy_dopt_frontier.so", "dopt_frontier")->decide(c.s);
  ASSERT_EQ(d.type, Type::GoTo) << d.reason;
  EXPECT_GT(d.goal.x, 9) << d.reason;
  EXPECT_NE(d.reason.find("no pose graph yet"), std::string::npos) << d.reason;
}

TEST(PolicyDOptFrontier, DoneWhenNoFrontierIsLeft) {
  Corridor c;
  fill(*std::const_pointer_cast<Grid>(c.map.grid), 0.1, 0.1, 9.9, 1.9, kFree);
  const asf::Decision d = make("policy_dopt_frontier.so", "dopt_frontier")->decide(c.s);
  EXPECT_EQ(d.type, Type::Done) << d.reason;
  EXPECT_NE(d.reason.find("no frontier left"), std::string::npos) << d.reason;
}

}  // namespace
