// Traveling salesman tours over a graph's shortest-path metric: Held-Karp (exact, small),
// Christofides and nearest neighbour with 2-opt / Or-opt improvement.
#include <asf/errors.h>
#include <asf/graph/routes.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <vector>

#include "route_helpers.h"

namespace asf::graph {

using namespace detail;

// ----------------------------------------------------------------------------------------------
// TSP

namespace {

using Matrix = std::vector<std::vector<double>>;

double tourCost(const Matrix& d, const std::vector<int>& t) {
  double c = 0;
  for (std::size_t i = 0; i < t.size(); ++i) c += d[t[i]][t[(i + 1) % t.size()]];
  return c;
}

std::vector<int> heldKarp(const Matrix& d, int start) {
  const int n = static_cast<int>(d.size());
  std::vector<int> others;
  for (int v = 0; v < n; ++v)
    if (v != start) others.push_back(v);
  const int r = static_cast<int>(others.size());
  const std::size_t full = (std::size_t{1} << r);
  // cost[mask * r + j]: shortest path start -> (all of mask) ending at others[j] in mask.
  std::vector<double> cost(full * r, kInf);
  std::vector<signed char> parent(full * r, -1);
  for (int j = 0; j < r; ++j) cost[(std::size_t{1} << j) * r + j] = d[start][others[j]];
  for (std::size_t mask = 1; mask < full; ++mask)
    for (int j = 0; j < r; ++j) {
      if (!(mask >> j & 1)) continue;
      const double cj = cost[mask * r + j];
      if (!std::isfinite(cj)) continue;
      for (int k = 0; k < r; ++k) {
        if (mask >> k & 1) continue;
        const std::size_t nm = mask | (std::size_t{1} << k);
        const double c = cj + d[others[j]][others[k]];
        if (c < cost[nm * r + k]) {
          cost[nm * r + k] = c;
          parent[nm * r + k] = static_cast<signed char>(j);
        }
      }
    }
  int last = 0;
  double best = kInf;
  for (int j = 0; j < r; ++j) {
    const double c = cost[(full - 1) * r + j] + d[others[j]][start];
    if (c < best) best = c, last = j;
  }
  std::vector<int> rev;
  std::size_t mask = full - 1;
  for (int j = last; j >= 0;) {
    rev.push_back(others[j]);
    const int pj = parent[mask * r + j];
    mask ^= std::size_t{1} << j;
    j = pj;
  }
  std::vector<int> tour{start};
  tour.insert(tour.end(), rev.rbegin(), rev.rend());
  return tour;
}

std::vector<int> nearestNeighbourTour(const Matrix& d, int start) {
  const int n = static_cast<int>(d.size());
  std::vector<char> in(n, 0);
  std::vector<int> t{start};
  in[start] = 1;
  while (static_cast<int>(t.size()) < n) {
    int best = -1;
    for (int v = 0; v < n; ++v)
      if (!in[v] && (best < 0 || d[t.back()][v] < d[t.back()][best])) best = v;
    in[best] = 1;
    t.push_back(best);
  }
  return t;
}

/// Prim on the complete graph given by d restricted to `use` nodes; parent of each (-1 root).
std::vector<int> primTree(const Matrix& d, const std::vector<char>& use, int root) {
  const int n = static_cast<int>(d.size());
  std::vector<int> parent(n, -1);
  std::vector<double> key(n, kInf);
  std::vector<char> done(n, 0);
  key[root] = 0;
  for (;;) {
    int a = -1;
    for (int v = 0; v < n; ++v)
      if (use[v] && !done[v] && (a < 0 || key[v] < key[a])) a = v;
    if (a < 0) break;
    done[a] = 1;
    for (int v = 0; v < n; ++v)
      if (use[v] && !done[v] && d[a][v] < key[v]) key[v] = d[a][v], parent[v] = a;
  }
  return parent;
}

std::vector<int> christofidesTour(const Matrix& d, int start) {
  const int n = static_cast<int>(d.size());
  const auto parent = primTree(d, std::vector<char>(n, 1), start);
  Multigraph h;
  h.n = n;
  for (int v = 0; v < n; ++v)
    if (parent[v] >= 0) h.edges.push_back({v, parent[v], d[v][parent[v]]});
  const auto odd = oddVertices(h);
  Matrix c(odd.size(), std::vector<double>(odd.size(), 0));
  for (std::size_t i = 0; i < odd.size(); ++i)
    for (std::size_t j = 0; j < odd.size(); ++j) c[i][j] = d[odd[i]][odd[j]];
  const auto mate = minWeightPerfectMatching(c);
  for (std::size_t i = 0; i < odd.size(); ++i)
    if (mate[i] > static_cast<int>(i)) h.edges.push_back({odd[i], odd[mate[i]], c[i][mate[i]]});
  const Walk w = eulerCircuit(h, start);
  std::vector<char> in(n, 0);
  std::vector<int> t;
  for (int v : w.nodes)
    if (!in[v]) in[v] = 1, t.push_back(v);
  return t;
}

/// 2-opt and Or-opt (segments of 1-3 nodes, either orientation) until neither improves;
/// t[0] stays in place.
void improveTour(const Matrix& d, std::vector<int>& t) {
  const int n = static_cast<int>(t.size());
  if (n < 4) return;
  const double eps = 1e-12 * std::max(1.0, tourCost(d, t));
  bool improved = true;
  while (improved) {
    improved = false;
    for (int i = 0; i + 2 < n; ++i)
      for (int j = i + 2; j < n; ++j) {
        if (i == 0 && j == n - 1) continue;
        const int a = t[i], b = t[i + 1], c = t[j], e = t[(j + 1) % n];
        if (d[a][c] + d[b][e] - d[a][b] - d[c][e] < -eps) {
          std::reverse(t.begin() + i + 1, t.begin() + j + 1);
          improved = true;
        }
      }
    for (int len = 1; len <= 3; ++len)
      for (int i = 1; i + len <= n; ++i) {
        const int s0 = t[i], s1 = t[i + len - 1];
        const int prev = t[i - 1], next = t[(i + len) % n];
        if (next == s0) continue;
        const double gain = d[prev][s0] + d[s1][next] - d[prev][next];
        int best_j = -1;
        bool best_rev = false;
        double best_add = gain - eps;
        for (int j = 0; j < n; ++j) {
          if (j >= i - 1 && j <= i + len - 1) continue;  // edges touching the segment
          const int a = t[j], b = t[(j + 1) % n];
          const double fwd = d[a][s0] + d[s1][b] - d[a][b];
          const double rev = d[a][s1] + d[s0][b] - d[a][b];
          if (fwd < best_add) best_add = fwd, best_j = j, best_rev = false;
          if (rev < best_add) best_add = rev, best_j = j, best_rev = true;
        }
        if (best_j < 0) continue;
        std::vector<int> seg(t.begin() + i, t.begin() + i + len);
        if (best_rev) std::reverse(seg.begin(), seg.end());
        const int anchor = t[best_j];
        std::vector<int> rest;
        rest.reserve(n);
        for (int k = 0; k < n; ++k)
          if (k < i || k >= i + len) rest.push_back(t[k]);
        const auto pos = std::find(rest.begin(), rest.end(), anchor) - rest.begin();
        rest.insert(rest.begin() + pos + 1, seg.begin(), seg.end());
        t.swap(rest);
        improved = true;
      }
  }
}

}  // namespace

// Max over node penalties of the minimum 1-tree (node `special` with its two cheapest edges,
// a spanning tree on the rest), by subgradient ascent. Every penalty vector gives a valid
// bound, so the result is one whatever the iterations do.
double heldKarpLowerBound(const std::vector<std::vector<double>>& d, double upper, int iterations) {
  const int n = static_cast<int>(d.size());
  for (const auto& row : d)
    if (static_cast<int>(row.size()) != n) throw InputError("tsp bound: matrix not square");
  if (n < 2) return 0;
  if (n == 2) return d[0][1] + d[1][0];
  const int special = 0;
  std::vector<double> pi(n, 0);
  std::vector<char> use(n, 1);
  use[special] = 0;
  double best = -kInf, lambda = 2;
  int since = 0;
  Matrix dp(n, std::vector<double>(n));
  for (int it = 0; it < std::max(1, iterations); ++it) {
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) dp[a][b] = d[a][b] + pi[a] + pi[b];
    const auto parent = primTree(dp, use, special == 0 ? 1 : 0);
    std::vector<int> deg(n, 0);
    double cost = 0;
    for (int v = 0; v < n; ++v)
      if (parent[v] >= 0) cost += dp[v][parent[v]], ++deg[v], ++deg[parent[v]];
    int m1 = -1, m2 = -1;
    for (int v = 0; v < n; ++v) {
      if (v == special) continue;
      if (m1 < 0 || dp[special][v] < dp[special][m1])
        m2 = m1, m1 = v;
      else if (m2 < 0 || dp[special][v] < dp[special][m2])
        m2 = v;
    }
    cost += dp[special][m1] + dp[special][m2];
    ++deg[m1], ++deg[m2], deg[special] = 2;
    double value = cost;
    for (double p : pi) value -= 2 * p;
    if (it == 0 || value > best + 1e-12 * std::max(1.0, std::abs(best))) {
      best = value;
      since = 0;
    } else if (++since >= 10) {
      lambda /= 2;
      since = 0;
    }
    double norm2 = 0;
    for (int v = 0; v < n; ++v) norm2 += double(deg[v] - 2) * (deg[v] - 2);
    if (norm2 == 0) break;  // the 1-tree is a tour: the bound is tight
    const double t = lambda * (upper - value) / norm2;
    if (!(t > 1e-15 * std::max(1.0, upper)) || lambda < 1e-6) break;
    for (int v = 0; v < n; ++v) pi[v] += t * (deg[v] - 2);
  }
  return best;
}

