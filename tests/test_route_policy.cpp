// The offline baselines' walks on a hand-made topological graph (asf::exploration::RoutePolicy::plan):
// the postman walk covers every region edge of the start's component, the TSP walk visits
// every region, and each step becomes two goals (border midpoint, next centroid).
#include <asf/exploration/route_policy.h>
#include <gtest/gtest.h>

#include <set>

namespace {

// Regions 1-2-3-4 in a cycle plus a dead end 3-5, a frontier edge (ignored), and region 9
// with no border to the others (another component, not walkable).
asf::TopoGraph graph() {
  asf::TopoGraph g;
  auto node = [&](asf::RegionId r, double x, double y) {
    asf::TopoNode n;
    n.region = r;
    n.centroid = {x, y};
    g.nodes.push_back(n);
  };
  node(1, 0, 0);
  node(2, 4, 0);
  node(3, 4, 4);
  node(4, 0, 4);
  node(5, 8, 4);
  node(9, 20, 20);
  node(asf::kUnexplored, 0, 0);
  auto edge = [&](asf::RegionId a, asf::RegionId b, double mx, double my) {
    asf::TopoEdge e;
    e.a = a;
    e.b = b;
    e.midpoint = {mx, my};
    g.edges.push_back(e);
  };
  edge(1, 2, 2, 0);
  edge(2, 3, 4, 2);
  edge(3, 4, 2, 4);
  edge(1, 4, 0, 2);
  edge(3, 5, 6, 4);
  edge(5, asf::kUnexplored, 9, 4);
  return g;
}

TEST(RoutePolicy, PostmanWalkCoversEveryEdgeOfTheStartComponent) {
  const asf::TopoGraph g = graph();
  const auto p = asf::exploration::RoutePolicy::plan(g, 1, asf::exploration::RoutePolicy::Route::ChinesePostman, 0.4, 1);
  EXPECT_EQ(p.edges, 5);
  EXPECT_DOUBLE_EQ(p.edges_length, 20.0);  // each edge 2 + 2 m through its midpoint
  // Odd regions 3 and 5 (degree 3 and 1): the dead end 3-5 is walked twice: 24 m.
  EXPECT_DOUBLE_EQ(p.walk.length, 24.0);
  ASSERT_EQ(p.walk.edges.size(), 6u);
  EXPECT_EQ(p.regions[p.walk.nodes.front()], 1);
  EXPECT_EQ(p.regions[p.walk.nodes.back()], 1) << "a closed walk";
  std::set<int> seen(p.walk.edges.begin(), p.walk.edges.end());
  EXPECT_EQ(seen.size(), 5u);
  ASSERT_EQ(p.goals.size(), 2 * p.walk.edges.size());
  for (std::size_t i = 0; i < p.walk.edges.size(); ++i) {
    const asf::RegionId to = p.regions[p.walk.nodes[i + 1]];
    const asf::TopoNode* n = g.node(to);
    EXPECT_DOUBLE_EQ(p.goals[2 * i + 1].x, n->centroid.x) << p.labels[2 * i + 1];
    EXPECT_DOUBLE_EQ(p.goals[2 * i + 1].y, n->centroid.y);
    EXPECT_DOUBLE_EQ(p.goals[2 * i].tolerance, 0.4);
  }
  for (asf::RegionId r : p.regions) EXPECT_NE(r, 9) << "region 9 is not reachable";
}

TEST(RoutePolicy, TspWalkVisitsEveryRegion) {
  const auto p = asf::exploration::RoutePolicy::plan(graph(), 2, asf::exploration::RoutePolicy::Route::Tsp, 0.4, 1);
  std::set<asf::RegionId> visited;
  for (int v : p.walk.nodes) visited.insert(p.regions[v]);
  EXPECT_EQ(visited, (std::set<asf::RegionId>{1, 2, 3, 4, 5}));
  // Shortest closed walk from 2 through all five: the cycle (16 m) plus 3-5 and back (8 m).
  EXPECT_DOUBLE_EQ(p.walk.length, 24.0);
  EXPECT_EQ(p.regions[p.walk.nodes.front()], 2);
  EXPECT_EQ(p.regions[p.walk.nodes.back()], 2);
}

TEST(RoutePolicy, IsolatedStartGivesAnEmptyWalk) {
  const auto p = asf::exploration::RoutePolicy::plan(graph(), 9, asf::exploration::RoutePolicy::Route::ChinesePostman, 0.4, 1);
  EXPECT_TRUE(p.walk.edges.empty());
  EXPECT_TRUE(p.goals.empty());
}

}  // namespace
