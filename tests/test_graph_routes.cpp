// Routes on a known graph: Euler, matching, Chinese postman, TSP, Tarry / Tremaux / DFS,
// and the asf route command. Oracles are brute force (edge duplications, permutations,
// pairings) on small instances and closed forms.
#include <asf/errors.h>
#include <asf/graph/families.h>
#include <asf/graph/file.h>
#include <asf/graph/routes.h>
#include <asf/graph/multigraph.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <numeric>
#include <random>
#include <set>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

using namespace asf::graph;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double totalLength(const Multigraph& g) {
  double t = 0;
  for (const auto& e : g.edges) t += e.length;
  return t;
}

/// Random connected multigraph: a random spanning tree, then extra edges (parallel edges and
/// self-loops allowed). Integer lengths in [1, maxlen] (or unit).
Multigraph randomConnected(std::mt19937& rng, int n, int extra, int maxlen = 1, bool loops = true) {
  Multigraph g;
  g.n = n;
  auto len = [&] { return maxlen <= 1 ? 1.0 : double(1 + rng() % maxlen); };
  for (int v = 1; v < n; ++v) g.edges.push_back({int(rng() % v), v, len()});
  for (int i = 0; i < extra; ++i) {
    int u = rng() % n, v = rng() % n;
    if (u == v && !loops) continue;
    g.edges.push_back({u, v, len()});
  }
  return g;
}

/// Random Eulerian multigraph: the union of random closed walks through node 0.
Multigraph randomEulerian(std::mt19937& rng, int n, int walks, int walk_len) {
  Multigraph g;
  g.n = n;
  for (int w = 0; w < walks; ++w) {
    int cur = 0;
    for (int s = 0; s < walk_len; ++s) {
      const int next = s + 1 == walk_len ? 0 : int(rng() % n);
      g.edges.push_back({cur, next, double(1 + rng() % 5)});
      cur = next;
    }
  }
  return g;
}

Multigraph pathGraph(int k) {
  Multigraph g;
  g.n = k + 1;
  for (int i = 0; i < k; ++i) g.edges.push_back({i, i + 1, 1});
  return g;
}

Multigraph completeGraph(int n) {
  Multigraph g;
  g.n = n;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) g.edges.push_back({i, j, 1});
  return g;
}


/// Per edge: traversals from u to v and from v to u (a self-loop counts in `forward`).
std::vector<std::array<int, 2>> directedCounts(const Multigraph& g, const Walk& w) {
  std::vector<std::array<int, 2>> c(g.m(), {0, 0});
  for (int i = 0; i < w.steps(); ++i) {
    const Edge& e = g.edges[w.edges[i]];
    const bool fwd = w.nodes[i] == e.u;
    ++c[w.edges[i]][fwd ? 0 : 1];
  }
  return c;
}

/// Brute-force postman: minimum over x_e in {1, 2} with the right parities (an optimal
/// postman walk never needs an edge three times).
double brutePostman(const Multigraph& g, int start, int end) {
  double best = kInf;
  const int m = g.m();
  for (long mask = 0; mask < (1L << m); ++mask) {
    std::vector<int> deg(g.n, 0);
    double len = 0;
    for (int e = 0; e < m; ++e) {
      const int x = 1 + (mask >> e & 1);
      deg[g.edges[e].u] += x;
      deg[g.edges[e].v] += x;
      len += x * g.edges[e].length;
    }
    bool ok = true;
    for (int v = 0; v < g.n; ++v) {
      const bool want_odd = start != end && (v == start || v == end);
      if ((deg[v] % 2 == 1) != want_odd) ok = false;
    }
    if (ok) best = std::min(best, len);
  }
  return best;
}

std::vector<std::vector<double>> floyd(const Multigraph& g) {
  std::vector<std::vector<double>> d(g.n, std::vector<double>(g.n, kInf));
  for (int v = 0; v < g.n; ++v) d[v][v] = 0;
  for (const auto& e : g.edges) {
    d[e.u][e.v] = std::min(d[e.u][e.v], e.length);
    d[e.v][e.u] = std::min(d[e.v][e.u], e.length);
  }
  for (int k = 0; k < g.n; ++k)
    for (int i = 0; i < g.n; ++i)
      for (int j = 0; j < g.n; ++j) d[i][j] = std::min(d[i][j], d[i][k] + d[k][j]);
  return d;
}

double bruteTsp(const Multigraph& g, int start) {
  const auto d = floyd(g);
  std::vector<int> rest;
  for (int v = 0; v < g.n; ++v)
    if (v != start) rest.push_back(v);
  double best = kInf;
  do {
    double c = 0;
    int cur = start;
    for (int v : rest) c += d[cur][v], cur = v;
    c += d[cur][start];
    best = std::min(best, c);
  } while (std::next_permutation(rest.begin(), rest.end()));
  return rest.empty() ? 0 : best;
}

