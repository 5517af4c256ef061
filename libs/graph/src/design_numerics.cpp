// The design vectors and the dense linear algebra of the optimal design problems.
#include <asf/errors.h>

#include <algorithm>
#include <cmath>

#include "design_solvers.h"

namespace asf::graph::detail {

void checkEdgeInformation(const Multigraph& g, const char* what) {
  for (int j = 0; j < g.m(); ++j)
    if (!(g.edges[j].information > 0) || !std::isfinite(g.edges[j].information))
      throw InputError(std::string(what) + ": information of edge " + std::to_string(j) +
                       " is not a positive finite number");
}

void checkWeights(const Multigraph& g, const VectorXd& x, const char* what) {
  checkEdgeInformation(g, what);
  if (x.size() != g.m())
    throw InputError(std::string(what) + ": " + std::to_string(x.size()) +
                     " weights for a graph of " + std::to_string(g.m()) + " edges");
  for (int j = 0; j < x.size(); ++j)
    if (!(x[j] >= 0) || !std::isfinite(x[j]))
      throw InputError(std::string(what) + ": weight of edge " + std::to_string(j) +
                       " is negative or not finite");
}

bool supportConnectedImpl(const Multigraph& g, const VectorXd& x) {
  if (g.n < 2) return false;
  Multigraph s;
  s.n = g.n;
  for (int j = 0; j < g.m(); ++j)
    if (x[j] > 0 && g.edges[j].u != g.edges[j].v) s.edges.push_back(g.edges[j]);
  return s.connected();
}

Design graphDesign(const Multigraph& g, std::vector<int>& kept) {
  Design d;
  d.graph = true;
  d.N = g.n;
  kept.clear();
  for (int j = 0; j < g.m(); ++j) {
    if (g.edges[j].u == g.edges[j].v) continue;
    kept.push_back(j);
    d.u.push_back(g.edges[j].u);
    d.v.push_back(g.edges[j].v);
  }
  d.m = static_cast<int>(kept.size());
  d.s.resize(d.m);
  for (int a = 0; a < d.m; ++a) d.s[a] = std::sqrt(g.edges[kept[a]].information);
  return d;
}

// In-place inverse of a lower-triangular matrix (recursive blocks: two half-size inverses
// and two triangular products), n^3/3 flops instead of the n^3 of a solve against I.
void invertLower(Eigen::Ref<MatrixXd> X) {
  const Eigen::Index n = X.rows();
  if (n <= 16) {
    for (Eigen::Index j = 0; j < n; ++j) {
      X(j, j) = 1.0 / X(j, j);
      for (Eigen::Index i = j + 1; i < n; ++i) {
        double acc = 0;
        for (Eigen::Index q = j; q < i; ++q) acc += X(i, q) * X(q, j);
        X(i, j) = -acc / X(i, i);
      }
    }
    return;
  }
  const Eigen::Index h = n / 2;
  invertLower(X.topLeftCorner(h, h));
  invertLower(X.bottomRightCorner(n - h, n - h));
  const MatrixXd T =
      X.bottomLeftCorner(n - h, h) * X.topLeftCorner(h, h).triangularView<Eigen::Lower>();
  X.bottomLeftCorner(n - h, h).noalias() =
      -(X.bottomRightCorner(n - h, n - h).triangularView<Eigen::Lower>() * T);
}

// Inverse of the matrix X = L L^T factored by c: L^-T L^-1 (symmetric by construction).
MatrixXd inverseFromLLT(const Eigen::LLT<MatrixXd>& c) {
  MatrixXd Li = c.matrixL();
  invertLower(Li);
  const Eigen::Index n = Li.rows();
  MatrixXd P = MatrixXd::Zero(n, n);
  P.selfadjointView<Eigen::Lower>().rankUpdate(Li.transpose());
  P.triangularView<Eigen::StrictlyUpper>() = P.transpose();
  return P;
}

// Largest step alpha with X + alpha dX still positive definite (X = R R^T given by its
// Cholesky factor): 1 / max(0, -lambda_min(R^-1 dX R^-T)), lambda_min estimated by Lanczos
// with full reorthogonalization (O(n^2) per iteration instead of a dense eigensolver). `start`
// (if not empty) is the first Lanczos vector and receives the Ritz vector of the smallest
// Ritz value: the extreme eigenvector moves little between the predictor and the corrector
// and between iterations, so a warm start converges in a few steps. It stops when that Ritz
// value changes by less than rtol (relative) in a step. A Ritz value is >= lambda_min, so the
// estimate can be long: callers verify the step by Cholesky.
double maxStepPD(const Eigen::LLT<MatrixXd>& X, const MatrixXd& dX, VectorXd& start, int kcap,
                 double rtol) {
  const int n = static_cast<int>(dX.rows());
  const int kmax = std::min(n, kcap);
  MatrixXd V(n, kmax + 1);
  VectorXd al(kmax), be(kmax + 1);
  VectorXd w(n), y(n), h(kmax + 1);
  if (start.size() == n && start.norm() > 0) {
    w = start;
  } else {
    for (int i = 0; i < n; ++i) w[i] = std::sin(1.0 + 0.7 * i);  // deterministic start
  }
  V.col(0) = w.normalized();
  Eigen::SelfAdjointEigenSolver<MatrixXd> es;
  double ritz = 0, prev = kInf, scale = 1e-300;
  int k = 0;
  for (;; ++k) {
    w = V.col(k);
    X.matrixU().solveInPlace(w);
    y.noalias() = dX * w;
    X.matrixL().solveInPlace(y);
    al[k] = V.col(k).dot(y);
    for (int pass = 0; pass < 2; ++pass) {
      h.head(k + 1).noalias() = V.leftCols(k + 1).transpose() * y;
      y.noalias() -= V.leftCols(k + 1) * h.head(k + 1);
    }
    be[k + 1] = y.norm();
    scale = std::max(scale, std::abs(al[k]));
    es.computeFromTridiagonal(al.head(k + 1), be.segment(1, k), Eigen::EigenvaluesOnly);
    ritz = es.eigenvalues()[0];
    if (k + 1 >= kmax || be[k + 1] <= 1e-12 * scale ||
        (k >= 2 && std::abs(ritz - prev) <= rtol * std::abs(ritz)))
      break;
    prev = ritz;
    V.col(k + 1) = y / be[k + 1];
  }
  es.computeFromTridiagonal(al.head(k + 1), be.segment(1, k), Eigen::ComputeEigenvectors);
  start.noalias() = V.leftCols(k + 1) * es.eigenvectors().col(0);
  return ritz < 0 ? -1.0 / ritz : kInf;
}

// Cholesky of X padded to be invertible (X + J/N for graphs); false if not positive definite.
bool factorPD(const Design& D, const MatrixXd& X, Eigen::LLT<MatrixXd>& c) {
  MatrixXd Y = X;
  D.pad(Y);
  c.compute(Y);
  return c.info() == Eigen::Success;
}

}  // namespace asf::graph::detail
