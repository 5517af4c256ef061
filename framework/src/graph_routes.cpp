#include <asf/errors.h>
#include <asf/graph_routes.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <functional>
#include <limits>
#include <numeric>
#include <queue>
#include <stdexcept>

namespace asf::graph {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string node1(int v) { return std::to_string(v + 1); }

std::string edgeName(const Multigraph& g, int e) {
  return "edge " + std::to_string(e + 1) + " (" + node1(g.edges[e].u) + "-" +
         node1(g.edges[e].v) + ")";
}

/// Endpoints in range and lengths usable as costs; every public entry point calls it.
void checkGraph(const Multigraph& g) {
  if (g.n < 0) throw InputError("graph: negative node count");
  for (int e = 0; e < g.m(); ++e) {
    const Edge& ed = g.edges[e];
    if (ed.u < 0 || ed.u >= g.n || ed.v < 0 || ed.v >= g.n)
      throw InputError("graph: edge " + std::to_string(e + 1) + " names a node outside 1.." +
                       std::to_string(g.n));
    if (!std::isfinite(ed.length) || ed.length < 0)
      throw InputError("graph: " + edgeName(g, e) + " has length " +
                       std::to_string(ed.length) + " (must be finite and >= 0)");
  }
}

void checkNode(const Multigraph& g, int v, const char* what) {
  if (v < 0 || v >= g.n)
    throw InputError(std::string(what) + " node " + std::to_string(v + 1) +
                     " is outside 1.." + std::to_string(g.n));
}

int otherEnd(const Edge& e, int v) { return e.u == v ? e.v : e.u; }

/// Appends one step to a walk.
void step(const Multigraph& g, Walk& w, int e) {
  const int from = w.nodes.back();
  w.nodes.push_back(otherEnd(g.edges[e], from));
  w.edges.push_back(e);
  w.length += g.edges[e].length;
}

/// Hierholzer on the multiset of edges `copies` (original edge indices, repeated for
/// duplicated edges), from `start`. Returns an empty optional-like walk (nodes empty) when
/// some copy is not reachable from start; parity is the caller's business.
Walk hierholzer(const Multigraph& g, const std::vector<int>& copies, int start) {
  std::vector<std::vector<int>> adj(g.n);
  for (int c = 0; c < static_cast<int>(copies.size()); ++c) {
    const Edge& e = g.edges[copies[c]];
    adj[e.u].push_back(c);
    if (e.v != e.u) adj[e.v].push_back(c);
  }
  std::vector<char> used(copies.size(), 0);
  std::vector<std::size_t> ptr(g.n, 0);
  std::vector<std::pair<int, int>> stack{{start, -1}};  // node, copy used to arrive there
  std::vector<std::pair<int, int>> out;
  out.reserve(copies.size() + 1);
  while (!stack.empty()) {
    const int v = stack.back().first;
    std::size_t& p = ptr[v];
    while (p < adj[v].size() && used[adj[v][p]]) ++p;
    if (p == adj[v].size()) {
      out.push_back(stack.back());
      stack.pop_back();
    } else {
      const int c = adj[v][p];
      used[c] = 1;
      stack.push_back({otherEnd(g.edges[copies[c]], v), c});
    }
  }
  Walk w;
  if (out.size() != copies.size() + 1) return w;
  std::reverse(out.begin(), out.end());
  w.nodes.push_back(start);
  for (std::size_t i = 1; i < out.size(); ++i) step(g, w, copies[out[i].second]);
  return w;
}

std::string firstUnreached(const Multigraph& g, const std::vector<int>& copies, int start) {
  // Reachability from start, to name an edge the walk could not reach.
  const auto inc = g.incidence();
  std::vector<char> seen(g.n, 0);
  std::vector<int> st{start};
  seen[start] = 1;
  while (!st.empty()) {
    const int a = st.back();
    st.pop_back();
    for (int e : inc[a]) {
      const int b = otherEnd(g.edges[e], a);
      if (!seen[b]) seen[b] = 1, st.push_back(b);
    }
  }
  for (int e : copies)
    if (!seen[g.edges[e].u]) return edgeName(g, e);
  return "an edge";
}

std::vector<int> oddVertices(const Multigraph& g) {
  std::vector<int> odd;
  const auto deg = g.degrees();
  for (int v = 0; v < g.n; ++v)
    if (deg[v] % 2) odd.push_back(v);
  return odd;
}

std::string nodeList(const std::vector<int>& vs) {
  std::string s;
  for (std::size_t i = 0; i < vs.size() && i < 12; ++i) s += (i ? ", " : "") + node1(vs[i]);
  if (vs.size() > 12) s += ", ...";
  return s;
}

std::vector<int> allEdges(const Multigraph& g) {
  std::vector<int> c(g.m());
  std::iota(c.begin(), c.end(), 0);
  return c;
}

// ----------------------------------------------------------------------------------------------
// Weighted blossom (Edmonds' primal-dual, O(k^3) on a dense matrix), maximum weight matching
// on integer weights > 0. Vertex duals are kept doubled (lab) so that everything stays integer.
// Indices are 1-based; 1..n vertices, n+1..2n blossoms; 0 means "none".
class WeightedBlossom {
 public:
  explicit WeightedBlossom(int n)
      : n_(n), nx_(n), size_(2 * n + 1), g_(size_ * size_), lab_(size_, 0), match_(size_, 0),
        slack_(size_, 0), st_(size_, 0), pa_(size_, 0), s_(size_, -1), vis_(size_, 0),
        flower_from_(size_, std::vector<int>(n + 1, 0)), flower_(size_) {
    for (int u = 0; u < size_; ++u)
      for (int v = 0; v < size_; ++v) G(u, v) = {u, v, 0};
  }