double bruteMatching(const std::vector<std::vector<double>>& c, std::vector<char>& used) {
  const int k = int(c.size());
  int i = 0;
  while (i < k && used[i]) ++i;
  if (i == k) return 0;
  used[i] = 1;
  double best = kInf;
  for (int j = i + 1; j < k; ++j)
    if (!used[j]) {
      used[j] = 1;
      best = std::min(best, c[i][j] + bruteMatching(c, used));
      used[j] = 0;
    }
  used[i] = 0;
  return best;
}

double matchingCost(const std::vector<std::vector<double>>& c, const std::vector<int>& mate) {
  const int k = int(c.size());
  double s = 0;
  for (int i = 0; i < k; ++i) {
    EXPECT_GE(mate[i], 0);
    EXPECT_LT(mate[i], k);
    EXPECT_NE(mate[i], i);
    EXPECT_EQ(mate[mate[i]], i) << "not a matching";
    if (mate[i] > i) s += c[i][mate[i]];
  }
  return s;
}

std::vector<std::vector<double>> randomCosts(std::mt19937& rng, int k, int kind) {
  std::vector<std::vector<double>> c(k, std::vector<double>(k, 0));
  std::vector<std::pair<double, double>> pts(k);
  for (auto& p : pts) p = {double(rng() % 1000) / 37.0, double(rng() % 1000) / 41.0};
  for (int i = 0; i < k; ++i)
    for (int j = i + 1; j < k; ++j) {
      double v;
      if (kind == 0)
        v = double(rng() % 4);  // many ties: the degenerate case for blossoms
      else if (kind == 1)
        v = double(rng() % 1000);
      else if (kind == 2)
        v = std::hypot(pts[i].first - pts[j].first, pts[i].second - pts[j].second);
      else
        v = std::ldexp(double(rng() % 100000), -10) + 1e-3 * (rng() % 7);
      c[i][j] = c[j][i] = v;
    }
  return c;
}

void expectValid(const Multigraph& g, const Walk& w) { EXPECT_EQ(walkError(g, w), ""); }

}  // namespace

// ------------------------------------------------------------------------------------------
// Walk

TEST(GraphRoutes, WalkErrorCatchesBrokenWalks) {
  Multigraph g = completeGraph(3);
  Walk w;
  w.nodes = {0, 1, 2};
  w.edges = {0, 2};  // 0-1, 1-2
  w.length = 2;
  EXPECT_EQ(walkError(g, w), "");
  w.edges = {0, 1};  // 0-2 does not join 1 and 2
  EXPECT_NE(walkError(g, w), "");
  w.edges = {0, 2};
  w.length = 3;
  EXPECT_NE(walkError(g, w), "");
  w.length = 2;
  w.nodes.pop_back();
  EXPECT_NE(walkError(g, w), "");
  EXPECT_EQ(Walk{}.traversals(3), (std::vector<int>{0, 0, 0}));
}

// ------------------------------------------------------------------------------------------
// Euler

TEST(GraphRoutes, EulerCircuitOnRandomEulerianMultigraphs) {
  std::mt19937 rng(1);
  for (int t = 0; t < 300; ++t) {
    const int n = 1 + rng() % 9;
    Multigraph g = randomEulerian(rng, n, 1 + rng() % 4, 1 + rng() % 7);
    ASSERT_TRUE(hasEulerCircuit(g));
    // Start anywhere on the edges (node 0 always has one).
    const int start = g.edges[rng() % g.m()].u;
    const Walk w = eulerCircuit(g, start);
    expectValid(g, w);
    EXPECT_TRUE(w.closed());
    EXPECT_EQ(w.nodes.front(), start);
    EXPECT_EQ(w.steps(), g.m());
    for (int c : w.traversals(g.m())) EXPECT_EQ(c, 1);
    EXPECT_NEAR(w.length, totalLength(g), 1e-9);
  }
}

