// Alternative routes in a weighted undirected multigraph: Yen's K shortest simple paths and
// the penalty method. Generic over vertex and edge indices; the path search (path_search.cpp)
// runs them on its reduced graph.
#include <asf/errors.h>
#include <asf/planning/expected_uncertainty.h>

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>
#include <set>
#include <string>

namespace asf::planning {

namespace {

using EdgePath = std::vector<std::size_t>;

/// One run of Yen's algorithm: the adjacency, and the vertices and edges a spur search may not
/// use.
class YenSearch {
 public:
  YenSearch(std::size_t n, const std::vector<WeightedEdge>& e, std::uint32_t t)
      : n_(n), e_(e), t_(t), adj_(n), banned_v_(n, 0), banned_e_(e.size(), 0) {
    for (std::size_t i = 0; i < e.size(); ++i) {
      if (e[i].a >= n || e[i].b >= n)
        throw Error("kShortestSimplePaths: edge " + std::to_string(i) +
                    " names a vertex >= " + std::to_string(n));
      if (!(e[i].w >= 0)) throw Error("kShortestSimplePaths: negative or NaN weight");
      if (e[i].a == e[i].b) continue;  // never on a simple path
      adj_[e[i].a].emplace_back(e[i].b, i);
      adj_[e[i].b].emplace_back(e[i].a, i);
    }
  }

  double cost(const EdgePath& p) const {
    double c = 0;
    for (std::size_t i : p) c += e_[i].w;
    return c;
  }

  /// Dijkstra from src to t avoiding banned vertices and edges; ties by (distance, vertex).
  bool shortest(std::uint32_t src, EdgePath& out) const {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    std::vector<double> dist(n_, kInf);
    std::vector<std::size_t> via(n_, 0);
    using Item = std::pair<double, std::uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
    dist[src] = 0;
    open.emplace(0.0, src);
    while (!open.empty()) {
      const auto [d, v] = open.top();
      open.pop();
      if (d > dist[v]) continue;
      if (v == t_) break;
      for (const auto& [w, i] : adj_[v]) {
        if (banned_v_[w] || banned_e_[i]) continue;
        if (d + e_[i].w < dist[w]) {
          dist[w] = d + e_[i].w;
          via[w] = i;
          open.emplace(dist[w], w);
        }
      }
    }
    out.clear();
    if (dist[t_] == kInf) return false;
    for (std::uint32_t v = t_; v != src;) {
      out.push_back(via[v]);
      v = e_[via[v]].a == v ? e_[via[v]].b : e_[via[v]].a;
    }
    std::reverse(out.begin(), out.end());
    return true;
  }

  /// Root: prev's first i edges; spur vertex verts[i]. Bans the root's vertices (simple paths)
  /// and the next edge of every accepted path sharing this root.
  void banForSpur(const std::vector<EdgePath>& accepted, const EdgePath& prev,
                  const std::vector<std::uint32_t>& verts, std::size_t i) {
    std::fill(banned_v_.begin(), banned_v_.end(), 0);
    std::fill(banned_e_.begin(), banned_e_.end(), 0);
    for (std::size_t j = 0; j < i; ++j) banned_v_[verts[j]] = 1;
    for (const EdgePath& p : accepted)
      if (p.size() > i && std::equal(p.begin(), p.begin() + static_cast<long>(i), prev.begin()))
        banned_e_[p[i]] = 1;
  }

  /// The vertices of an edge path from s.
  std::vector<std::uint32_t> vertices(std::uint32_t s, const EdgePath& p) const {
    std::vector<std::uint32_t> verts{s};
    for (std::size_t i : p) verts.push_back(e_[i].a == verts.back() ? e_[i].b : e_[i].a);
    return verts;
  }

 private:
  std::size_t n_;
  const std::vector<WeightedEdge>& e_;
  std::uint32_t t_;
  std::vector<std::vector<std::pair<std::uint32_t, std::size_t>>> adj_;
  std::vector<char> banned_v_, banned_e_;
};

struct Candidate {
  double cost;
  EdgePath path;
  bool operator<(const Candidate& o) const {
    if (cost != o.cost) return cost < o.cost;
    if (path.size() != o.path.size()) return path.size() < o.path.size();
    return path < o.path;
  }
};

}  // namespace

std::vector<std::vector<std::size_t>> kShortestSimplePaths(std::size_t n,
                                                           const std::vector<WeightedEdge>& e,
                                                           std::uint32_t s, std::uint32_t t,
                                                           std::size_t k) {
  YenSearch yen(n, e, t);
  std::vector<EdgePath> A;
  if (s >= n || t >= n || k == 0) return A;
  if (s == t) {
    A.emplace_back();
    return A;
  }
  EdgePath first;
  if (!yen.shortest(s, first)) return A;
  A.push_back(first);
  std::set<EdgePath> seen{first};
  std::set<Candidate> B;
  while (A.size() < k) {
    const EdgePath prev = A.back();
    const std::vector<std::uint32_t> verts = yen.vertices(s, prev);
    for (std::size_t i = 0; i < prev.size(); ++i) {
      yen.banForSpur(A, prev, verts, i);
      EdgePath spur;
      if (!yen.shortest(verts[i], spur)) continue;
      EdgePath total(prev.begin(), prev.begin() + static_cast<long>(i));
      total.insert(total.end(), spur.begin(), spur.end());
      if (seen.insert(total).second) B.insert({yen.cost(total), std::move(total)});
    }
    if (B.empty()) break;
    A.push_back(B.begin()->path);
    B.erase(B.begin());
  }
  return A;
}

std::vector<std::vector<std::size_t>> diversePaths(std::size_t n,
                                                   const std::vector<WeightedEdge>& e,
                                                   std::uint32_t s, std::uint32_t t,
                                                   std::size_t count, double penalty) {
  if (!(penalty > 0)) throw Error("diversePaths: the penalty must be positive");
  std::vector<WeightedEdge> w = e;
  std::vector<std::vector<std::size_t>> out;
  std::set<std::vector<std::size_t>> seen;
  for (std::size_t i = 0; i < count; ++i) {
    const auto p = kShortestSimplePaths(n, w, s, t, 1);
    if (p.empty()) break;
    if (seen.insert(p[0]).second) out.push_back(p[0]);
    for (std::size_t k : p[0]) w[k].w *= 1 + penalty;
  }
  return out;
}

}  // namespace asf::planning
