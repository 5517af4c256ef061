#include <asf/errors.h>
#include <asf/graph/families.h>

#include <algorithm>
#include <fstream>
#include <random>
#include <set>

namespace asf::graph {

namespace {
using Rng = std::mt19937_64;

int uniformInt(Rng& rng, int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }
bool coin(Rng& rng, double p) { return std::uniform_real_distribution<double>(0, 1)(rng) < p; }
}  // namespace

Multigraph gridGraph(int rows, int cols) {
  if (rows < 1 || cols < 1) throw Error("gridGraph: rows and cols must be >= 1");
  Multigraph g;
  g.n = rows * cols;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const int v = r * cols + c;
      if (c + 1 < cols) g.edges.push_back({v, v + 1, 1.0});
      if (r + 1 < rows) g.edges.push_back({v, v + cols, 1.0});
    }
  return g;
}

Multigraph randomConnectedGraph(int n, int m, std::uint32_t seed) {
  if (n < 1 || m < n - 1 || static_cast<long>(m) > static_cast<long>(n) * (n - 1) / 2)
    throw Error("randomConnectedGraph: needs n >= 1 and n-1 <= m <= n(n-1)/2");
  std::mt19937 r(seed);
  Multigraph g;
  g.n = n;
  std::set<std::pair<int, int>> s;
  for (int i = 1; i < n; ++i) {
    const int j = std::uniform_int_distribution<int>(0, i - 1)(r);
    g.edges.push_back({j, i, 1});
    s.insert({j, i});
  }
  std::uniform_int_distribution<int> node(0, n - 1);
  while (g.m() < m) {
    int a = node(r), b = node(r);
    if (a == b) continue;
    if (a > b) std::swap(a, b);
    if (!s.insert({a, b}).second) continue;
    g.edges.push_back({a, b, 1});
  }
  return g;
}

Multigraph randomTree(int n, std::uint64_t seed) {
  if (n < 1) throw Error("randomTree: n must be >= 1");
  Multigraph g;
  g.n = n;
  if (n == 1) return g;
  if (n == 2) {
    g.edges.push_back({0, 1, 1.0});
    return g;
  }
  Rng rng(seed);
  std::vector<int> code(n - 2), degree(n, 1);
  for (int& c : code) ++degree[c = uniformInt(rng, 0, n - 1)];
  // Pruefer decoding: repeatedly join the smallest leaf to the next code entry.
  std::set<int> leaves;
  for (int v = 0; v < n; ++v)
    if (degree[v] == 1) leaves.insert(v);
  for (int c : code) {
    const int leaf = *leaves.begin();
    leaves.erase(leaves.begin());
    g.edges.push_back({leaf, c, 1.0});
    if (--degree[c] == 1) leaves.insert(c);
  }
  const int a = *leaves.begin(), b = *std::next(leaves.begin());
  g.edges.push_back({a, b, 1.0});
  return g;
}

Multigraph smallWorld(int n, int k, double beta, std::uint64_t seed) {
  if (k < 2 || k % 2 || k >= n) throw Error("smallWorld: k must be even with 2 <= k < n");
  Rng rng(seed);
  for (;;) {
    std::set<std::pair<int, int>> e;
    for (int v = 0; v < n; ++v)
      for (int j = 1; j <= k / 2; ++j)
        e.insert({std::min(v, (v + j) % n), std::max(v, (v + j) % n)});
    std::vector<std::pair<int, int>> ring(e.begin(), e.end());
    for (auto& [u, v] : ring) {
      if (!coin(rng, beta)) continue;
      const int w = uniformInt(rng, 0, n - 1);
      const std::pair<int, int> nv{std::min(u, w), std::max(u, w)};
      if (w == u || e.count(nv)) continue;
      e.erase({u, v});
      e.insert(nv);
    }
    Multigraph g;
    g.n = n;
    for (const auto& [u, v] : e) g.edges.push_back({u, v, 1.0});
    if (g.connected()) return g;
  }
}