TEST(GraphRoutes, EulerRefusesWithReasons) {
  // Path 1-2-3: odd nodes 1 and 3.
  try {
    eulerCircuit(pathGraph(2), 0);
    FAIL() << "no circuit expected";
  } catch (const asf::Error& e) {
    EXPECT_NE(std::string(e.what()).find("odd degree (1, 3)"), std::string::npos) << e.what();
  }
  // Two disjoint triangles: even degrees, not connected.
  Multigraph two;
  two.n = 6;
  two.edges = {{0, 1, 1}, {1, 2, 1}, {2, 0, 1}, {3, 4, 1}, {4, 5, 1}, {5, 3, 1}};
  EXPECT_FALSE(hasEulerCircuit(two));
  EXPECT_THROW(eulerCircuit(two, 0), asf::Error);
  EXPECT_THROW(eulerCircuit(pathGraph(2), 7), asf::InputError);
  // Trail between the two odd nodes, not from the middle.
  const Walk t = eulerTrail(pathGraph(3));
  EXPECT_EQ(t.nodes, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(eulerTrail(pathGraph(3), 3).nodes.back(), 0);
  EXPECT_THROW(eulerTrail(pathGraph(3), 1), asf::Error);
  EXPECT_THROW(eulerTrail(completeGraph(4)), asf::Error);  // 4 odd nodes
  // Edgeless graph: the trivial walk.
  Multigraph one;
  one.n = 1;
  EXPECT_EQ(eulerCircuit(one, 0).nodes, std::vector<int>{0});
}

TEST(GraphRoutes, EulerHandlesSelfLoopsAndParallelEdges) {
  Multigraph g;
  g.n = 2;
  g.edges = {{0, 0, 1}, {0, 1, 2}, {1, 0, 3}, {1, 1, 4}, {1, 1, 5}};
  const Walk w = eulerCircuit(g, 1);
  expectValid(g, w);
  EXPECT_EQ(w.steps(), 5);
  for (int c : w.traversals(g.m())) EXPECT_EQ(c, 1);
  EXPECT_DOUBLE_EQ(w.length, 15);
}

// ------------------------------------------------------------------------------------------
// Matching

TEST(GraphRoutes, MatchingDpAgreesWithBruteForce) {
  std::mt19937 rng(2);
  for (int t = 0; t < 200; ++t) {
    const int k = 2 * (1 + rng() % 4);
    const auto c = randomCosts(rng, k, t % 4);
    std::vector<char> used(k, 0);
    EXPECT_NEAR(matchingCost(c, minWeightPerfectMatching(c, MatchingMethod::BitmaskDP)),
                bruteMatching(c, used), 1e-9);
  }
}

TEST(GraphRoutes, BlossomAgreesWithDpOnRandomCompleteGraphs) {
  std::mt19937 rng(3);
  int instances = 0;
  for (int k = 2; k <= 16; k += 2)
    for (int t = 0; t < 120; ++t) {
      const int kind = t % 4;
      const auto c = randomCosts(rng, k, kind);
      const double dp = matchingCost(c, minWeightPerfectMatching(c, MatchingMethod::BitmaskDP));
      const double bl = matchingCost(c, minWeightPerfectMatching(c, MatchingMethod::Blossom));
      if (kind == 0 || kind == 1 || kind == 3)  // integer or dyadic: exact
        ASSERT_EQ(bl, dp) << "k=" << k << " t=" << t;
      else
        ASSERT_NEAR(bl, dp, 1e-9 * std::max(1.0, dp)) << "k=" << k << " t=" << t;
      ++instances;
    }
  // A few at the DP's size limit.
  for (int t = 0; t < 3; ++t) {
    const auto c = randomCosts(rng, 20, 1);
    EXPECT_EQ(matchingCost(c, minWeightPerfectMatching(c, MatchingMethod::Blossom)),
              matchingCost(c, minWeightPerfectMatching(c, MatchingMethod::BitmaskDP)));
  }
  EXPECT_EQ(instances, 8 * 120);
}

TEST(GraphRoutes, BlossomBeatsGreedyAndLocalSwapsOnLargeInstances) {
  // No exact oracle at k = 80: the blossom must be a perfect matching no 2-swap improves.
  std::mt19937 rng(4);
  for (int t = 0; t < 5; ++t) {
    const int k = 80;
    const auto c = randomCosts(rng, k, 1 + t % 2);
    const auto mate = minWeightPerfectMatching(c, MatchingMethod::Blossom);
    matchingCost(c, mate);
    for (int i = 0; i < k; ++i)
      for (int j = 0; j < k; ++j) {
        const int a = mate[i], b = mate[j];
        if (j == i || j == a) continue;
        // Swap partners: (i,a),(j,b) -> (i,j),(a,b) must not be cheaper.
        EXPECT_GE(c[i][j] + c[a][b] + 1e-9, c[i][a] + c[j][b]);
      }
  }
}

TEST(GraphRoutes, MatchingRejectsBadInput) {
  EXPECT_THROW(minWeightPerfectMatching({{0}}), asf::InputError);  // odd size
  EXPECT_THROW(minWeightPerfectMatching({{0, 1}, {2, 0}}), asf::InputError);  // asymmetric
  EXPECT_THROW(minWeightPerfectMatching({{0, -1}, {-1, 0}}), asf::InputError);
  EXPECT_TRUE(minWeightPerfectMatching({}).empty());
}

// ------------------------------------------------------------------------------------------
// Chinese postman

TEST(GraphRoutes, PostmanClosedForms) {
  for (int k = 1; k <= 6; ++k) {
    const auto r = chinesePostman(pathGraph(k), 0);
    EXPECT_DOUBLE_EQ(r.walk.length, 2.0 * k);
    EXPECT_TRUE(r.walk.closed());
  }
  const auto k4 = chinesePostman(completeGraph(4), 2);
  EXPECT_DOUBLE_EQ(k4.walk.length, 8);  // 6 edges + 2 added for 4 odd nodes
  EXPECT_DOUBLE_EQ(k4.added_length, 2);
  EXPECT_EQ(k4.odd_vertices.size(), 4u);
  // Trees: every edge twice. Cycles: every edge once.
  std::mt19937 rng(5);
  for (int t = 0; t < 20; ++t) {
    const Multigraph tree = randomConnected(rng, 2 + rng() % 12, 0, 9);
    const auto r = chinesePostman(tree, rng() % tree.n);
    EXPECT_DOUBLE_EQ(r.walk.length, 2 * totalLength(tree));
    for (int c : r.walk.traversals(tree.m())) EXPECT_EQ(c, 2);
  }
  Multigraph cyc;
  cyc.n = 5;
  for (int i = 0; i < 5; ++i) cyc.edges.push_back({i, (i + 1) % 5, 1.5});
  EXPECT_DOUBLE_EQ(chinesePostman(cyc, 3).walk.length, 7.5);
  // Open: a path walked end to end once.
  EXPECT_DOUBLE_EQ(chinesePostman(pathGraph(4), 0, 4).walk.length, 4);
}

TEST(GraphRoutes, PostmanMatchesBruteForceOnSmallGraphs) {
  std::mt19937 rng(6);
  for (int t = 0; t < 250; ++t) {
    const int n = 2 + rng() % 5;
    const Multigraph g = randomConnected(rng, n, rng() % 6, 7);
    const int start = rng() % n;
    const bool open = t % 3 == 2;
    const int end = open ? int(rng() % n) : -1;
    const auto r = chinesePostman(g, start, end);
    expectValid(g, r.walk);
    EXPECT_EQ(r.walk.nodes.front(), start);
    EXPECT_EQ(r.walk.nodes.back(), end < 0 ? start : end);
    EXPECT_TRUE(coversAllEdges(g, r.walk));
    const auto x = r.walk.traversals(g.m());
    for (int e = 0; e < g.m(); ++e) EXPECT_EQ(x[e], 1 + r.duplicates[e]);
    ASSERT_NEAR(r.walk.length, brutePostman(g, start, end < 0 ? start : end), 1e-9)
        << "t=" << t;
    // Both matching methods reach the same optimum.
    EXPECT_NEAR(chinesePostman(g, start, end, MatchingMethod::Blossom).walk.length,
                r.walk.length, 1e-9);
  }
}

TEST(GraphRoutes, PostmanOnLargeGraphsDpAndBlossomAgree) {
  // Grids have many odd border nodes: 5x6 has 14, which the DP still handles.
  const Multigraph g = asf::graph::gridGraph(6, 5);
  const auto dp = chinesePostman(g, 0, -1, MatchingMethod::BitmaskDP);
  const auto bl = chinesePostman(g, 0, -1, MatchingMethod::Blossom);
  EXPECT_EQ(dp.odd_vertices.size(), 14u);
  EXPECT_DOUBLE_EQ(dp.walk.length, bl.walk.length);
  // 14 odd border nodes: 3 on the top and bottom rows, so two pairs cross a corner (2 each).
  EXPECT_DOUBLE_EQ(dp.walk.length, g.m() + 9.0);
  expectValid(g, bl.walk);
}

TEST(GraphRoutes, PostmanRefusesUnreachableEdges) {
  Multigraph g;
  g.n = 4;
  g.edges = {{0, 1, 1}, {2, 3, 1}};
  EXPECT_THROW(chinesePostman(g, 0), asf::Error);
  g.edges[0].length = -1;
  EXPECT_THROW(chinesePostman(g, 0), asf::InputError);
  // Isolated nodes are ignored.
  Multigraph h;
  h.n = 3;
  h.edges = {{0, 1, 2}};
  EXPECT_DOUBLE_EQ(chinesePostman(h, 1).walk.length, 4);
}

// ------------------------------------------------------------------------------------------
// TSP

TEST(GraphRoutes, HeldKarpMatchesBruteForcePermutations) {
  std::mt19937 rng(7);
  for (int t = 0; t < 120; ++t) {
    const int n = 1 + rng() % 8;
    const Multigraph g = randomConnected(rng, n, rng() % 8, 9);
    const int start = rng() % n;
    TspOptions dp_only;
    dp_only.certify = false;  // always the DP (n >= 3), never a certified heuristic
    const auto r = travelingSalesman(g, start, dp_only);
    EXPECT_TRUE(r.exact);
    if (n >= 3) {
      EXPECT_EQ(r.method, "held-karp");
    }
    // The default (heuristic first, certified by the bound, else the DP) is optimal too.
    EXPECT_NEAR(travelingSalesman(g, start).walk.length, r.walk.length, 1e-9);
    expectValid(g, r.walk);
    EXPECT_TRUE(r.walk.closed());
    EXPECT_EQ(r.walk.nodes.front(), start);
    EXPECT_TRUE(visitsAllNodes(g, r.walk));
    ASSERT_NEAR(r.walk.length, bruteTsp(g, start), 1e-9) << "t=" << t;
    EXPECT_EQ(r.order.size(), size_t(n));
  }
}

TEST(GraphRoutes, TspHeuristicBetweenBoundAndExact) {
  std::mt19937 rng(8);
  TspOptions heur;
  heur.exact_max_nodes = 0;
  heur.certify = false;
  TspOptions certified;
  certified.exact_max_nodes = 0;
  double worst = 1;
  for (int t = 0; t < 60; ++t) {
    const int n = 3 + rng() % 10;
    const Multigraph g = randomConnected(rng, n, rng() % 15, 20, false);
    const int start = rng() % n;
    const auto exact = travelingSalesman(g, start);
    const auto h = travelingSalesman(g, start, heur);
    EXPECT_FALSE(h.exact);
    expectValid(g, h.walk);
    EXPECT_TRUE(h.walk.closed());
    EXPECT_EQ(h.walk.nodes.front(), start);
    EXPECT_TRUE(visitsAllNodes(g, h.walk));
    EXPECT_GE(h.walk.length, exact.walk.length - 1e-9);
    EXPECT_LE(h.lower_bound, exact.walk.length + 1e-9);
    // The raw (uncapped) bound must hold too, and be useful.
    const double raw = heldKarpLowerBound(floyd(g), h.walk.length);
    EXPECT_LE(raw, exact.walk.length + 1e-9);
    EXPECT_GE(raw, 0.8 * exact.walk.length);
    worst = std::max(worst, h.walk.length / exact.walk.length);
    // Certification only claims optimality when the tour meets the bound.
    const auto c = travelingSalesman(g, start, certified);
    if (c.exact) {
      EXPECT_NEAR(c.walk.length, exact.walk.length, 1e-9);
    }
  }
  EXPECT_LT(worst, 1.1);  // local search with kicks on <= 12 nodes is rarely far off
}

TEST(GraphRoutes, TspOnGridIsNearOptimalWithTightBound) {
  // An even grid has a Hamiltonian cycle: the optimum is n, and the 1-tree bound is n too.
  const Multigraph g = asf::graph::gridGraph(8, 8);
  const auto r = travelingSalesman(g, 5);
  EXPECT_EQ(r.exact, r.walk.length <= 64 + 1e-9);  // certified exactly when it found n
  expectValid(g, r.walk);
  EXPECT_TRUE(visitsAllNodes(g, r.walk));
  EXPECT_LE(r.lower_bound, 64 + 1e-9);
  EXPECT_LE(heldKarpLowerBound(floyd(g), r.walk.length), 64 + 1e-9);
  EXPECT_GE(r.lower_bound, 60);
  EXPECT_LE(r.walk.length, 70);
  Multigraph two = pathGraph(4);
  two.n = 6;  // node 6 has no edge
  EXPECT_THROW(travelingSalesman(two, 0), asf::Error);
}

// ------------------------------------------------------------------------------------------
// Explorers

TEST(GraphRoutes, TarryChooseRule) {
  std::mt19937 rng(0);
  const TarryOptions plain;
  // The entrance edge is the last resort.
  std::vector<TarryCandidate> c = {{1, false, true, true, 1}, {2, false, false, false, 5}};
  EXPECT_EQ(tarryChoose(c, plain, rng), 2);
  c[1].traversed_outward = true;
  EXPECT_EQ(tarryChoose(c, plain, rng), 1);
  c[0].traversed_outward = true;
  EXPECT_EQ(tarryChoose(c, plain, rng), -1);
  // Loop closing first, then the nearest.
  c = {{1, false, false, false, 1}, {2, false, false, true, 9}, {3, false, false, true, 4},
       {4, false, true, true, 0}};
  EXPECT_EQ(tarryChoose(c, TarryOptions::modified(), rng), 3);
  TarryOptions near_only;
  near_only.nearest_first = true;
  EXPECT_EQ(tarryChoose(c, near_only, rng), 1);
  // Ties are drawn: both edges appear over seeds, each seed always gives the same one.
  c = {{1, false, false, false, 1}, {2, false, false, false, 1}};
  std::set<int> seen;
  for (unsigned s = 0; s < 20; ++s) {
    std::mt19937 a(s), b(s);
    const int x = tarryChoose(c, plain, a);
    EXPECT_EQ(x, tarryChoose(c, plain, b));
    seen.insert(x);
  }
  EXPECT_EQ(seen.size(), 2u);
}

TEST(GraphRoutes, TarryTraversesEveryEdgeOnceEachWayAndEntranceLast) {
  std::mt19937 rng(9);
  for (int t = 0; t < 300; ++t) {
    const int n = 1 + rng() % 10;
    const Multigraph g = randomConnected(rng, n, rng() % 12, 5);
    const int start = rng() % n;
    const auto r = tarry(g, start, TarryOptions{}, rng());
    const Walk& w = r.walk;
    expectValid(g, w);
    EXPECT_TRUE(w.closed());
    EXPECT_EQ(w.nodes.front(), start);
    EXPECT_TRUE(r.covered_all_edges);
    EXPECT_TRUE(r.visited_all_nodes);
    EXPECT_EQ(w.steps(), 2 * g.m());
    EXPECT_NEAR(w.length, 2 * totalLength(g), 1e-9);
    const auto dc = directedCounts(g, w);
    for (int e = 0; e < g.m(); ++e) {
      if (g.edges[e].u == g.edges[e].v) {
        EXPECT_EQ(dc[e][0], 2);
      } else {
        EXPECT_EQ(dc[e], (std::array<int, 2>{1, 1})) << "edge " << e;
      }
    }
    // The edge of first entry into a node is the last one used to leave it.
    std::vector<int> entrance(n, -1), last_exit(n, -1);
    std::vector<char> seen(n, 0);
    seen[start] = 1;
    for (int i = 0; i < w.steps(); ++i) {
      last_exit[w.nodes[i]] = w.edges[i];
      const int b = w.nodes[i + 1];
      if (!seen[b]) seen[b] = 1, entrance[b] = w.edges[i];
    }
    for (int v = 0; v < n; ++v) {
      if (v != start) {
        EXPECT_EQ(last_exit[v], entrance[v]) << "node " << v;
      }
    }
  }
}

TEST(GraphRoutes, ModifiedTarryStopsWhenCoveredWithinPostmanAndTwiceTotal) {
  std::mt19937 rng(10);
  for (int t = 0; t < 200; ++t) {
    const int n = 2 + rng() % 7;
    const Multigraph g = randomConnected(rng, n, rng() % 7, 6);
    const int start = rng() % n;
    const auto r = tarry(g, start, TarryOptions::modified(), rng());
    expectValid(g, r.walk);
    EXPECT_TRUE(r.covered_all_edges);
    EXPECT_EQ(r.steps_to_cover_edges, r.walk.steps());  // stops at once
    const auto dc = directedCounts(g, r.walk);  // never the same way twice
    for (int e = 0; e < g.m(); ++e) {
      if (g.edges[e].u == g.edges[e].v) {
        EXPECT_LE(dc[e][0], 2);
      } else {
        EXPECT_TRUE(dc[e][0] <= 1 && dc[e][1] <= 1);
      }
    }
    EXPECT_LE(r.walk.length, 2 * totalLength(g) + 1e-9);
    // No walk from start covering every edge is shorter than the open postman walk to
    // wherever it ends.
    EXPECT_GE(r.walk.length + 1e-9,
              chinesePostman(g, start, r.walk.nodes.back()).walk.length);
  }
}

TEST(GraphRoutes, ModifiedTarryOnHandMadeGraph) {
  // Triangle 1-2-3 (lengths 1, 1, 2) with a pendant 2-4 (length 5), from node 1.
  Multigraph g;
  g.n = 4;
  g.edges = {{0, 1, 1}, {1, 2, 1}, {2, 0, 2}, {1, 3, 5}};
  const auto r = tarry(g, 0, TarryOptions::modified(), 0);
  // 1->2 (nearest), 2->3 (nearest frontier), 3->1 (loop closing), 1->3 (allowed: not yet left
  // 1 by it), 3->2 (entrance, last resort), 2->4 (the entrance 1-2 comes last), stop.
  EXPECT_EQ(r.walk.nodes, (std::vector<int>{0, 1, 2, 0, 2, 1, 3}));
  EXPECT_DOUBLE_EQ(r.walk.length, 12);
  EXPECT_FALSE(r.walk.closed());
  // Loop closing: at node 2 (entered from 1), an edge to visited node 1 beats the frontier.
  Multigraph h;
  h.n = 4;
  h.edges = {{0, 1, 1}, {1, 2, 1}, {1, 0, 9}, {2, 3, 1}};
  TarryOptions lc;
  lc.loop_closing_first = true;
  int short_first = 0;
  for (unsigned s = 0; s < 10; ++s) {
    const auto w = tarry(h, 0, lc, s).walk;
    ASSERT_GE(w.steps(), 2);
    if (w.edges[0] == 0) {  // 1 -> 2 by the short edge, then back by the long one
      EXPECT_EQ(w.edges[1], 2);
      ++short_first;
    }
  }
  EXPECT_GT(short_first, 0);
}

TEST(GraphRoutes, TremauxTurnsBackAndWalksEveryEdgeTwice) {
  std::mt19937 rng(11);
  for (int t = 0; t < 300; ++t) {
    const int n = 1 + rng() % 10;
    const Multigraph g = randomConnected(rng, n, rng() % 12, 3);
    const int start = rng() % n;
    const auto r = tremaux(g, start, rng());
    const Walk& w = r.walk;
    expectValid(g, w);
    EXPECT_TRUE(w.closed());
    EXPECT_EQ(w.nodes.front(), start);
    EXPECT_TRUE(r.covered_all_edges);
    const auto dc = directedCounts(g, w);
    for (int e = 0; e < g.m(); ++e)
      EXPECT_EQ(dc[e][0] + dc[e][1], 2) << "edge " << e;
    for (int e = 0; e < g.m(); ++e) {
      if (g.edges[e].u != g.edges[e].v) {
        EXPECT_EQ(dc[e][0], 1);
      }
    }
    // Arriving at an old node by a new edge: the next step walks that edge back.
    std::vector<char> seen(n, 0);
    std::vector<int> used(g.m(), 0);
    seen[start] = 1;
    for (int i = 0; i < w.steps(); ++i) {
      const int e = w.edges[i], b = w.nodes[i + 1];
      const int times = ++used[e];
      const bool old = seen[b];
      seen[b] = 1;
      if (old && times == 1) {
        ASSERT_LT(i + 1, w.steps());
        EXPECT_EQ(w.edges[i + 1], e);
      }
    }
  }
}

TEST(GraphRoutes, DfsWalksASpanningTreeTwice) {
  std::mt19937 rng(12);
  for (int t = 0; t < 200; ++t) {
    const int n = 1 + rng() % 12;
    const Multigraph g = randomConnected(rng, n, rng() % 10, 4);
    const int start = rng() % n;
    const auto r = dfsExplore(g, start, rng());
    const Walk& w = r.walk;
    expectValid(g, w);
    EXPECT_TRUE(w.closed());
    EXPECT_TRUE(r.visited_all_nodes);
    EXPECT_EQ(w.steps(), 2 * (n - 1));
    const auto x = w.traversals(g.m());
    int tree = 0;
    for (int e = 0; e < g.m(); ++e) {
      EXPECT_TRUE(x[e] == 0 || x[e] == 2);
      if (x[e]) {
        ++tree;
        EXPECT_NE(g.edges[e].u, g.edges[e].v);
      }
    }
    EXPECT_EQ(tree, n - 1);
    EXPECT_EQ(r.covered_all_edges, g.m() == n - 1);
  }
}

TEST(GraphRoutes, ExplorersAreDeterministicPerSeed) {
  const Multigraph g = asf::graph::gridGraph(4, 4);
  using Fn = std::function<Walk(unsigned)>;
  const std::vector<Fn> fns = {
      [&](unsigned s) { return tarry(g, 0, TarryOptions{}, s).walk; },
      [&](unsigned s) { return tarry(g, 0, TarryOptions::modified(), s).walk; },
      [&](unsigned s) { return tremaux(g, 0, s).walk; },
      [&](unsigned s) { return dfsExplore(g, 0, s).walk; },
  };
  for (const auto& f : fns) {
    std::set<std::vector<int>> distinct;
    for (unsigned s = 0; s < 10; ++s) {
      EXPECT_EQ(f(s).edges, f(s).edges);
      distinct.insert(f(s).nodes);
    }
    EXPECT_GT(distinct.size(), 1u);  // the seed does break ties
  }
}

TEST(GraphRoutes, ComputeRouteDispatchAndNames) {
  const Multigraph g = completeGraph(4);
  for (const char* name : {"euler", "cpp", "tsp", "tarry", "tarry_modified", "tremaux", "dfs"})
    EXPECT_EQ(routeAlgorithmName(parseRouteAlgorithm(name)), name);
  EXPECT_THROW(parseRouteAlgorithm("chinese"), asf::InputError);
  EXPECT_THROW(computeRoute(g, RouteAlgorithm::Euler, 0), asf::Error);
  const auto cpp = computeRoute(g, RouteAlgorithm::ChinesePostman, 1);
  EXPECT_TRUE(cpp.exact);
  EXPECT_DOUBLE_EQ(cpp.walk.length, 8);
  EXPECT_TRUE(cpp.covered_all_edges);
  EXPECT_GE(cpp.steps_to_cover_edges, 6);
  const auto tsp = computeRoute(g, RouteAlgorithm::Tsp, 0);
  EXPECT_DOUBLE_EQ(tsp.walk.length, 4);
  EXPECT_FALSE(tsp.covered_all_edges);
  EXPECT_EQ(tsp.steps_to_visit_nodes, 3);
  EXPECT_THROW(computeRoute(g, RouteAlgorithm::Tarry, 0, 0, 2), asf::InputError);
  const auto open = computeRoute(pathGraph(3), RouteAlgorithm::Euler, 0, 0, 3);
  EXPECT_EQ(open.walk.nodes.back(), 3);
}

// ------------------------------------------------------------------------------------------
// Files and the command

namespace {

std::filesystem::path tempFile(const std::string& name, const std::string& text) {
  const auto p = std::filesystem::temp_directory_path() /
                 ("graph_routes_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(p) << text;
  return p;
}

/// Runs asf with arguments; returns the exit code, stdout in out, stderr in err.
int runAsf(const std::string& args, std::string& out, std::string& err) {
  const auto dir = std::filesystem::temp_directory_path();
  // ctest runs tests in parallel processes: one pair of files per process.
  const std::string tag = std::to_string(::getpid());
  const auto o = dir / ("graph_routes_out_" + tag + ".txt");
  const auto e = dir / ("graph_routes_err_" + tag + ".txt");
  const std::string cmd = std::string(ASF_TEST_BINARY_DIR) + "/bin/asf " + args + " >" +
                          o.string() + " 2>" + e.string();
  const int rc = std::system(cmd.c_str());
  auto slurp = [](const std::filesystem::path& p) {
    std::ifstream f(p);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
  };
  out = slurp(o);
  err = slurp(e);
  std::filesystem::remove(o);
  std::filesystem::remove(e);
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

}  // namespace

TEST(GraphFile, ListsPickTheLineAskedAndOtherFilesRefuseOne) {
  const auto p = tempFile("pick.txt", "# two graphs\n3 2 1-2 2-3\n\n4 3 1-2 2-3 3-4\n");
  const auto ref = asf::graph::NoiseReference::Median;
  GraphFile first = readGraphFile(p.string(), std::nullopt, false, ref);
  EXPECT_EQ(first.line, 2);
  EXPECT_EQ(first.g.n, 3);
  GraphFile fourth = readGraphFile(p.string(), 4, false, ref);
  EXPECT_EQ(fourth.line, 4);
  EXPECT_EQ(fourth.g.m(), 3);
  EXPECT_FALSE(fourth.pose_graph.has_value());
  try {
    readGraphFile(p.string(), 3, false, ref);  // the blank line
    FAIL() << "expected InputError";
  } catch (const asf::InputError& e) {
    EXPECT_EQ(std::string(e.what()), p.string() + ":3: no graph on that line");
  }
  const auto empty = tempFile("empty.txt", "# nothing\n");
  EXPECT_THROW(graphOnLine(readGraphList(empty.string()), empty.string(), std::nullopt),
               asf::InputError);
  const auto g2o = tempFile("two.g2o",
                            "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n"
                            "EDGE_SE2 0 1 1 0 0 100 0 0 100 0 1000\n");
  EXPECT_THROW(readGraphFile(g2o.string(), 1, false, ref), asf::InputError);
  const GraphFile pg = readGraphFile(g2o.string(), std::nullopt, true, ref);
  ASSERT_TRUE(pg.pose_graph.has_value());
  EXPECT_EQ(pg.g.n, 2);
  EXPECT_EQ(pg.positions.size(), 2u);
  const auto dir = std::filesystem::temp_directory_path() / "asf_test_graph_file_dir";
  std::filesystem::create_directories(dir);
  EXPECT_THROW(readGraphFile(dir.string(), std::nullopt, false, ref), asf::InputError);
  for (const auto& f : {p, empty, g2o}) std::filesystem::remove(f);
  std::filesystem::remove_all(dir);
}

TEST(GraphRoutes, MalformedGraphFilesNameFileAndLine) {
  const auto p = tempFile("bad.txt", "4 3 1-2 2-3 3-4\n# comment\n\n3 2 1-2 2-9\n");
  try {
    readGraphList(p.string());
    FAIL() << "expected InputError";
  } catch (const asf::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(p.string() + ":4"), std::string::npos) << e.what();
  }
  const auto q = tempFile("count.txt", "3 3 1-2 2-3\n");
  EXPECT_THROW(readGraphList(q.string()), asf::InputError);
  // A node count no dense analysis can hold: named, not std::bad_alloc (issue 20, item 7).
  const auto huge = tempFile("huge.txt", "3 2 1-2 2-3\n2147483647 0\n");
  try {
    readGraphList(huge.string());
    FAIL() << "expected InputError";
  } catch (const asf::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(huge.string() + ":2: n = 2147483647 nodes"),
              std::string::npos)
        << e.what();
  }
  std::filesystem::remove(huge);
  std::string out, err;
  EXPECT_EQ(runAsf("route " + p.string() + " --algorithm cpp", out, err), 1);
  EXPECT_NE(err.find(p.string() + ":4"), std::string::npos) << err;
  std::filesystem::remove(p);
  std::filesystem::remove(q);
}

TEST(GraphRoutes, RouteCommand) {
  // Line 1: a path 1-2-3; line 3: K4.
  const auto p = tempFile("list.txt", "3 2 1-2 2-3\n# K4 next\n4 6 1-2 1-3 1-4 2-3 2-4 3-4\n");
  std::string out, err;
  ASSERT_EQ(runAsf("route " + p.string() + " --algorithm cpp --index 3 --start 2 --json", out, err),
            0)
      << err;
  const auto j = nlohmann::json::parse(out);
  EXPECT_EQ(j["index"], 3);
  EXPECT_EQ(j["n"], 4);
  EXPECT_DOUBLE_EQ(j["length"].get<double>(), 8);
  EXPECT_EQ(j["traversals"], 8);
  EXPECT_EQ(j["nodes"].front(), 2);
  EXPECT_EQ(j["nodes"].back(), 2);
  EXPECT_TRUE(j["covered_all_edges"].get<bool>());
  EXPECT_EQ(j["edge_traversals"].size(), 6u);
  // Text output of the first graph.
  ASSERT_EQ(runAsf("route " + p.string() + " -a tarry --seed 3", out, err), 0) << err;
  EXPECT_NE(out.find("length 4, 4 traversals, closed"), std::string::npos) << out;
  EXPECT_NE(out.find("walk: 1 2 3 2 1"), std::string::npos) << out;
  // Errors: no Euler circuit (1), unknown algorithm (usage, 2), start outside the graph (1),
  // no graph on that line (1).
  EXPECT_EQ(runAsf("route " + p.string() + " -a euler", out, err), 1);
  EXPECT_NE(err.find(p.string() + ":1"), std::string::npos) << err;
  EXPECT_EQ(runAsf("route " + p.string() + " -a nope", out, err), 2);
  EXPECT_EQ(runAsf("route " + p.string() + " -a dfs --start 9", out, err), 1);
  EXPECT_EQ(runAsf("route " + p.string() + " -a dfs --index 2", out, err), 1);
  std::filesystem::remove(p);
}
