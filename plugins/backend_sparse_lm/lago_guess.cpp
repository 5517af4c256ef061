// The LAGO-style initial guess of the sparse_lm back-end (see lago_guess.h).
#include "lago_guess.h"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <queue>

namespace asf::sparse_lm::detail {

namespace {

struct Arc {
  int edge, other;
  bool forward;  // traversed from -> to
};

/// Spanning tree of least accumulated rotation variance from the held nodes (Dijkstra):
/// each reached node's parent arc, its orientation composed down the tree, and the order
/// the nodes were reached in.
struct RotationTree {
  std::vector<double> var_th;  ///< per edge: marginal variance of the measured rotation
  std::vector<double> th;
  std::vector<char> done;
  std::vector<int> pop_order;
  std::vector<Arc> parent;
};

RotationTree rotationTree(const Problem& P, const Structure& S, const Poses& x) {
  const int n = static_cast<int>(x.size());
  RotationTree t;
  std::vector<std::vector<Arc>> adj(n);
  t.var_th.assign(P.edges.size(), 0.0);
  for (std::size_t k = 0; k < P.edges.size(); ++k) {
    const auto& e = P.edges[k];
    if (e.from == e.to) continue;
    adj[e.from].push_back({static_cast<int>(k), e.to, true});
    adj[e.to].push_back({static_cast<int>(k), e.from, false});
    t.var_th[k] = std::max(e.W.inverse()(2, 2), 1e-12);
  }
  std::vector<double> dist(n, std::numeric_limits<double>::infinity());
  t.th.assign(n, 0.0);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> q;
  for (int i = 0; i < n; ++i)
    if (S.free[i] < 0) {
      dist[i] = 0;
      t.th[i] = x[i].z();
      q.emplace(0.0, i);
    }
  t.done.assign(n, 0);
  t.parent.assign(n, Arc{-1, -1, true});
  while (!q.empty()) {
    const auto [d, v] = q.top();
    q.pop();
    if (t.done[v]) continue;
    t.done[v] = 1;
    t.pop_order.push_back(v);
    for (const Arc& a : adj[v]) {
      const double nd = d + t.var_th[a.edge];
      if (nd < dist[a.other]) {
        dist[a.other] = nd;
        t.parent[a.other] = Arc{a.edge, v, a.forward};
        const double dz = P.edges[a.edge].z.z();
        t.th[a.other] = t.th[v] + (a.forward ? dz : -dz);
        q.emplace(nd, a.other);
      }
    }
  }
  return t;
}

/// Orientations: min sum w (th_j - th_i - (dz + 2 pi k))^2, k from the tree's unwrapping,
/// over the free reached nodes (`idx`: their unknown's index, -1 for the others); the
/// solution replaces t.th. False if the system cannot be solved.
bool solveOrientations(const Problem& P, const std::vector<int>& idx, int m, RotationTree& t) {
  using Triplet = Eigen::Triplet<double>;
  std::vector<Triplet> T;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m);
  for (std::size_t k = 0; k < P.edges.size(); ++k) {
    const auto& e = P.edges[k];
    if (e.from == e.to || !t.done[e.from] || !t.done[e.to]) continue;
    const double wrap = std::round((t.th[e.to] - t.th[e.from] - e.z.z()) / (2 * M_PI));
    const double delta = e.z.z() + 2 * M_PI * wrap;
    const double w = 1 / t.var_th[k];
    const int a = idx[e.from], b = idx[e.to];
    // residual th_b - th_a - delta; held ends are constants
    double c = delta;
    if (a < 0) c += t.th[e.from];
    if (b < 0) c -= t.th[e.to];
    if (b >= 0) {
      T.emplace_back(b, b, w);
      rhs[b] += w * c;
    }
    if (a >= 0) {
      T.emplace_back(a, a, w);
      rhs[a] -= w * c;
    }
    if (a >= 0 && b >= 0) {
      T.emplace_back(a, b, -w);
      T.emplace_back(b, a, -w);
    }
  }
  Eigen::SparseMatrix<double> A(m, m);
  A.setFromTriplets(T.begin(), T.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
  if (ldlt.info() != Eigen::Success) return false;
  const Eigen::VectorXd sol_th = ldlt.solve(rhs);
  if (ldlt.info() != Eigen::Success || !sol_th.allFinite()) return false;
  for (std::size_t i = 0; i < idx.size(); ++i)
    if (idx[i] >= 0) t.th[i] = sol_th[idx[i]];
  return true;
}

}  // namespace

bool lagoGuess(const Problem& P, const Structure& S, Poses& x) {
  const int n = static_cast<int>(x.size());
  RotationTree t = rotationTree(P, S, x);
  std::vector<int> idx(n, -1);
  int m = 0;
  for (int i = 0; i < n; ++i)
    if (S.free[i] >= 0 && t.done[i]) idx[i] = m++;
  if (m == 0) return false;
  if (!solveOrientations(P, idx, m, t)) return false;
  // Positions: compose the measurements down the same tree with those orientations.
  for (int v : t.pop_order) {
    if (idx[v] < 0) continue;
    const Arc& pa = t.parent[v];
    const Eigen::Vector2d& tz = P.edges[pa.edge].z.head<2>();
    const int u = pa.other;
    if (pa.forward)  // u -> v: t_v = t_u + R(th_u) t_z
      x[v].head<2>() = x[u].head<2>() + Eigen::Rotation2Dd(t.th[u]) * tz;
    else  // v -> u: t_v = t_u - R(th_v) t_z
      x[v].head<2>() = x[u].head<2>() - Eigen::Rotation2Dd(t.th[v]) * tz;
    x[v].z() = asf::se2::wrapAngle(t.th[v]);
  }
  return true;
}

}  // namespace asf::sparse_lm::detail