  void setWeight(int u, int v, std::int64_t w) {
    G(u, v).w = w;
    G(v, u).w = w;
  }

  /// mate (1-based, 0 = single) of a maximum weight matching.
  std::vector<int> solve() {
    nx_ = n_;
    std::int64_t wmax = 0;
    for (int u = 1; u <= n_; ++u) {
      st_[u] = u;
      flower_[u].clear();
      for (int v = 1; v <= n_; ++v) {
        flower_from_[u][v] = (u == v ? u : 0);
        wmax = std::max(wmax, G(u, v).w);
      }
    }
    for (int u = 1; u <= n_; ++u) lab_[u] = wmax;
    while (augmentOnce()) {
    }
    return std::vector<int>(match_.begin(), match_.begin() + n_ + 1);
  }

 private:
  struct E {
    int u, v;
    std::int64_t w;
  };
  E& G(int u, int v) { return g_[static_cast<std::size_t>(u) * size_ + v]; }

  std::int64_t delta(const E& e) { return lab_[e.u] + lab_[e.v] - G(e.u, e.v).w * 2; }

  void updateSlack(int u, int x) {
    if (!slack_[x] || delta(G(u, x)) < delta(G(slack_[x], x))) slack_[x] = u;
  }
  void setSlack(int x) {
    slack_[x] = 0;
    for (int u = 1; u <= n_; ++u)
      if (G(u, x).w > 0 && st_[u] != x && s_[st_[u]] == 0) updateSlack(u, x);
  }
  void queuePush(int x) {
    if (x <= n_) {
      queue_.push_back(x);
    } else {
      for (int y : flower_[x]) queuePush(y);
    }
  }
  void setTop(int x, int b) {
    st_[x] = b;
    if (x > n_)
      for (int y : flower_[x]) setTop(y, b);
  }
  /// Position of sub-blossom xr in blossom b, orienting the cycle so it is even.
  int evenPosition(int b, int xr) {
    auto& f = flower_[b];
    const int pr = static_cast<int>(std::find(f.begin(), f.end(), xr) - f.begin());
    if (pr % 2 == 1) {
      std::reverse(f.begin() + 1, f.end());
      return static_cast<int>(f.size()) - pr;
    }
    return pr;
  }
  void setMatch(int u, int v) {
    match_[u] = G(u, v).v;
    if (u <= n_) return;
    const E e = G(u, v);
    const int xr = flower_from_[u][e.u];
    const int pr = evenPosition(u, xr);
    for (int i = 0; i < pr; ++i) setMatch(flower_[u][i], flower_[u][i ^ 1]);
    setMatch(xr, v);
    std::rotate(flower_[u].begin(), flower_[u].begin() + pr, flower_[u].end());
  }
  void augment(int u, int v) {
    for (;;) {
      const int xnv = st_[match_[u]];
      setMatch(u, v);
      if (!xnv) return;
      setMatch(xnv, st_[pa_[xnv]]);
      u = st_[pa_[xnv]];
      v = xnv;
    }
  }
  int lowestCommonAncestor(int u, int v) {
    for (++stamp_; u || v; std::swap(u, v)) {
      if (u == 0) continue;
      if (vis_[u] == stamp_) return u;
      vis_[u] = stamp_;
      u = st_[match_[u]];
      if (u) u = st_[pa_[u]];
    }
    return 0;
  }
  void addBlossom(int u, int lca, int v) {
    int b = n_ + 1;
    while (b <= nx_ && st_[b]) ++b;
    if (b > nx_) ++nx_;
    lab_[b] = 0;
    s_[b] = 0;
    match_[b] = match_[lca];
    auto& f = flower_[b];
    f.clear();
    f.push_back(lca);
    for (int x = u, y; x != lca; x = st_[pa_[y]]) {
      f.push_back(x);
      f.push_back(y = st_[match_[x]]);
      queuePush(y);
    }
    std::reverse(f.begin() + 1, f.end());
    for (int x = v, y; x != lca; x = st_[pa_[y]]) {
      f.push_back(x);
      f.push_back(y = st_[match_[x]]);
      queuePush(y);
    }
    setTop(b, b);
    for (int x = 1; x <= nx_; ++x) G(b, x).w = G(x, b).w = 0;
    for (int x = 1; x <= n_; ++x) flower_from_[b][x] = 0;
    for (int xs : f) {
      for (int x = 1; x <= nx_; ++x)
        if (G(b, x).w == 0 || delta(G(xs, x)) < delta(G(b, x))) {
          G(b, x) = G(xs, x);
          G(x, b) = G(x, xs);
        }
      for (int x = 1; x <= n_; ++x)
        if (flower_from_[xs][x]) flower_from_[b][x] = xs;
    }
    setSlack(b);
  }
  void expandBlossom(int b) {
    for (int x : flower_[b]) setTop(x, x);
    const int xr = flower_from_[b][G(b, pa_[b]).u];
    const int pr = evenPosition(b, xr);
    for (int i = 0; i < pr; i += 2) {
      const int xs = flower_[b][i], xns = flower_[b][i + 1];
      pa_[xs] = G(xns, xs).u;
      s_[xs] = 1;
      s_[xns] = 0;
      slack_[xs] = 0;
      setSlack(xns);
      queuePush(xns);
    }
    s_[xr] = 1;
    pa_[xr] = pa_[b];
    for (std::size_t i = pr + 1; i < flower_[b].size(); ++i) {
      const int xs = flower_[b][i];
      s_[xs] = -1;
      setSlack(xs);
    }
    st_[b] = 0;
  }
  /// A tight edge from an outer (S) vertex: grow the tree, augment, or shrink a blossom.
  bool onTightEdge(const E& e) {
    const int u = st_[e.u], v = st_[e.v];
    if (s_[v] == -1) {
      pa_[v] = e.u;
      s_[v] = 1;
      const int nu = st_[match_[v]];
      slack_[v] = slack_[nu] = 0;
      s_[nu] = 0;
      queuePush(nu);
    } else if (s_[v] == 0) {
      const int lca = lowestCommonAncestor(u, v);
      if (!lca) {
        augment(u, v);
        augment(v, u);
        return true;
      }
      addBlossom(u, lca, v);
    }
    return false;
  }
  /// One stage: true when the matching grew.
  bool augmentOnce() {
    std::fill(s_.begin(), s_.begin() + nx_ + 1, -1);
    std::fill(slack_.begin(), slack_.begin() + nx_ + 1, 0);
    queue_.clear();
    for (int x = 1; x <= nx_; ++x)
      if (st_[x] == x && !match_[x]) {
        pa_[x] = 0;
        s_[x] = 0;
        queuePush(x);
      }
    if (queue_.empty()) return false;
    // Each dual adjustment labels a blossom, makes one, expands one or augments: O(k) per
    // stage. The guard turns a bug into an error instead of a hang.
    for (long rounds = 0;; ++rounds) {
      if (rounds > 8L * size_ + 64) throw std::logic_error("blossom: stage does not terminate");
      while (!queue_.empty()) {
        const int u = queue_.front();
        queue_.pop_front();
        if (s_[st_[u]] == 1) continue;
        for (int v = 1; v <= n_; ++v)
          if (G(u, v).w > 0 && st_[u] != st_[v]) {
            if (delta(G(u, v)) == 0) {
              if (onTightEdge(G(u, v))) return true;
            } else {
              updateSlack(u, st_[v]);
            }
          }
      }
      std::int64_t d = std::numeric_limits<std::int64_t>::max();
      for (int b = n_ + 1; b <= nx_; ++b)
        if (st_[b] == b && s_[b] == 1) d = std::min(d, lab_[b] / 2);
      for (int x = 1; x <= nx_; ++x)
        if (st_[x] == x && slack_[x]) {
          if (s_[x] == -1)
            d = std::min(d, delta(G(slack_[x], x)));
          else if (s_[x] == 0)
            d = std::min(d, delta(G(slack_[x], x)) / 2);
        }
      for (int u = 1; u <= n_; ++u) {
        if (s_[st_[u]] == 0) {
          if (lab_[u] <= d) return false;  // no augmenting path gains weight any more
          lab_[u] -= d;
        } else if (s_[st_[u]] == 1) {
          lab_[u] += d;
        }
      }
      for (int b = n_ + 1; b <= nx_; ++b)
        if (st_[b] == b) {
          if (s_[st_[b]] == 0)
            lab_[b] += d * 2;
          else if (s_[st_[b]] == 1)
            lab_[b] -= d * 2;
        }
      queue_.clear();
      for (int x = 1; x <= nx_; ++x)
        if (st_[x] == x && slack_[x] && st_[slack_[x]] != x && delta(G(slack_[x], x)) == 0)
          if (onTightEdge(G(slack_[x], x))) return true;
      for (int b = n_ + 1; b <= nx_; ++b)
        if (st_[b] == b && s_[b] == 1 && lab_[b] == 0) expandBlossom(b);
    }
  }

