// Tests of the mechanical_work planner: its choice is the minimum of the criterion over all
// simple paths (brute force), and it needs marginals.
#include <asf/planning/expected_uncertainty.h>
#include <asf/planner.h>
#include <asf/framework/registry.h>
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <functional>
#include <random>

namespace {

std::shared_ptr<const asf::framework::PluginInfo> info() {
  static auto i =
      asf::framework::Registry::loadFile(ASF_TEST_PLUGIN_DIR "/planner_mechanical_work.so");
  return i;
}

asf::framework::PluginHandle<asf::Planner> make() {
  auto h = asf::framework::Registry::create<asf::Planner>(info());
  h->configure(asf::Params::fromSpecs("mechanical_work", info()->descriptor->keys,
                                      info()->descriptor->num_keys),
               asf::PluginContext{});
  return h;
}

TEST(PlannerMechanicalWork, ChoosesTheMinimumOverAllSimplePaths) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.01, 0.3);
  auto planner = make();
  for (int trial = 0; trial < 30; ++trial) {
    asf::PoseGraph g;
    const int n = 6 + trial % 4;
    for (int i = 0; i < n; ++i) g.addNode(mrpt::poses::CPose2D(i, (i * 7) % 3, 0.1 * i));
    auto edge = [&](int a, int b) {
      asf::PoseEdge e;
      e.from = a;
      e.to = b;
      e.mean = g.nodes[b].pose - g.nodes[a].pose;
      const double s = u(rng);
      e.information = Eigen::Vector3d(1 / (s * s), 1 / (s * s), 4 / (s * s)).asDiagonal();
      g.addEdge(e);
    };
    for (int i = 1; i < n; ++i) edge(i - 1, i);
    for (int k = 0; k < 3; ++k) {
      const int a = rng() % n, b = rng() % n;
      if (a != b) edge(a, b);
    }
    asf::Marginals m;
    for (int i = 0; i < n; ++i)
      m.node.push_back(Eigen::Vector3d(u(rng), u(rng), u(rng)).asDiagonal());
    const asf::NodeId s = 0, t = static_cast<asf::NodeId>(n - 1);
    // Brute force over simple paths of the original graph.
    double best = 1e300;
    std::vector<asf::NodeId> cur{s};
    std::vector<char> on(n, 0);
    std::function<void(asf::NodeId)> dfs = [&](asf::NodeId v) {
      if (v == t) {
        const auto model = asf::planning::makePathModel(g, &m, cur);
        best = std::min(best, asf::planning::evaluatePath(asf::planning::Criterion::MechanicalWork,
                                                          model, asf::planning::CriterionOptions{})
                                  .cost);
        return;
      }
      on[v] = 1;
      for (asf::NodeId w = 0; w < static_cast<asf::NodeId>(n); ++w) {
        bool joined = false;
        for (const auto& e : g.edges)
          joined |= (e.from == v && e.to == w) || (e.from == w && e.to == v);
        if (!joined || on[w]) continue;
        cur.push_back(w);
        dfs(w);
        cur.pop_back();
      }
      on[v] = 0;
    };
    dfs(s);
    const auto r = planner->plan(asf::PlanRequest{&g, &m, nullptr, s, t});
    ASSERT_TRUE(r.found) << r.reason;
    EXPECT_NEAR(r.cost, best, 1e-12 + 1e-9 * best) << trial;
    EXPECT_EQ(r.criterion, "work");
  }
}

TEST(PlannerMechanicalWork, DecreasingUncertaintyCostsNothing) {
  // A chain whose marginals shrink towards the goal: every increment is negative.
  asf::PoseGraph g;
  asf::Marginals m;
  for (int i = 0; i < 5; ++i) {
    g.addNode(mrpt::poses::CPose2D(i, 0, 0));
    m.node.push_back(Eigen::Matrix3d::Identity() * (1.0 / (i + 1)));
    if (i == 0) continue;
    asf::PoseEdge e;
    e.from = i - 1;
    e.to = i;
    e.mean = mrpt::poses::CPose2D(1, 0, 0);
    g.addEdge(e);
  }
  const auto r = make()->plan(asf::PlanRequest{&g, &m, nullptr, 0, 4});
  ASSERT_TRUE(r.found);
  EXPECT_EQ(r.cost, 0);
  EXPECT_FALSE(make()->plan(asf::PlanRequest{&g, nullptr, nullptr, 0, 4}).found);
}

}  // namespace
