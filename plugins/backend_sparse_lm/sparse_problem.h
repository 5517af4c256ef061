#pragma once
// Private to backend_sparse_lm: the problem as the inner loops see it (edges without CPose2D
// arithmetic) and the block structure of the normal matrix; shared by sparse_se2.cpp,
// sparse_se2_marginals.cpp, lago_guess.cpp and marginal_update.cpp.
#include <asf/pose_graph.h>
#include <asf/se2_edge.h>

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "sparse_se2.h"

namespace asf::sparse_lm::detail {

using Poses = std::vector<Eigen::Vector3d>;

/// The graph's edges in the form the inner loops want (no CPose2D arithmetic there).
struct Problem {
  struct Edge {
    int from, to;
    Eigen::Vector3d z;
    Eigen::Matrix3d W;
    Kernel kernel;  ///< None for the edges Options::robust_edges leaves quadratic
  };
  std::vector<Edge> edges;

  Problem(const asf::PoseGraph& g, const Options& o) {
    edges.reserve(g.edges.size());
    for (const auto& e : g.edges) add(e, o);
  }
  /// Only the edges g.edges[k] for k in `subset`, in that order.
  Problem(const asf::PoseGraph& g, const std::vector<std::size_t>& subset, const Options& o) {
    edges.reserve(subset.size());
    for (std::size_t k : subset) add(g.edges.at(k), o);
  }

 private:
  void add(const asf::PoseEdge& e, const Options& o) {
    // Decided on the graph's own node ids (a window's edges keep them).
    const bool robust =
        o.robust_edges == RobustEdges::All ||
        (o.robust_edges == RobustEdges::LoopClosures && e.kind == asf::EdgeKind::LoopClosure) ||
        (o.robust_edges == RobustEdges::CrossLinks && e.from + 1 != e.to && e.to + 1 != e.from);
    edges.push_back({static_cast<int>(e.from),
                     static_cast<int>(e.to),
                     {e.mean.x(), e.mean.y(), e.mean.phi()},
                     e.information,
                     robust ? o.kernel : Kernel::None});
  }
};

inline Poses posesOf(const asf::PoseGraph& g) {
  Poses x(g.size());
  for (std::size_t i = 0; i < g.size(); ++i)
    x[i] = {g.nodes[i].pose.x(), g.nodes[i].pose.y(), g.nodes[i].pose.phi()};
  return x;
}

inline double cost(const Problem& P, const Poses& x, const Options& o) {
  double c = 0;
  for (const auto& e : P.edges) {
    const Eigen::Vector3d r = asf::se2::edgeError(x[e.from], x[e.to], e.z);
    c += robustCost(e.kernel, o.robust_delta, r.dot(e.W * r));
  }
  return c;
}

/// Block and scalar structure of the normal matrix H: its upper triangle in compressed
/// columns, 3x3 blocks, one block column per free node (not node 0, not fixed).
struct Structure {
  std::vector<int> free;  ///< node -> free index, -1 for node 0 and fixed nodes
  int nfree = 0;
  /// (column j, row i) with i <= j, sorted by column then row: the diagonal block ends
  /// each column.
  std::vector<std::pair<int, int>> blocks;
  std::vector<int> col_begin;  ///< nfree + 1 offsets into blocks
  std::vector<int> Ap, Ai;     ///< scalar CSC pattern (upper triangle, rows sorted)
  std::vector<int> off;        ///< per edge: its off-diagonal block (index into blocks) or -1

  int dim() const { return 3 * nfree; }
  bool sameAs(const Structure& o) const { return free == o.free && blocks == o.blocks; }
  /// True if this structure is o plus new free nodes (appended) and new blocks.
  bool grewFrom(const Structure& o) const {
    if (free.size() < o.free.size() || nfree < o.nfree) return false;
    if (!std::equal(o.free.begin(), o.free.end(), free.begin())) return false;
    return std::includes(blocks.begin(), blocks.end(), o.blocks.begin(), o.blocks.end());
  }
  /// Position in the value array of entry (3i + r, 3j + c) of the k-th block of column j.
  int pos(int j, int k, int r, int c) const { return Ap[3 * j + c] + 3 * k + r; }
  int diagBlock(int j) const { return col_begin[j + 1] - 1 - col_begin[j]; }