  int n_, nx_, size_;
  std::vector<E> g_;
  std::vector<std::int64_t> lab_;
  std::vector<int> match_, slack_, st_, pa_, s_, vis_;
  int stamp_ = 0;
  std::vector<std::vector<int>> flower_from_, flower_;
  std::deque<int> queue_;
};

std::vector<int> matchingBlossom(const std::vector<std::vector<double>>& cost) {
  const int k = static_cast<int>(cost.size());
  double cmax = 0;
  for (const auto& row : cost)
    for (double c : row) cmax = std::max(cmax, c);
  std::vector<int> mate(k, -1);
  if (cmax <= 0) {  // every perfect matching is optimal
    for (int i = 0; i + 1 < k; i += 2) mate[i] = i + 1, mate[i + 1] = i;
    return mate;
  }
  // Integer costs: a power of two keeps integers and dyadic values exact.
  const double scale = std::ldexp(1.0, 40 - std::ilogb(cmax) - 1);
  std::vector<std::vector<std::int64_t>> ci(k, std::vector<std::int64_t>(k, 0));
  std::int64_t imax = 0;
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) {
      ci[i][j] = std::llround(cost[i][j] * scale);
      imax = std::max(imax, ci[i][j]);
    }
  // Maximum weight of W - c: a big enough W makes every maximum weight matching perfect
  // (any perfect one outweighs any smaller one), hence the minimum cost perfect matching.
  const std::int64_t W = (static_cast<std::int64_t>(k) / 2 + 1) * imax + 1;
  WeightedBlossom b(k);
  for (int i = 0; i < k; ++i)
    for (int j = i + 1; j < k; ++j) b.setWeight(i + 1, j + 1, W - ci[i][j]);
  const auto m = b.solve();
  for (int i = 0; i < k; ++i) {
    if (m[i + 1] == 0) throw std::logic_error("blossom: matching not perfect");
    mate[i] = m[i + 1] - 1;
  }
  return mate;
}

