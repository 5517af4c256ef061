// The LAGO-style initial guess of the sparse_lm back-end (see lago_guess.h).
#include "lago_guess.h"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <queue>

namespace asf_sparse_lm::detail {

bool lagoGuess(const Problem& P, const Structure& S, Poses& x) {
  const int n = static_cast<int>(x.size());
  struct Arc {
    int edge, other;
    bool forward;  // traversed from -> to
  };
  std::vector<std::vector<Arc>> adj(n);
  std::vector<double> var_th(P.edges.size());
  for (std::size_t k = 0; k < P.edges.size(); ++k) {
    const auto& e = P.edges[k];
    if (e.from == e.to) continue;
    adj[e.from].push_back({static_cast<int>(k), e.to, true});
    adj[e.to].push_back({static_cast<int>(k), e.from, false});
    // marginal variance of the measured rotation
    var_th[k] = std::max(e.W.inverse()(2, 2), 1e-12);
  }
  // Spanning tree of least accumulated rotation variance from the held nodes (Dijkstra).
  std::vector<double> dist(n, std::numeric_limits<double>::infinity()), th(n, 0.0);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> q;
  for (int i = 0; i < n; ++i)
    if (S.free[i] < 0) {
      dist[i] = 0;
      th[i] = x[i].z();
      q.emplace(0.0, i);
    }
  std::vector<char> done(n, 0);
  std::vector<int> pop_order;
  std::vector<Arc> parent(n, Arc{-1, -1, true});
  while (!q.empty()) {
    const auto [d, v] = q.top();
    q.pop();
    if (done[v]) continue;
    done[v] = 1;
    pop_order.push_back(v);
    for (const Arc& a : adj[v]) {
      const double nd = d + var_th[a.edge];
      if (nd < dist[a.other]) {
        dist[a.other] = nd;
        parent[a.other] = Arc{a.edge, v, a.forward};
        const double dz = P.edges[a.edge].z.z();
        th[a.other] = th[v] + (a.forward ? dz : -dz);
        q.emplace(nd, a.other);
      }
    }
  }
  std::vector<int> idx(n, -1);
  int m = 0;
  for (int i = 0; i < n; ++i)
    if (S.free[i] >= 0 && done[i]) idx[i] = m++;
  if (m == 0) return false;

  // Orientations: min sum w (th_j - th_i - (dz + 2 pi k))^2, k from the tree's unwrapping.
  using Triplet = Eigen::Triplet<double>;
  std::vector<Triplet> T;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m);
  for (std::size_t k = 0; k < P.edges.size(); ++k) {
    const auto& e = P.edges[k];
    if (e.from == e.to || !done[e.from] || !done[e.to]) continue;
    const double wrap = std::round((th[e.to] - th[e.from] - e.z.z()) / (2 * M_PI));
    const double delta = e.z.z() + 2 * M_PI * wrap;
    const double w = 1 / var_th[k];
    const int a = idx[e.from], b = idx[e.to];
    // residual th_b - th_a - delta; held ends are constants
    double c = delta;
    if (a < 0) c += th[e.from];
    if (b < 0) c -= th[e.to];
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
  for (int i = 0; i < n; ++i)
    if (idx[i] >= 0) th[i] = sol_th[idx[i]];
  // Positions: compose the measurements down the same tree with those orientations.
  for (int v : pop_order) {
    if (idx[v] < 0) continue;
    const Arc& pa = parent[v];
    const Eigen::Vector2d& tz = P.edges[pa.edge].z.head<2>();
    const int u = pa.other;
    if (pa.forward)  // u -> v: t_v = t_u + R(th_u) t_z
      x[v].head<2>() = x[u].head<2>() + Eigen::Rotation2Dd(th[u]) * tz;
    else  // v -> u: t_v = t_u - R(th_v) t_z
      x[v].head<2>() = x[u].head<2>() - Eigen::Rotation2Dd(th[v]) * tz;
    x[v].z() = asf::se2::wrapAngle(th[v]);
  }
  return true;
}

}  // namespace asf_sparse_lm::detail