  /// Node 0 (the gauge) and g.fixed.
  static std::vector<char> heldNodes(const asf::PoseGraph& g) {
    std::vector<char> held(g.size(), 0);
    if (!held.empty()) held[0] = 1;
    for (asf::NodeId f : g.fixed) held[f] = 1;
    return held;
  }
  static Structure of(const asf::PoseGraph& g) {
    std::vector<std::pair<int, int>> ends;
    ends.reserve(g.edges.size());
    for (const auto& e : g.edges) ends.emplace_back(e.from, e.to);
    return of(heldNodes(g), ends);
  }
  static Structure of(const std::vector<char>& held, const Problem& P) {
    std::vector<std::pair<int, int>> ends;
    ends.reserve(P.edges.size());
    for (const auto& e : P.edges) ends.emplace_back(e.from, e.to);
    return of(held, ends);
  }
  /// Free nodes: those not `held`; one entry of `off` per element of `ends` (edge ends).
  static Structure of(const std::vector<char>& held, const std::vector<std::pair<int, int>>& ends) {
    Structure S;
    const std::size_t n = held.size();
    S.free.assign(n, -1);
    for (std::size_t i = 0; i < n; ++i)
      if (!held[i]) S.free[i] = S.nfree++;
    S.blocks.reserve(S.nfree + ends.size());
    for (int j = 0; j < S.nfree; ++j) S.blocks.emplace_back(j, j);
    for (const auto& [from, to] : ends) {
      const int a = S.free[from], b = S.free[to];
      if (a >= 0 && b >= 0 && a != b) S.blocks.emplace_back(std::max(a, b), std::min(a, b));
    }
    std::sort(S.blocks.begin(), S.blocks.end());
    S.blocks.erase(std::unique(S.blocks.begin(), S.blocks.end()), S.blocks.end());
    S.col_begin.assign(S.nfree + 1, 0);
    for (const auto& bk : S.blocks) ++S.col_begin[bk.first + 1];
    for (int j = 0; j < S.nfree; ++j) S.col_begin[j + 1] += S.col_begin[j];

    S.Ap.assign(S.dim() + 1, 0);
    for (int j = 0; j < S.nfree; ++j) {
      const int m = S.col_begin[j + 1] - S.col_begin[j];
      for (int c = 0; c < 3; ++c) S.Ap[3 * j + c + 1] = S.Ap[3 * j + c] + 3 * (m - 1) + c + 1;
    }
    S.Ai.resize(S.Ap.back());
    for (int j = 0; j < S.nfree; ++j)
      for (int c = 0; c < 3; ++c) {
        int p = S.Ap[3 * j + c];
        for (int k = S.col_begin[j]; k + 1 < S.col_begin[j + 1]; ++k)
          for (int r = 0; r < 3; ++r) S.Ai[p++] = 3 * S.blocks[k].second + r;
        for (int r = 0; r <= c; ++r) S.Ai[p++] = 3 * j + r;
      }

    S.off.assign(ends.size(), -1);
    for (std::size_t k = 0; k < ends.size(); ++k) {
      const int a = S.free[ends[k].first], b = S.free[ends[k].second];
      if (a < 0 || b < 0 || a == b) continue;
      const std::pair<int, int> key(std::max(a, b), std::min(a, b));
      const auto first = S.blocks.begin() + S.col_begin[key.first];
      const auto last = S.blocks.begin() + S.col_begin[key.first + 1];
      S.off[k] = static_cast<int>(std::lower_bound(first, last, key) - S.blocks.begin());
    }
    return S;
  }
};

}  // namespace asf::sparse_lm::detail