std::vector<int> matchingDp(const std::vector<std::vector<double>>& cost) {
  const int k = static_cast<int>(cost.size());
  // best[mask]: cheapest perfect matching of the vertices in mask (even popcount only).
  const std::size_t full = (std::size_t{1} << k) - 1;
  std::vector<double> best(full + 1, kInf);
  best[0] = 0;
  for (std::size_t mask = 1; mask <= full; ++mask) {
    if (__builtin_popcountll(mask) % 2) continue;
    const int i = __builtin_ctzll(mask);
    double b = kInf;
    for (int j = i + 1; j < k; ++j)
      if (mask >> j & 1) b = std::min(b, cost[i][j] + best[mask ^ (std::size_t{1} << i) ^ (std::size_t{1} << j)]);
    best[mask] = b;
  }
  std::vector<int> mate(k, -1);
  std::size_t mask = full;
  while (mask) {
    const int i = __builtin_ctzll(mask);
    int bj = -1;
    for (int j = i + 1; j < k; ++j)
      if (mask >> j & 1) {
        const double c = cost[i][j] + best[mask ^ (std::size_t{1} << i) ^ (std::size_t{1} << j)];
        if (c == best[mask]) {
          bj = j;
          break;
        }
      }
    if (bj < 0) throw std::logic_error("matching DP: no pair reproduces the optimum");
    mate[i] = bj;
    mate[bj] = i;
    mask ^= (std::size_t{1} << i) | (std::size_t{1} << bj);
  }
  return mate;
}

}  // namespace

// ----------------------------------------------------------------------------------------------
// Walk

std::vector<int> Walk::traversals(int m) const {
  std::vector<int> x(m, 0);
  for (int e : edges)
    if (e >= 0 && e < m) ++x[e];
  return x;
}

std::vector<double> Walk::weights(int m) const {
  const auto x = traversals(m);
  return std::vector<double>(x.begin(), x.end());
}

std::string walkError(const Multigraph& g, const Walk& w) {
  if (w.nodes.empty()) return "walk has no node";
  if (w.nodes.size() != w.edges.size() + 1)
    return "walk has " + std::to_string(w.nodes.size()) + " nodes for " +
           std::to_string(w.edges.size()) + " edges";
  for (int v : w.nodes)
    if (v < 0 || v >= g.n) return "walk names node " + std::to_string(v) + " (0-based) outside the graph";
  double len = 0;
  for (std::size_t i = 0; i < w.edges.size(); ++i) {
    const int e = w.edges[i];
    if (e < 0 || e >= g.m()) return "step " + std::to_string(i) + " names edge " + std::to_string(e) + " outside the graph";
    const Edge& ed = g.edges[e];
    const int a = w.nodes[i], b = w.nodes[i + 1];
    if (!((ed.u == a && ed.v == b) || (ed.u == b && ed.v == a)))
      return "step " + std::to_string(i) + ": " + edgeName(g, e) + " does not join " + node1(a) +
             " and " + node1(b);
    len += ed.length;
  }
  if (std::abs(len - w.length) > 1e-9 * std::max(1.0, std::abs(len)))
    return "walk length " + std::to_string(w.length) + " but its edges sum to " + std::to_string(len);
  return "";
}

