// Tests of the shortest planner against brute-force enumeration of simple paths.
#include <asf/planner.h>
#include <asf/framework/registry.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <set>

namespace {

std::shared_ptr<const asf::framework::PluginInfo> info() {
  static auto i = asf::framework::Registry::loadFile(ASF_TEST_PLUGIN_DIR "/planner_shortest.so");
  return i;
}

asf::framework::PluginHandle<asf::Planner> make() {
  auto h = asf::framework::Registry::create<asf::Planner>(info());
  h->configure(asf::Params::fromSpecs("shortest", info()->descriptor->keys,
                                      info()->descriptor->num_keys),
               asf::PluginContext{});
  return h;
}

double dist(const asf::PoseGraph& g, asf::NodeId a, asf::NodeId b) {
  return std::hypot(g.nodes[a].pose.x() - g.nodes[b].pose.x(),
                    g.nodes[a].pose.y() - g.nodes[b].pose.y());
}

bool joined(const asf::PoseGraph& g, asf::NodeId a, asf::NodeId b) {
  for (const auto& e : g.edges)
    if ((e.from == a && e.to == b) || (e.from == b && e.to == a)) return true;
  return false;
}

/// Minimum length over all simple paths (infinity if none).
double bruteForce(const asf::PoseGraph& g, asf::NodeId s, asf::NodeId t) {
  double best = std::numeric_limits<double>::infinity();
  std::vector<char> on(g.size(), 0);
  std::function<void(asf::NodeId, double)> dfs = [&](asf::NodeId v, double len) {
    if (v == t) {
      best = std::min(best, len);
      return;
    }
    on[v] = 1;
    for (asf::NodeId w = 0; w < g.size(); ++w)
      if (!on[w] && joined(g, v, w)) dfs(w, len + dist(g, v, w));
    on[v] = 0;
  };
  dfs(s, 0);
  return best;
}

TEST(PlannerShortest, MatchesBruteForceOnRandomGraphs) {
  auto planner = make();
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 10);
  int found = 0, not_found = 0;
  for (int trial = 0; trial < 300; ++trial) {
    asf::PoseGraph g;
    const int n = 2 + static_cast<int>(rng() % 7);
    for (int i = 0; i < n; ++i) g.addNode(mrpt::poses::CPose2D(u(rng), u(rng), u(rng)));
    const int m = static_cast<int>(rng() % (n * 2));
    for (int k = 0; k < m; ++k) {
      asf::PoseEdge e;
      e.from = static_cast<asf::NodeId>(rng() % n);
      e.to = static_cast<asf::NodeId>(rng() % n);
      if (e.from != e.to) g.addEdge(e);
    }
    asf::PlanRequest req;
    req.graph = &g;
    req.start = static_cast<asf::NodeId>(rng() % n);
    req.goal = static_cast<asf::NodeId>(rng() % n);
    const asf::PlanResult r = planner->plan(req);
    const double oracle = bruteForce(g, req.start, req.goal);
    EXPECT_EQ(r.criterion, "distance");
    if (std::isinf(oracle)) {
      EXPECT_FALSE(r.found) << trial;
      EXPECT_FALSE(r.reason.empty());
      ++not_found;
      continue;
    }
    ++found;
    ASSERT_TRUE(r.found) << trial << ": " << r.reason;
    EXPECT_NEAR(r.cost, oracle, 1e-9) << trial;
    ASSERT_FALSE(r.nodes.empty());
    EXPECT_EQ(r.nodes.front(), req.start);
    EXPECT_EQ(r.nodes.back(), req.goal);
    double len = 0;
    for (std::size_t i = 1; i < r.nodes.size(); ++i) {
      EXPECT_TRUE(joined(g, r.nodes[i - 1], r.nodes[i])) << trial;
      len += dist(g, r.nodes[i - 1], r.nodes[i]);
    }
    EXPECT_NEAR(len, r.cost, 1e-9);
    EXPECT_EQ(std::set<asf::NodeId>(r.nodes.begin(), r.nodes.end()).size(), r.nodes.size());
  }
  EXPECT_GT(found, 50);
  EXPECT_GT(not_found, 20);
}

TEST(PlannerShortest, TrivialAndInvalidRequests) {
  auto planner = make();
  asf::PoseGraph g;
  for (int i = 0; i < 3; ++i) g.addNode(mrpt::poses::CPose2D(i, 0, 0));
  asf::PoseEdge e;
  e.from = 0;
  e.to = 1;
  g.addEdge(e);
  asf::PlanRequest req;
  req.graph = &g;
  req.start = req.goal = 2;
  auto r = planner->plan(req);
  ASSERT_TRUE(r.found);
  EXPECT_EQ(r.nodes, std::vector<asf::NodeId>{2});
  EXPECT_EQ(r.cost, 0);
  req.start = 0;
  req.goal = 2;
  r = planner->plan(req);
  EXPECT_FALSE(r.found);
  EXPECT_NE(r.reason.find("not connected"), std::string::npos) << r.reason;
  req.goal = 9;
  r = planner->plan(req);
  EXPECT_FALSE(r.found);
  EXPECT_NE(r.reason.find("9"), std::string::npos) << r.reason;
  req.graph = nullptr;
  EXPECT_FALSE(planner->plan(req).found);
  // Edge direction does not matter.
  req.graph = &g;
  req.start = 1;
  req.goal = 0;
  r = planner->plan(req);
  ASSERT_TRUE(r.found);
  EXPECT_EQ(r.nodes, (std::vector<asf::NodeId>{1, 0}));
  EXPECT_DOUBLE_EQ(r.cost, 1);
}

}  // namespace