Multigraph roomsAndCorridor(int corridor, int max_rooms, double door_prob, double loop_prob,
                            std::uint64_t seed) {
  if (corridor < 1 || max_rooms < 0) throw Error("roomsAndCorridor: corridor >= 1, max_rooms >= 0");
  Rng rng(seed);
  Multigraph g;
  g.n = corridor;
  for (int c = 0; c + 1 < corridor; ++c) g.edges.push_back({c, c + 1, 1.0});
  if (corridor >= 3 && coin(rng, loop_prob)) g.edges.push_back({corridor - 1, 0, 1.0});
  std::vector<std::vector<int>> rooms(corridor);
  for (int c = 0; c < corridor; ++c) {
    const int r = uniformInt(rng, 0, max_rooms);
    for (int i = 0; i < r; ++i) {
      rooms[c].push_back(g.n);
      g.edges.push_back({c, g.n++, 1.0});
    }
  }
  // Doors between rooms of the same or the next corridor node.
  for (int c = 0; c < corridor; ++c) {
    std::vector<int> near = rooms[c];
    if (c + 1 < corridor) near.insert(near.end(), rooms[c + 1].begin(), rooms[c + 1].end());
    for (std::size_t i = 0; i + 1 < near.size(); ++i)
      if (coin(rng, door_prob)) g.edges.push_back({near[i], near[i + 1], 1.0});
  }
  return g;
}

std::vector<Multigraph> generateFamily(const std::string& family, int count, int max_nodes,
                                       std::uint64_t seed) {
  if (count < 0) throw Error("generateFamily: count must be >= 0");
  if (max_nodes < 4) throw Error("generateFamily: max_nodes must be >= 4");
  static const char* kFamilies[] = {"grid", "tree", "smallworld", "rooms"};
  const bool mixed = family == "mixed";
  if (!mixed &&
      std::find(std::begin(kFamilies), std::end(kFamilies), family) == std::end(kFamilies))
    throw Error("unknown graph family '" + family + "' (grid, tree, smallworld, rooms, mixed)");
  std::vector<Multigraph> out;
  for (int i = 0; i < count; ++i) {
    const std::uint64_t s = seed + static_cast<std::uint64_t>(i);
    Rng rng(s * 0x9E3779B97F4A7C15ull + 1);
    const std::string f = mixed ? kFamilies[i % 4] : family;
    Multigraph g;
    if (f == "grid") {
      const int rows = uniformInt(rng, 2, std::max(2, max_nodes / 2));
      const int cols = uniformInt(rng, 2, std::max(2, max_nodes / rows));
      g = gridGraph(rows, cols);
    } else if (f == "tree") {
      g = randomTree(uniformInt(rng, 4, max_nodes), s);
    } else if (f == "smallworld") {
      const int n = uniformInt(rng, 6, std::max(6, max_nodes));
      g = smallWorld(n, 4, 0.2, s);
    } else {
      // corridor * (1 + max_rooms) <= max_nodes: never above the cap.
      const int corridor = uniformInt(rng, 2, std::max(2, max_nodes / 4));
      const int max_rooms = std::max(1, std::min(4, (max_nodes - corridor) / corridor));
      for (std::uint64_t k = 0; g.n < 4; ++k)  // two bare corridor nodes: draw again
        g = roomsAndCorridor(corridor, max_rooms, 0.3, 0.3, s + 1000003 * k);
    }
    out.push_back(std::move(g));
  }
  return out;
}

void writeGraphList(const std::string& path, const std::vector<Multigraph>& graphs,
                    const std::string& comment) {
  std::ofstream f(path);
  if (!f) throw Error(path + ": cannot write graph list");
  f << "# " << (comment.empty() ? "graph list: n m u1-v1 ... (1-based)" : comment) << "\n";
  for (const Multigraph& g : graphs) {
    f << g.n << ' ' << g.m();
    for (const Edge& e : g.edges) f << ' ' << e.u + 1 << '-' << e.v + 1;
    f << '\n';
  }
  if (!f) throw Error(path + ": write failed");
}

}  // namespace asf::graph