bool coversAllEdges(const Multigraph& g, const Walk& w) {
  const auto x = w.traversals(g.m());
  return std::all_of(x.begin(), x.end(), [](int c) { return c > 0; });
}

bool visitsAllNodes(const Multigraph& g, const Walk& w) {
  std::vector<char> seen(g.n, 0);
  for (int v : w.nodes)
    if (v >= 0 && v < g.n) seen[v] = 1;
  return std::all_of(seen.begin(), seen.end(), [](char c) { return c != 0; });
}

// ----------------------------------------------------------------------------------------------
// Euler

bool hasEulerCircuit(const Multigraph& g) {
  checkGraph(g);
  if (!oddVertices(g).empty()) return false;
  if (g.m() == 0) return true;
  return !hierholzer(g, allEdges(g), g.edges[0].u).nodes.empty();
}

Walk eulerCircuit(const Multigraph& g, int start) {
  checkGraph(g);
  checkNode(g, start, "start");
  const auto odd = oddVertices(g);
  if (!odd.empty())
    throw Error("no Euler circuit: " + std::to_string(odd.size()) +
                " nodes of odd degree (" + nodeList(odd) + ")");
  const auto all = allEdges(g);
  Walk w = hierholzer(g, all, start);
  if (w.nodes.empty())
    throw Error("no Euler circuit from node " + node1(start) + ": " +
                firstUnreached(g, all, start) + " is not reachable from it");
  return w;
}

Walk eulerTrail(const Multigraph& g, int start) {
  checkGraph(g);
  const auto odd = oddVertices(g);
  if (odd.size() > 2)
    throw Error("no Euler trail: " + std::to_string(odd.size()) + " nodes of odd degree (" +
                nodeList(odd) + "), at most 2 allowed");
  if (start < 0) {
    // The lower odd node, else the first node with an edge (node 0 for an edgeless graph).
    start = 0;
    if (!odd.empty()) {
      start = odd.front();
    } else {
      const auto deg = g.degrees();
      for (int v = g.n - 1; v >= 0; --v)
        if (deg[v] > 0) start = v;
    }
  }
  checkNode(g, start, "start");
  if (odd.size() == 2 && start != odd[0] && start != odd[1])
    throw Error("no Euler trail from node " + node1(start) + ": a trail must start at an odd node (" +
                nodeList(odd) + ")");
  const auto all = allEdges(g);
  Walk w = hierholzer(g, all, start);
  if (w.nodes.empty())
    throw Error("no Euler trail from node " + node1(start) + ": " +
                firstUnreached(g, all, start) + " is not reachable from it");
  return w;
}

// ----------------------------------------------------------------------------------------------
// Shortest paths

Walk ShortestPaths::walkTo(const Multigraph& g, int target) const {
  if (target < 0 || target >= static_cast<int>(dist.size()) || !std::isfinite(dist[target]))
    throw Error("no path from node " + node1(source) + " to node " + node1(target));
  std::vector<int> rev;
  for (int v = target; v != source;) {
    const int e = pred_edge[v];
    rev.push_back(e);
    v = otherEnd(g.edges[e], v);
  }
  Walk w;
  w.nodes.push_back(source);
  for (auto it = rev.rbegin(); it != rev.rend(); ++it) step(g, w, *it);
  return w;
}

ShortestPaths dijkstra(const Multigraph& g, int source) {
  checkGraph(g);
  checkNode(g, source, "source");
  const auto inc = g.incidence();
  ShortestPaths sp;
  sp.source = source;
  sp.dist.assign(g.n, kInf);
  sp.pred_edge.assign(g.n, -1);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> pq;
  sp.dist[source] = 0;
  pq.push({0, source});
  while (!pq.empty()) {
    const auto [d, a] = pq.top();
    pq.pop();
    if (d > sp.dist[a]) continue;
    for (int e : inc[a]) {
      const int b = otherEnd(g.edges[e], a);
      const double nd = d + g.edges[e].length;
      if (nd < sp.dist[b]) {
        sp.dist[b] = nd;
        sp.pred_edge[b] = e;
        pq.push({nd, b});
      }
    }
  }
  return sp;
}

// ----------------------------------------------------------------------------------------------
// Matching

