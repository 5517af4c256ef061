#pragma once
// Private to the graph library: the numerics of the optimal design problems of
// graph/information.h (thesis chapter 5), shared by its files: the design vectors, dense
// linear algebra helpers (design_numerics.cpp), the E-optimal interior point method
// (design_e.cpp) and the smooth criteria's Newton method (design_smooth.cpp).
//
// Numerics. Everything works on the n x n matrices of the graph: a matrix X restricted to the
// complement of the all-ones vector 1 is represented by X + J/n (J = 11^T), which is invertible
// when X is on 1-perp, and whose inverse is X^+ + J/n. For a_j = e_u - e_v (orthogonal to 1)
// the quadratic forms a_j^T X a_l are then four look-ups, so the gradients and Hessians of the
// design problems cost O(m n + m^2) once X is known, instead of O(m n^2) with a reduced basis.
#include <asf/graph/multigraph.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <functional>
#include <limits>
#include <vector>

namespace asf::graph::detail {

using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr double kInf = std::numeric_limits<double>::infinity();

/// InputError unless every edge's information is positive and finite.
void checkEdgeInformation(const Multigraph& g, const char* what);
/// checkEdgeInformation, and one finite non-negative weight per edge.
void checkWeights(const Multigraph& g, const VectorXd& x, const char* what);
/// The edges of positive weight (self-loops aside) connect every node.
bool supportConnectedImpl(const Multigraph& g, const VectorXd& x);

// The design vectors of an E problem: graph edges in the full n-space (lookups, 1-perp
// padding) or dense rows of A in R^k.
struct Design {
  bool graph = true;
  int N = 0;  // matrix size
  int m = 0;
  std::vector<int> u, v;  // graph mode
  VectorXd s;             // graph mode: a_j = s_j (e_u - e_v), s_j = sqrt(edge information)
  MatrixXd A;             // dense mode (m x N)