TspResult travelingSalesman(const Multigraph& g, int start, const TspOptions& options) {
  checkGraph(g);
  checkNode(g, start, "start");
  if (!g.connected()) throw Error("no TSP walk: the graph is not connected");
  const int n = g.n;
  std::vector<ShortestPaths> sp;
  sp.reserve(n);
  Matrix d(n, std::vector<double>(n));
  for (int v = 0; v < n; ++v) {
    sp.push_back(dijkstra(g, v));
    d[v] = sp.back().dist;
  }
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b) d[a][b] = d[b][a] = std::min(d[a][b], d[b][a]);

  TspResult r;
  if (n <= 2) {
    r.order = {start};
    if (n == 2) r.order.push_back(1 - start);
    r.exact = true;
    r.method = "trivial";
  } else {
    // Heuristic first: when it meets the Held-Karp bound it is optimal, certified, and the
    // exponential DP is not needed.
    auto a = nearestNeighbourTour(d, start);
    auto b = christofidesTour(d, start);
    improveTour(d, a);
    improveTour(d, b);
    r.order = tourCost(d, b) <= tourCost(d, a) ? b : a;
    double cost = tourCost(d, r.order);
    const double bound = heldKarpLowerBound(d, cost, options.bound_iterations);
    const double tol = 1e-9 * std::max(1.0, cost);
    // Iterated local search: double-bridge kicks (t[0] stays), keep improvements.
    std::mt19937 rng(options.seed);
    for (int k = 0; k < options.kicks && n >= 8 && cost - bound > tol; ++k) {
      std::array<int, 3> cut;
      for (int& c : cut) c = 1 + static_cast<int>(rng() % (n - 1));
      std::sort(cut.begin(), cut.end());
      if (cut[0] == cut[1] || cut[1] == cut[2]) continue;
      std::vector<int> t(r.order.begin(), r.order.begin() + cut[0]);
      t.insert(t.end(), r.order.begin() + cut[1], r.order.begin() + cut[2]);
      t.insert(t.end(), r.order.begin() + cut[0], r.order.begin() + cut[1]);
      t.insert(t.end(), r.order.begin() + cut[2], r.order.end());
      improveTour(d, t);
      const double c = tourCost(d, t);
      if (c < cost - tol) r.order.swap(t), cost = c;
    }
    r.lower_bound = std::min(cost, bound);  // rounding can put the bound a hair above
    r.method = "christofides+2opt+oropt+kicks";
    if (options.certify && cost - bound <= tol) {
      r.exact = true;
      r.method += " (certified by the bound)";
    } else if (n <= std::min(options.exact_max_nodes, 20)) {
      r.order = heldKarp(d, start);
      r.exact = true;
      r.method = "held-karp";
    }
  }
  // Expand the closure tour into the graph's edges.
  r.walk.nodes.push_back(start);
  for (std::size_t i = 0; i < r.order.size() && n > 1; ++i) {
    const int a = r.order[i], b = r.order[(i + 1) % r.order.size()];
    for (int e : sp[a].walkTo(g, b).edges) step(g, r.walk, e);
  }
  if (r.exact) r.lower_bound = r.walk.length;
  return r;
}

}  // namespace asf::graph