std::vector<int> minWeightPerfectMatching(const std::vector<std::vector<double>>& cost,
                                          MatchingMethod method) {
  const int k = static_cast<int>(cost.size());
  if (k % 2) throw InputError("matching: odd number of vertices (" + std::to_string(k) + ")");
  for (int i = 0; i < k; ++i) {
    if (static_cast<int>(cost[i].size()) != k) throw InputError("matching: cost matrix not square");
    for (int j = 0; j < k; ++j) {
      if (!std::isfinite(cost[i][j]) || cost[i][j] < 0)
        throw InputError("matching: cost(" + std::to_string(i) + "," + std::to_string(j) +
                         ") must be finite and >= 0");
      if (cost[i][j] != cost[j][i]) throw InputError("matching: cost matrix not symmetric");
    }
  }
  if (k == 0) return {};
  if (method == MatchingMethod::Auto)
    method = k <= 12 ? MatchingMethod::BitmaskDP : MatchingMethod::Blossom;
  if (method == MatchingMethod::BitmaskDP) {
    if (k > 22)
      throw InputError("matching: the bitmask DP is limited to 22 vertices (" +
                       std::to_string(k) + " given); use the blossom");
    return matchingDp(cost);
  }
  if (k > 2000)
    throw InputError("matching: the dense blossom is limited to 2000 vertices (" +
                     std::to_string(k) + " given)");
  return matchingBlossom(cost);
}

// ----------------------------------------------------------------------------------------------
// Chinese postman

