// Minimum-weight perfect matching on a complete graph (the Chinese postman's odd nodes,
// Christofides' odd tree nodes): Edmonds' weighted blossom, O(k^3), and an exact bitmask DP
// for small k.
#include <asf/errors.h>
#include <asf/graph/routes.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <numeric>
#include <vector>

namespace asf::graph {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// ----------------------------------------------------------------------------------------------
// Weighted blossom (Edmonds' primal-dual, O(k^3) on a dense matrix), maximum weight matching
// on integer weights > 0. Vertex duals are kept doubled (lab) so that everything stays integer.
// Indices are 1-based; 1..n vertices, n+1..2n blossoms; 0 means "none".
class WeightedBlossom {
 public:
  explicit WeightedBlossom(int n)
      : n_(n),
        nx_(n),
        size_(2 * n + 1),
        g_(size_ * size_),
        lab_(size_, 0),
        match_(size_, 0),
        slack_(size_, 0),
        st_(size_, 0),
        pa_(size_, 0),
        s_(size_, -1),
        vis_(size_, 0),
        flower_from_(size_, std::vector<int>(n + 1, 0)),
        flower_(size_) {
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
      if (mask >> j & 1)
        b = std::min(b, cost[i][j] + best[mask ^ (std::size_t{1} << i) ^ (std::size_t{1} << j)]);
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
      throw InputError("matching: the bitmask DP is limited to 22 vertices (" + std::to_string(k) +
                       " given); use the blossom");
    return matchingDp(cost);
  }
  if (k > 2000)
    throw InputError("matching: the dense blossom is limited to 2000 vertices (" +
                     std::to_string(k) + " given)");
  return matchingBlossom(cost);
}

}  // namespace asf::graph
