// Tests of the sum_dopt planner: the sum of the nodes' det(Sigma) along the chosen path is
// the smallest, and its scalar key switches the criterion.
#include <asf/planner.h>
#include <asf/framework/registry.h>
#include <gtest/gtest.h>

namespace {

std::shared_ptr<const asf::framework::PluginInfo> info() {
  static auto i = asf::framework::Registry::loadFile(ASF_TEST_PLUGIN_DIR "/planner_sum_dopt.so");
  return i;
}

asf::framework::PluginHandle<asf::Planner> make(
    const std::map<std::string, std::string>& keys = {}) {
  auto h = asf::framework::Registry::create<asf::Planner>(info());
  h->configure(asf::Params::fromSpecs("sum_dopt", info()->descriptor->keys,
                                      info()->descriptor->num_keys, keys),
               asf::PluginContext{});
  return h;
}

/// A square 0-1-2 / 0-3-2: node 1 uncertain in all axes, node 3 elongated (large trace,
/// small determinant).
struct Square {
  asf::PoseGraph g;
  asf::Marginals m;
  Square() {
    const double xy[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (auto& p : xy) g.addNode(mrpt::poses::CPose2D(p[0], p[1], 0));
    for (auto [a, b] : {std::pair{0, 1}, {1, 2}, {0, 3}, {3, 2}}) {
      asf::PoseEdge e;
      e.from = a;
      e.to = b;
      e.mean = g.nodes[b].pose - g.nodes[a].pose;
      g.addEdge(e);
    }
    m.node = {Eigen::Matrix3d::Zero(), Eigen::Matrix3d::Identity() * 0.5,
              Eigen::Matrix3d::Identity() * 0.1,
              Eigen::Vector3d(2.0, 0.01, 0.01).asDiagonal()};
  }
};

TEST(PlannerSumDopt, MinimizesTheSumOfDeterminants) {
  const Square s;
  auto r = make()->plan(asf::PlanRequest{&s.g, &s.m, nullptr, 0, 2});
  ASSERT_TRUE(r.found) << r.reason;
  EXPECT_EQ(r.nodes, (std::vector<asf::NodeId>{0, 3, 2}));
  EXPECT_NEAR(r.cost, 2e-4 + 1e-3, 1e-15);
  // Under trace (A-optimality) the other side wins.
  r = make({{"scalar", "trace"}})->plan(asf::PlanRequest{&s.g, &s.m, nullptr, 0, 2});
  ASSERT_TRUE(r.found);
  EXPECT_EQ(r.nodes, (std::vector<asf::NodeId>{0, 1, 2}));
  EXPECT_NEAR(r.cost, 1.5 + 0.3, 1e-12);
}

TEST(PlannerSumDopt, NeedsMarginals) {
  const Square s;
  const auto r = make()->plan(asf::PlanRequest{&s.g, nullptr, nullptr, 0, 2});
  EXPECT_FALSE(r.found);
  EXPECT_FALSE(r.reason.empty());
}

}  // namespace