PostmanResult chinesePostman(const Multigraph& g, int start, int end, MatchingMethod method) {
  checkGraph(g);
  checkNode(g, start, "start");
  if (end >= 0) checkNode(g, end, "end");
  if (end < 0) end = start;
  PostmanResult r;
  r.duplicates.assign(g.m(), 0);
  for (const Edge& e : g.edges) r.edges_length += e.length;

  // Vertices whose parity is wrong for a closed (or start -> end) walk.
  std::vector<char> odd(g.n, 0);
  for (int v : oddVertices(g)) odd[v] = 1;
  if (end != start) odd[start] ^= 1, odd[end] ^= 1;
  for (int v = 0; v < g.n; ++v)
    if (odd[v]) r.odd_vertices.push_back(v);

  const ShortestPaths from_start = dijkstra(g, start);
  for (int e = 0; e < g.m(); ++e)
    if (!std::isfinite(from_start.dist[g.edges[e].u]))
      throw Error("no postman walk from node " + node1(start) + ": " + edgeName(g, e) +
                  " is not reachable from it");
  if (!std::isfinite(from_start.dist[end]))
    throw Error("no postman walk: node " + node1(end) + " is not reachable from node " + node1(start));

  const int k = static_cast<int>(r.odd_vertices.size());
  std::vector<ShortestPaths> sp;
  sp.reserve(k);
  for (int v : r.odd_vertices) sp.push_back(dijkstra(g, v));
  std::vector<std::vector<double>> cost(k, std::vector<double>(k, 0));
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) cost[i][j] = sp[i].dist[r.odd_vertices[j]];
  // Dijkstra from i and from j may differ in the last bits; the matching wants symmetry.
  for (int i = 0; i < k; ++i)
    for (int j = i + 1; j < k; ++j) cost[i][j] = cost[j][i] = std::min(cost[i][j], cost[j][i]);
  const auto mate = minWeightPerfectMatching(cost, method);

  std::vector<int> copies = allEdges(g);
  for (int i = 0; i < k; ++i) {
    if (mate[i] < i) continue;
    const Walk p = sp[i].walkTo(g, r.odd_vertices[mate[i]]);
    for (int e : p.edges) {
      ++r.duplicates[e];
      copies.push_back(e);
    }
  }
  r.walk = hierholzer(g, copies, start);
  if (r.walk.nodes.empty() || r.walk.nodes.back() != end)
    throw std::logic_error("chinesePostman: augmented graph not Eulerian");
  r.added_length = r.walk.length - r.edges_length;
  return r;
}

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
    if (mate[i] > static_cast<int>(i))
      h.edges.push_back({odd[i], odd[mate[i]], c[i][mate[i]]});
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
double heldKarpLowerBound(const std::vector<std::vector<double>>& d, double upper,
                          int iterations) {
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
      if (m1 < 0 || dp[special][v] < dp[special][m1]) m2 = m1, m1 = v;
      else if (m2 < 0 || dp[special][v] < dp[special][m2]) m2 = v;
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
  if (!g.connected())
    throw Error("no TSP walk: the graph is not connected");
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

// ----------------------------------------------------------------------------------------------
// On-line explorers

int tarryChoose(const std::vector<TarryCandidate>& candidates, const TarryOptions& options,
                std::mt19937& rng) {
  std::vector<const TarryCandidate*> allowed;
  for (const auto& c : candidates)
    if (!c.traversed_outward && !c.entrance) allowed.push_back(&c);
  if (allowed.empty()) {
    for (const auto& c : candidates)
      if (c.entrance && !c.traversed_outward) return c.edge;  // the last resort
    return -1;
  }
  if (options.loop_closing_first &&
      std::any_of(allowed.begin(), allowed.end(), [](auto* c) { return c->leads_to_visited; }))
    allowed.erase(std::remove_if(allowed.begin(), allowed.end(),
                                 [](auto* c) { return !c->leads_to_visited; }),
                  allowed.end());
  if (options.nearest_first) {
    double best = kInf;
    for (auto* c : allowed) best = std::min(best, c->cost);
    const double tol = 1e-12 * std::max(1.0, std::abs(best));
    allowed.erase(std::remove_if(allowed.begin(), allowed.end(),
                                 [&](auto* c) { return c->cost > best + tol; }),
                  allowed.end());
  }
  if (allowed.size() == 1) return allowed.front()->edge;
  return allowed[rng() % allowed.size()]->edge;
}

namespace {

/// Bookkeeping shared by the explorers: the walk, coverage and the step counts.
struct Tracker {
  const Multigraph& g;
  Walk w;
  std::vector<int> count;
  std::vector<char> seen;
  int uncovered, unseen;
  ExploreResult r;

  Tracker(const Multigraph& graph, int start)
      : g(graph), count(graph.m(), 0), seen(graph.n, 0), uncovered(graph.m()), unseen(graph.n - 1) {
    w.nodes.push_back(start);
    seen[start] = 1;
    if (uncovered == 0) r.steps_to_cover_edges = 0;
    if (unseen == 0) r.steps_to_visit_nodes = 0;
  }
  int at() const { return w.nodes.back(); }
  void go(int e, bool bounded = true) {
    if (bounded && w.steps() > 2 * g.m() + 2)  // the explorers walk each edge at most twice
      throw std::logic_error("explorer: walk longer than twice the edges");
    step(g, w, e);
    if (count[e]++ == 0 && --uncovered == 0) r.steps_to_cover_edges = w.steps();
    if (!seen[at()]) {
      seen[at()] = 1;
      if (--unseen == 0) r.steps_to_visit_nodes = w.steps();
    }
  }
  ExploreResult finish() {
    r.covered_all_edges = uncovered == 0;
    r.visited_all_nodes = unseen == 0;
    r.walk = std::move(w);
    return r;
  }
};

}  // namespace

ExploreResult tarry(const Multigraph& g, int start, const TarryOptions& options,
                    std::uint32_t seed) {
  checkGraph(g);
  checkNode(g, start, "start");
  std::mt19937 rng(seed);
  const auto inc = g.incidence();
  // Darts: 2e leaves edges[e].u, 2e+1 leaves edges[e].v (both leave the node of a self-loop).
  std::vector<char> dart_used(2 * g.m(), 0);
  std::vector<int> entrance(g.n, -1);
  // What the explorer knows: edges at visited nodes; never-traversed ones among them.
  std::vector<char> known(g.m(), 0);
  int known_untraversed = 0;
  Tracker tr(g, start);
  auto arrive = [&](int v) {
    for (int e : inc[v])
      if (!known[e]) known[e] = 1, ++known_untraversed;
  };
  arrive(start);
  std::vector<TarryCandidate> cands;
  for (;;) {
    if (options.stop_when_covered && known_untraversed == 0) break;
    const int cur = tr.at();
    cands.clear();
    for (int e : inc[cur]) {
      const Edge& ed = g.edges[e];
      TarryCandidate c;
      c.edge = e;
      c.traversed_outward = ed.u == ed.v ? (dart_used[2 * e] && dart_used[2 * e + 1])
                                         : dart_used[ed.u == cur ? 2 * e : 2 * e + 1];
      c.entrance = e == entrance[cur];
      c.leads_to_visited = tr.seen[otherEnd(ed, cur)] != 0;
      c.cost = ed.length;
      cands.push_back(c);
    }
    const int e = tarryChoose(cands, options, rng);
    if (e < 0) break;
    const Edge& ed = g.edges[e];
    const int d = ed.u == ed.v ? (dart_used[2 * e] ? 2 * e + 1 : 2 * e)
                               : (ed.u == cur ? 2 * e : 2 * e + 1);
    dart_used[d] = 1;
    if (tr.count[e] == 0) --known_untraversed;
    const int next = otherEnd(ed, cur);
    const bool first_visit = !tr.seen[next];
    tr.go(e);
    if (first_visit) {
      entrance[next] = e;
      arrive(next);
    }
  }
  return tr.finish();
}

ExploreResult tremaux(const Multigraph& g, int start, std::uint32_t seed) {
  checkGraph(g);
  checkNode(g, start, "start");
  std::mt19937 rng(seed);
  const auto inc = g.incidence();
  std::vector<int> entrance(g.n, -1);
  Tracker tr(g, start);
  int turn_back = -1;  // edge to walk back at once (arrived at an old node by a new edge)
  std::vector<int> fresh;
  for (;;) {
    const int cur = tr.at();
    int e = turn_back;
    if (e < 0) {
      fresh.clear();
      for (int f : inc[cur])
        if (tr.count[f] == 0) fresh.push_back(f);
      if (!fresh.empty())
        e = fresh.size() == 1 ? fresh[0] : fresh[rng() % fresh.size()];
      else if (entrance[cur] >= 0 && tr.count[entrance[cur]] < 2)
        e = entrance[cur];
      else
        break;
    }
    const int next = otherEnd(g.edges[e], cur);
    const bool old = tr.seen[next] != 0;
    tr.go(e);
    turn_back = -1;
    if (!old)
      entrance[next] = e;
    else if (tr.count[e] == 1)
      turn_back = e;
  }
  return tr.finish();
}

ExploreResult dfsExplore(const Multigraph& g, int start, std::uint32_t seed) {
  checkGraph(g);
  checkNode(g, start, "start");
  std::mt19937 rng(seed);
  const auto inc = g.incidence();
  std::vector<int> parent(g.n, -1);
  Tracker tr(g, start);
  std::vector<int> forward;
  for (;;) {
    const int cur = tr.at();
    forward.clear();
    for (int e : inc[cur])
      if (!tr.seen[otherEnd(g.edges[e], cur)]) forward.push_back(e);
    if (!forward.empty()) {
      const int e = forward.size() == 1 ? forward[0] : forward[rng() % forward.size()];
      parent[otherEnd(g.edges[e], cur)] = e;
      tr.go(e);
    } else if (cur != start) {
      tr.go(parent[cur]);
    } else {
      break;
    }
  }
  return tr.finish();
}

// ----------------------------------------------------------------------------------------------
// Dispatch

namespace {
const std::pair<RouteAlgorithm, const char*> kAlgorithmNames[] = {
    {RouteAlgorithm::Euler, "euler"},     {RouteAlgorithm::ChinesePostman, "cpp"},
    {RouteAlgorithm::Tsp, "tsp"},         {RouteAlgorithm::Tarry, "tarry"},
    {RouteAlgorithm::TarryModified, "tarry_modified"},
    {RouteAlgorithm::Tremaux, "tremaux"}, {RouteAlgorithm::Dfs, "dfs"},
};
}  // namespace

RouteAlgorithm parseRouteAlgorithm(const std::string& name) {
  std::string all;
  for (const auto& [a, s] : kAlgorithmNames) {
    if (name == s) return a;
    all += (all.empty() ? "" : ", ") + std::string(s);
  }
  throw InputError("unknown route algorithm '" + name + "' (one of " + all + ")");
}

std::string routeAlgorithmName(RouteAlgorithm a) {
  for (const auto& [b, s] : kAlgorithmNames)
    if (a == b) return s;
  return "?";
}

RouteResult computeRoute(const Multigraph& g, RouteAlgorithm algorithm, int start,
                         std::uint32_t seed, int end) {
  RouteResult r;
  r.algorithm = algorithm;
  if (end >= 0 && algorithm != RouteAlgorithm::Euler &&
      algorithm != RouteAlgorithm::ChinesePostman)
    throw InputError("an end node applies to euler and cpp only");
  auto fromExplore = [&](ExploreResult x) { r.walk = std::move(x.walk); };
  switch (algorithm) {
    case RouteAlgorithm::Euler:
      if (end < 0) {
        r.walk = eulerCircuit(g, start);
      } else {
        r.walk = eulerTrail(g, start);
        if (r.walk.nodes.back() != end)
          throw Error("no Euler trail from node " + node1(start) + " to node " + node1(end) +
                      " (it would end at node " + node1(r.walk.nodes.back()) + ")");
      }
      r.exact = true;
      r.lower_bound = r.walk.length;
      break;
    case RouteAlgorithm::ChinesePostman:
      r.walk = chinesePostman(g, start, end).walk;
      r.exact = true;
      r.lower_bound = r.walk.length;
      break;
    case RouteAlgorithm::Tsp: {
      TspResult t = travelingSalesman(g, start);
      r.walk = std::move(t.walk);
      r.exact = t.exact;
      r.lower_bound = t.lower_bound;
      break;
    }
    case RouteAlgorithm::Tarry: fromExplore(tarry(g, start, TarryOptions{}, seed)); break;
    case RouteAlgorithm::TarryModified:
      fromExplore(tarry(g, start, TarryOptions::modified(), seed));
      break;
    case RouteAlgorithm::Tremaux: fromExplore(tremaux(g, start, seed)); break;
    case RouteAlgorithm::Dfs: fromExplore(dfsExplore(g, start, seed)); break;
  }
  // Coverage along the walk, the same way for every algorithm.
  Tracker tr(g, r.walk.nodes.front());
  for (int e : r.walk.edges) tr.go(e, /*bounded=*/false);
  const ExploreResult x = tr.finish();
  r.covered_all_edges = x.covered_all_edges;
  r.visited_all_nodes = x.visited_all_nodes;
  r.steps_to_cover_edges = x.steps_to_cover_edges;
  r.steps_to_visit_nodes = x.steps_to_visit_nodes;
  return r;
}

}  // namespace asf::graph