  int k() const { return graph ? N - 1 : N; }
  // Pi: identity on the space of the problem (I - J/N for graphs).
  MatrixXd pi() const {
    MatrixXd P = MatrixXd::Identity(N, N);
    if (graph) P.array() -= 1.0 / N;
    return P;
  }
  // Added to a matrix living on 1-perp to make it invertible (J/N), or nothing.
  void pad(MatrixXd& X, double s = 1.0) const {
    if (graph) X.array() += s / N;
  }
  // Rows a_j^T X (m x cols(X)).
  MatrixXd rows(const MatrixXd& X) const {
    if (!graph) return A * X;
    MatrixXd W(m, X.cols());
    for (int j = 0; j < m; ++j) W.row(j) = s[j] * (X.row(u[j]) - X.row(v[j]));
    return W;
  }
  // R = [a_j^T X a_l] (X symmetric).
  MatrixXd quad(const MatrixXd& X) const { return quadRows(rows(X)); }
  // The same from W = rows(X).
  MatrixXd quadRows(const MatrixXd& W) const {
    if (!graph) return W * A.transpose();
    MatrixXd R(m, m);
    for (int l = 0; l < m; ++l) R.col(l) = s[l] * (W.col(u[l]) - W.col(v[l]));
    return R;
  }
  // X sum_j w_j a_j a_j^T (graphs: two columns per edge, O(rows(X) m)).
  MatrixXd mulSum(const MatrixXd& X, const VectorXd& w) const {
    if (!graph) return (X * A.transpose()) * w.asDiagonal() * A;
    MatrixXd Y = MatrixXd::Zero(X.rows(), N);
    VectorXd c(X.rows());
    for (int j = 0; j < m; ++j) {
      c = (w[j] * s[j] * s[j]) * (X.col(u[j]) - X.col(v[j]));
      Y.col(u[j]) += c;
      Y.col(v[j]) -= c;
    }
    return Y;
  }
  // X Pi.
  MatrixXd mulPi(const MatrixXd& X) const {
    if (!graph) return X;
    MatrixXd Y = X;
    Y.colwise() -= X.rowwise().sum() / N;
    return Y;
  }
  // a_j^T X a_j; X need not be symmetric (the symmetric part counts).
  VectorXd diagQuad(const MatrixXd& X) const {
    VectorXd d(m);
    if (!graph) {
      d = (A * X).cwiseProduct(A).rowwise().sum();
      return d;
    }
    for (int j = 0; j < m; ++j)
      d[j] = s[j] * s[j] * (X(u[j], u[j]) + X(v[j], v[j]) - X(u[j], v[j]) - X(v[j], u[j]));
    return d;
  }
  // sum_j w_j a_j a_j^T.
  MatrixXd sumOuter(const VectorXd& w) const {
    if (!graph) return A.transpose() * w.asDiagonal() * A;
    MatrixXd L = MatrixXd::Zero(N, N);
    for (int j = 0; j < m; ++j) {
      const double wj = w[j] * s[j] * s[j];
      L(u[j], u[j]) += wj;
      L(v[j], v[j]) += wj;
      L(u[j], v[j]) -= wj;
      L(v[j], u[j]) -= wj;
    }
    return L;
  }
  // Eigenvalues of X on the problem space (graph: 1-perp), ascending; X symmetric, X 1 = 0.
  VectorXd spectrum(const MatrixXd& X) const {
    if (!graph)
      return Eigen::SelfAdjointEigenSolver<MatrixXd>(X, Eigen::EigenvaluesOnly).eigenvalues();
    // Shift the 1 direction above every other eigenvalue (Gershgorin) and drop it.
    const double s = 2.0 * X.cwiseAbs().rowwise().sum().maxCoeff() + 1e-300;
    MatrixXd Y = X;
    pad(Y, s);
    const VectorXd e =
        Eigen::SelfAdjointEigenSolver<MatrixXd>(Y, Eigen::EigenvaluesOnly).eigenvalues();
    return e.head(N - 1);
  }
};

/// The design of a graph's edges, self-loops dropped (`kept`: the edges used, in order).
Design graphDesign(const Multigraph& g, std::vector<int>& kept);
/// In-place inverse of a lower-triangular matrix.
void invertLower(Eigen::Ref<MatrixXd> X);
/// Inverse of the matrix factored by `c`.
MatrixXd inverseFromLLT(const Eigen::LLT<MatrixXd>& c);
/// Largest step keeping X + alpha dX positive definite (Lanczos estimate; see the definition).
double maxStepPD(const Eigen::LLT<MatrixXd>& X, const MatrixXd& dX, VectorXd& start, int kcap = 40,
                 double rtol = 1e-3);
/// Cholesky of X padded to be invertible; false if not positive definite.
bool factorPD(const Design& D, const MatrixXd& X, Eigen::LLT<MatrixXd>& c);

/// Called after each iteration with (iteration, value, bound).
using IterationReport = std::function<void(int, double, double)>;

// ---- E: primal-dual interior point method on
//   max t  s.t.  S = sum_j x_j a_j a_j^T - t Pi >= 0,  sum x = 1,  x >= 0
// dual:  min nu  s.t.  <a_j a_j^T, Z> + z_j = nu,  tr Z = 1,  Z >= 0,  z >= 0.
// HKM search direction, Mehrotra predictor-corrector, separate primal and dual step lengths.
// The start is primal and dual feasible, so the linear constraints stay satisfied and the
// gap is <Z, S> + x^T z = nu - t.
//
// Cost per iteration: one Cholesky and one inverse of S, the (m+1) x (m+1) Schur complement
// (entries (a_j^T Z a_l)(a_j^T S^-1 a_l) by look-ups) and its Cholesky, and two dense products
// (Z dS + dZ_aff dS_aff) S^-1: products with dS = sum dx_j a_j a_j^T - dt Pi are sparse (two
// columns per edge). The Cholesky factors that accept a step are those of the next iteration.
struct EResult {
  VectorXd x;
  MatrixXd W;  // dual matrix, trace 1 on the problem space, PSD
  double value = 0, bound = 0;
  int iterations = 0;
};

EResult solveE(const Design& D, double tol, int max_iter, const IterationReport& report);

// ---- Smooth criteria (finite p < 1): F_p(x) = tr(M^p)/p, log det M for p = 0, concave.
struct SmoothEval {
  bool ok = false;
  double F = -kInf;  // objective (for line searches)
  double phi = 0;    // ||L||_p
  VectorXd g;        // gradient a_j^T M^(p-1) a_j
  MatrixXd H;        // Hessian (negative semidefinite)
};

SmoothEval evalSmooth(const Design& D, const VectorXd& x, double p, bool derivatives,
                      bool gradient_only = false);

struct SmoothResult {
  VectorXd x;
  double value = 0, bound = 0;
  int iterations = 0;
};

SmoothResult solveSmooth(const Design& D, double p, double tol, int max_iter,
                         const IterationReport& report);

}  // namespace asf::graph::detail
