// Information of walks on graphs and certified optimal edge weights (thesis chapter 5).
//
// Numerics. Everything works on the n x n matrices of the graph: a matrix X restricted to the
// complement of the all-ones vector 1 is represented by X + J/n (J = 11^T), which is invertible
// when X is on 1-perp, and whose inverse is X^+ + J/n. For a_j = e_u - e_v (orthogonal to 1)
// the quadratic forms a_j^T X a_l are then four look-ups, so the gradients and Hessians of the
// design problems cost O(m n + m^2) once X is known, instead of O(m n^2) with a reduced basis.
#include <asf/errors.h>
#include <asf/graph_information.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <unordered_set>

namespace asf::graph {

using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

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
    if (!graph) return Eigen::SelfAdjointEigenSolver<MatrixXd>(X, Eigen::EigenvaluesOnly).eigenvalues();
    // Shift the 1 direction above every other eigenvalue (Gershgorin) and drop it.
    const double s = 2.0 * X.cwiseAbs().rowwise().sum().maxCoeff() + 1e-300;
    MatrixXd Y = X;
    pad(Y, s);
    const VectorXd e = Eigen::SelfAdjointEigenSolver<MatrixXd>(Y, Eigen::EigenvaluesOnly).eigenvalues();
    return e.head(N - 1);
  }
};

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
  const MatrixXd T = X.bottomLeftCorner(n - h, h) * X.topLeftCorner(h, h).triangularView<Eigen::Lower>();
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
double maxStepPD(const Eigen::LLT<MatrixXd>& X, const MatrixXd& dX, VectorXd& start,
                 int kcap = 40, double rtol = 1e-3) {
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

// The certificate of a dual Z, made rigorous: W = Z shifted to PSD on the problem space,
// bound = max_j a_j^T W a_j / tr W; value = lambda_min at x clipped to the simplex.
void certifyE(const Design& D, const VectorXd& xin, const MatrixXd& Z, EResult& r) {
  r.x = xin.cwiseMax(0.0);
  r.x /= r.x.sum();
  r.value = std::max(0.0, D.spectrum(D.sumOuter(r.x))[0]);
  MatrixXd W = 0.5 * (Z + Z.transpose());
  const double zmin = D.spectrum(W)[0];
  if (zmin < 0) W -= zmin * D.pi();
  const double tr = W.trace();
  r.W = W / tr;
  r.bound = D.diagQuad(r.W).maxCoeff();
}

using IterationReport = std::function<void(int, double, double)>;

EResult solveE(const Design& D, double tol, int max_iter, const IterationReport& report) {
  const int m = D.m, N = D.N, k = D.k();
  const MatrixXd Pi = D.pi();
  VectorXd x = VectorXd::Constant(m, 1.0 / m);
  const double lmin0 = D.spectrum(D.sumOuter(x))[0];
  if (!(lmin0 > 0)) throw Error("E-optimal design: the design vectors do not span the space");
  // Start: x uniform, t = lambda_min / 2, and the centred dual Z = S^-1 / tr S^-1 (Z S is a
  // multiple of Pi), which also puts Z's weight on the low eigenvectors of L(x), so the
  // starting bound is already of the order of the optimum.
  double t = 0.5 * lmin0;
  MatrixXd S = D.sumOuter(x) - t * Pi;
  Eigen::LLT<MatrixXd> cS, cZ;
  if (!factorPD(D, S, cS)) throw Error("E-optimal design: no interior starting point");
  MatrixXd Z = inverseFromLLT(cS);
  D.pad(Z, -1.0);
  Z /= Z.trace();
  VectorXd za = D.diagQuad(Z);
  double nu = za.maxCoeff() + lmin0;  // dual feasible, z of the order of the gap
  VectorXd z = (nu - za.array()).matrix();

  EResult best;
  best.bound = kInf;
  auto consider = [&](const VectorXd& xc, const MatrixXd& Zc, int it) {
    EResult r;
    certifyE(D, xc, Zc, r);
    r.iterations = it;
    // Keep the best certificate and the best primal separately, then pair them.
    if (best.bound == kInf || r.bound < best.bound) {
      best.bound = r.bound;
      best.W = r.W;
    }
    if (best.x.size() == 0 || r.value > best.value) {
      best.value = r.value;
      best.x = r.x;
    }
    best.iterations = it;
    return (best.bound - best.value) <= tol * best.bound;
  };

  bool okS = true, okZ = factorPD(D, Z, cZ);
  MatrixXd Sinv, Ws, Wz, H(m + 1, m + 1);
  VectorXd vS, vZ;  // Lanczos warm starts (step lengths)
  for (int it = 1; it <= max_iter; ++it) {
    if (!okS) break;  // lost interiority (numerical end)
    Sinv = inverseFromLLT(cS);
    D.pad(Sinv, -1.0);
    const double mu = ((Z.cwiseProduct(S)).sum() + x.dot(z)) / (k + m);
    // Certificate estimate at no cost: S > 0 gives lambda_min(L(x)) >= t, and a positive
    // definite Z gives the bound max_j a_j^T Z a_j / tr Z; certifyE then does it exactly.
    za = D.diagQuad(Z);
    const double lo = t / x.sum(), hi = okZ ? za.maxCoeff() / Z.trace() : nu;
    if (report) report(it, lo, hi);
    if (hi - lo <= 0.2 * tol * hi || mu <= 0) {
      if (consider(x, Z, it)) return best;
      if (mu <= 0) break;
    }
    Ws = D.rows(Sinv);
    Wz = D.rows(Z);
    const MatrixXd Rz = D.quadRows(Wz), Rs = D.quadRows(Ws);
    const VectorXd c = Wz.cwiseProduct(Ws).rowwise().sum();  // a_j^T Z S^-1 a_j
    const double tau = Z.cwiseProduct(Sinv).sum();            // tr(Z S^-1)
    const VectorXd sinv = Rs.diagonal();
    const double trSinv = Sinv.trace();
    H.topLeftCorner(m, m) = Rz.cwiseProduct(Rs);
    H.topLeftCorner(m, m).diagonal() += z.cwiseQuotient(x);
    H.block(0, m, m, 1) = -c;
    H.block(m, 0, 1, m) = -c.transpose();
    H(m, m) = tau;
    Eigen::LLT<MatrixXd> cH(H);
    if (cH.info() != Eigen::Success) break;
    VectorXd e = VectorXd::Zero(m + 1);
    e.head(m).setOnes();
    const VectorXd He = cH.solve(e);
    const double eHe = e.dot(He);
    const double re = 1.0 - x.sum();

    struct Dir {
      VectorXd dx, dz;
      double dt = 0, dnu = 0;
      MatrixXd dS, dZ;
    };
    auto direction = [&](double sigma_mu, const Dir* aff) {
      VectorXd rhs(m + 1);
      rhs.head(m) = sigma_mu * (sinv + x.cwiseInverse()) - VectorXd::Constant(m, nu);
      rhs[m] = 1.0 - sigma_mu * trSinv;
      MatrixXd M;  // Z dS (+ dZ_aff dS_aff): the product that meets S^-1
      if (aff) {
        // Second-order term G = dZ_aff dS_aff S^-1: a_j^T G a_j and tr G without forming G.
        M = D.mulSum(aff->dZ, aff->dx) - aff->dt * D.mulPi(aff->dZ);
        rhs.head(m) -= D.rows(M).cwiseProduct(Ws).rowwise().sum() +
                       aff->dz.cwiseProduct(aff->dx).cwiseQuotient(x);
        rhs[m] += M.cwiseProduct(Sinv).sum();
      }
      const VectorXd Hr = cH.solve(rhs);
      Dir d;
      d.dnu = (e.dot(Hr) - re) / eHe;
      const VectorXd sol = Hr - d.dnu * He;
      d.dx = sol.head(m);
      d.dt = sol[m];
      d.dS = D.sumOuter(d.dx) - d.dt * Pi;
      if (aff)
        M += D.mulSum(Z, d.dx) - d.dt * D.mulPi(Z);
      else
        M = D.mulSum(Z, d.dx) - d.dt * D.mulPi(Z);
      MatrixXd T(N, N);
      T.noalias() = M * Sinv;
      d.dZ = sigma_mu * Sinv - Z - 0.5 * (T + T.transpose());
      d.dz = (sigma_mu * x.cwiseInverse() - z - z.cwiseProduct(d.dx).cwiseQuotient(x));
      if (aff) d.dz -= aff->dz.cwiseProduct(aff->dx).cwiseQuotient(x);
      return d;
    };
    auto steps = [&](const Dir& d, double& ap, double& ad, int kcap) {
      ap = ad = kInf;
      for (int j = 0; j < m; ++j) {
        if (d.dx[j] < 0) ap = std::min(ap, -x[j] / d.dx[j]);
        if (d.dz[j] < 0) ad = std::min(ad, -z[j] / d.dz[j]);
      }
      ap = std::min(ap, maxStepPD(cS, d.dS, vS, kcap));
      ad = std::min(ad, okZ ? maxStepPD(cZ, d.dZ, vZ, kcap) : 0.0);
    };
    const Dir aff = direction(0.0, nullptr);
    double ap, ad;
    steps(aff, ap, ad, 6);  // the predictor's steps only set sigma: a rough estimate will do
    ap = std::min(1.0, ap);
    ad = std::min(1.0, ad);
    const MatrixXd Sa = S + ap * aff.dS, Za = Z + ad * aff.dZ;
    const double mu_aff =
        ((Za.cwiseProduct(Sa)).sum() + (x + ap * aff.dx).dot(z + ad * aff.dz)) / (k + m);
    const double sigma = std::clamp(std::pow(mu_aff / mu, 3.0), 0.0, 1.0);
    const Dir d = direction(sigma * mu, &aff);
    steps(d, ap, ad, 40);
    ap = std::min(1.0, 0.98 * ap);
    ad = std::min(1.0, 0.98 * ad);
    // Accept the longest step (backtracking) whose new S, resp. Z, factors: those Cholesky
    // factors serve the next iteration.
    okS = false;
    for (int back = 0; back < 30 && !okS; ++back, ap *= 0.8) {
      const VectorXd xn = x + ap * d.dx;
      const double tn = t + ap * d.dt;
      MatrixXd Sn = D.sumOuter(xn) - tn * Pi;
      if (factorPD(D, Sn, cS)) {
        okS = true;
        x = xn;
        t = tn;
        S.swap(Sn);
      }
    }
    if (!okS) okS = factorPD(D, S, cS);  // keep x, t (and the old factor)
    bool okZn = false;
    for (int back = 0; back < 30 && !okZn; ++back, ad *= 0.8) {
      MatrixXd Zn = Z + ad * d.dZ;
      Zn = 0.5 * (Zn + Zn.transpose()).eval();
      if (factorPD(D, Zn, cZ)) {
        okZn = true;
        Z.swap(Zn);
        z += ad * d.dz;
        nu += ad * d.dnu;
      }
    }
    if (!okZn) okZ = factorPD(D, Z, cZ);
    best.iterations = it;
  }
  consider(x, Z, best.iterations);
  return best;
}

// ---- Smooth criteria (finite p < 1): F_p(x) = tr(M^p)/p, log det M for p = 0, concave.
struct SmoothEval {
  bool ok = false;
  double F = -kInf;  // objective (for line searches)
  double phi = 0;    // ||L||_p
  VectorXd g;        // gradient a_j^T M^(p-1) a_j
  MatrixXd H;        // Hessian (negative semidefinite)
};

SmoothEval evalSmooth(const Design& D, const VectorXd& x, double p, bool derivatives,
                      bool gradient_only = false) {
  SmoothEval r;
  derivatives = derivatives || gradient_only;
  const int k = D.k(), m = D.m;
  MatrixXd L = D.sumOuter(x);
  if (p == 0.0 || p == -1.0) {
    MatrixXd Lp = L;
    D.pad(Lp);
    Eigen::LLT<MatrixXd> c(Lp);
    if (c.info() != Eigen::Success) return r;
    const double logdet = 2.0 * c.matrixLLT().diagonal().array().log().sum();
    if (p == 0.0 && !derivatives) {
      r.ok = std::isfinite(logdet);
      r.F = logdet;
      r.phi = std::exp(logdet / k);
      return r;
    }
    MatrixXd P = inverseFromLLT(c);
    D.pad(P, -1.0);  // P = M^+ on 1-perp
    if (p == 0.0) {
      r.F = logdet;
      r.phi = std::exp(logdet / k);
      if (gradient_only) {
        r.g = D.diagQuad(P);
      } else if (derivatives) {
        const MatrixXd R = D.quad(P);
        r.g = R.diagonal();
        r.H = -R.cwiseProduct(R);
      }
    } else {
      const double tr = P.trace();
      if (!(tr > 0)) return r;
      r.F = -tr;
      r.phi = k / tr;
      if (gradient_only) {
        r.g = D.rows(P).rowwise().squaredNorm();  // a_j^T P^2 a_j = |P a_j|^2
      } else if (derivatives) {
        const MatrixXd R = D.quad(P), R2 = D.quad(P * P);
        r.g = R2.diagonal();
        r.H = -2.0 * R.cwiseProduct(R2);
      }
    }
    r.ok = std::isfinite(r.F);
    return r;
  }
  // General p: spectral decomposition on the problem space.
  MatrixXd Y = L;
  double s = 0;
  if (D.graph) {
    s = 2.0 * L.cwiseAbs().rowwise().sum().maxCoeff() + 1e-300;
    D.pad(Y, s);
  }
  Eigen::SelfAdjointEigenSolver<MatrixXd> es(Y, derivatives ? Eigen::ComputeEigenvectors
                                                            : Eigen::EigenvaluesOnly);
  const VectorXd mu = es.eigenvalues().head(k);
  if (!(mu[0] > 0)) return r;
  // Scaled sums so that tiny/huge mu^p do not over/underflow in phi.
  const double ref = p < 0 ? mu[0] : mu[k - 1];
  const double mean = (mu / ref).array().pow(p).mean();
  r.phi = ref * std::pow(mean, 1.0 / p);
  r.F = mu.array().pow(p).sum() / p;
  r.ok = std::isfinite(r.F) && std::isfinite(r.phi);
  if (!derivatives || !r.ok) return r;
  const MatrixXd V = es.eigenvectors().leftCols(k);
  const MatrixXd B = D.rows(V);  // B(j, i) = a_j . v_i
  const VectorXd f1 = mu.array().pow(p - 1);
  r.g = B.cwiseAbs2() * f1;
  if (gradient_only) return r;
  // Daleckii-Krein: H_jl = sum_ii' G_ii' B_ji B_ji' B_li B_li'.
  MatrixXd G(k, k);
  for (int i = 0; i < k; ++i)
    for (int i2 = 0; i2 < k; ++i2) {
      const double a = mu[i], b = mu[i2];
      G(i, i2) = std::abs(a - b) > 1e-9 * std::max(a, b) ? (f1[i] - f1[i2]) / (a - b)
                                                         : (p - 1) * std::pow(0.5 * (a + b), p - 2);
    }
  r.H = MatrixXd::Zero(m, m);
  MatrixXd C(m, k);
  for (int i = 0; i < k; ++i) {
    C = B.col(i).asDiagonal() * B;
    r.H.noalias() += (C * G.row(i).transpose().asDiagonal()) * C.transpose();
  }
  return r;
}

struct SmoothResult {
  VectorXd x;
  double value = 0, bound = 0;
  int iterations = 0;
};

SmoothResult solveSmooth(const Design& D, double p, double tol, int max_iter,
                         const IterationReport& report) {
  const int m = D.m;
  VectorXd x = VectorXd::Constant(m, 1.0 / m);
  SmoothResult out;
  // Warm start: multiplicative updates x_j <- x_j (g_j / x^T g)^(1/(1-p)) (Silvey-Titterington-
  // Torsney; monotone for D) are cheap (no Hessian) and remove most of the initial error.
  for (int w = 0; w < 3; ++w) {
    SmoothEval e0 = evalSmooth(D, x, p, false, true);
    if (!e0.ok) break;
    const double lam = x.dot(e0.g);
    VectorXd xt = x.cwiseProduct((e0.g / lam).array().pow(1.0 / (1.0 - p)).matrix());
    xt /= xt.sum();
    x = xt;
  }
  SmoothEval ev = evalSmooth(D, x, p, true);
  if (!ev.ok) throw Error("optimal design: the uniform weights have no information");
  Eigen::LLT<MatrixXd> c;  // Newton system factor (kept for chord steps)
  std::vector<int> Fprev;
  bool lastChord = false;
  for (int it = 0;; ++it) {
    const double lam = x.dot(ev.g);
    const double ratio = ev.g.maxCoeff() / lam;  // bound / value
    out.x = x;
    out.value = ev.phi;
    out.bound = ev.phi * ratio;
    out.iterations = it;
    if (report) report(it, out.value, out.bound);
    if (ratio - 1.0 <= tol * ratio || it >= max_iter) break;
    // Free set: positive weights, and zero weights whose gradient beats the multiplier.
    std::vector<int> F;
    for (int j = 0; j < m; ++j)
      if (x[j] > 0 || ev.g[j] > lam) F.push_back(j);
    // Newton step on the free set: K d = g - l 1 with sum d = 0, K = -H. Zero weights whose
    // step would be negative are then fixed at zero; the system without them is solved with
    // the same Cholesky factor through the bordered (capacitance) formula, not refactored:
    // with E the columns of the fixed variables and C = E^T K^-1 E, the solution of the
    // reduced system is K^-1 r - K^-1 E C^-1 E^T K^-1 r (zero on the fixed variables).
    // Close to the optimum (relative gap below 1e-4) with an unchanged free set, the factor
    // of the previous Hessian is reused (a chord step: it converges fast there, and the
    // certificate does not depend on it); the step after a chord step uses a fresh Hessian.
    const int f = static_cast<int>(F.size());
    VectorXd gF(f);
    for (int b = 0; b < f; ++b) gF[b] = ev.g[F[b]];
    const bool chord = F == Fprev && ratio - 1.0 < 1e-4 * ratio && !lastChord;
    if (!chord) {
      MatrixXd K(f, f);
      for (int b = 0; b < f; ++b)
        for (int a = 0; a < f; ++a) K(a, b) = -ev.H(F[a], F[b]);
      const double reg = 1e-13 * K.diagonal().mean();
      K.diagonal().array() += reg;
      c.compute(K);
      if (c.info() != Eigen::Success) {
        K.diagonal().array() += 1e-8 * K.diagonal().mean();
        c.compute(K);
      }
    }
    lastChord = chord;
    Fprev = F;
    const VectorXd Kg0 = c.solve(gF), K10 = c.solve(VectorXd::Ones(f));
    std::vector<int> fixed;  // positions in F
    std::vector<char> isFixed(f, 0);
    VectorXd d = VectorXd::Zero(m);
    for (int pass = 0; pass < 8; ++pass) {
      VectorXd Kg = Kg0, K1 = K10;
      if (!fixed.empty()) {
        const int r = static_cast<int>(fixed.size());
        MatrixXd E = MatrixXd::Zero(f, r);
        for (int q = 0; q < r; ++q) E(fixed[q], q) = 1.0;
        const MatrixXd KE = c.solve(E);
        MatrixXd C(r, r);
        VectorXd eg(r), e1(r);
        for (int q = 0; q < r; ++q) {
          C.row(q) = KE.row(fixed[q]);
          eg[q] = Kg0[fixed[q]];
          e1[q] = K10[fixed[q]];
        }
        const Eigen::LDLT<MatrixXd> cC(0.5 * (C + C.transpose()));
        Kg -= KE * cC.solve(eg);
        K1 -= KE * cC.solve(e1);
        for (int q : fixed) Kg[q] = K1[q] = 0;
      }
      const double l = Kg.sum() / K1.sum();
      const VectorXd dF = Kg - l * K1;
      d.setZero();
      int added = 0;
      for (int a = 0; a < f; ++a) {
        if (isFixed[a]) continue;
        d[F[a]] = dF[a];
        if (x[F[a]] <= 0 && dF[a] < 0) {  // zero weights that would go negative stay at zero
          isFixed[a] = 1;
          fixed.push_back(a);
          ++added;
        }
      }
      if (added == 0) break;
      d.setZero();
    }
    const double slope = ev.g.dot(d);
    if (!(slope > 0)) break;  // no ascent left at machine precision
    // Projection arc (Bertsekas): x(a) = P_simplex-ish(x + a d) by clipping at zero, so
    // several weights can reach zero in one step; Armijo test along the arc.
    double a = 1.0;
    bool accepted = false, evaluated = false;
    for (int ls = 0; ls < 60 && !accepted; ++ls, a *= 0.5) {
      VectorXd xt = (x + a * d).cwiseMax(0.0);
      xt /= xt.sum();
      const SmoothEval trial = evalSmooth(D, xt, p, false);
      if (!trial.ok) continue;
      const double pred = ev.g.dot(xt - x);
      // Round-off dominates the Armijo test once steps are tiny: accept a non-decrease.
      if (trial.F >= ev.F + 1e-4 * pred || (a < 1e-10 && trial.F >= ev.F)) {
        x = xt;
        accepted = true;
      } else if (ls == 0 && pred <= 1e-9 * std::abs(ev.F)) {
        // The full Newton step promises an increase of F below its round-off, so F can not
        // rank the points; the certificate (the quantity that matters) can: take the step
        // if it lowers bound / value.
        SmoothEval full = evalSmooth(D, xt, p, true);
        if (full.ok && full.g.maxCoeff() / xt.dot(full.g) < ratio) {
          x = xt;
          ev = std::move(full);
          accepted = evaluated = true;
        }
      }
    }
    if (!accepted) break;
    if (!evaluated) ev = evalSmooth(D, x, p, true);
    if (!ev.ok) break;
  }
  return out;
}

}  // namespace

double parseCriterion(const std::string& text) {
  std::string t;
  for (char ch : text)
    if (!std::isspace(static_cast<unsigned char>(ch))) t += ch;
  std::string up = t;
  for (auto& ch : up) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  if (up == "T") return kCriterionT;
  if (up == "D") return kCriterionD;
  if (up == "A") return kCriterionA;
  if (up == "E" || up == "-INF") return kCriterionE;
  if (up.rfind("P=", 0) == 0) t = t.substr(2);
  std::size_t pos = 0;
  double p = 0;
  try {
    p = std::stod(t, &pos);
  } catch (const std::exception&) {
    pos = std::string::npos;
  }
  if (pos != t.size() || std::isnan(p) || p > 1)
    throw InputError("criterion '" + text + "': expected T, D, A, E or a number p <= 1");
  return p;
}

std::string criterionName(double p) {
  if (p == kCriterionT) return "T";
  if (p == kCriterionD) return "D";
  if (p == kCriterionA) return "A";
  if (p == kCriterionE) return "E";
  std::ostringstream os;
  os << "p=" << p;
  return os.str();
}

bool supportConnected(const Multigraph& g, const VectorXd& x) {
  checkWeights(g, x, "supportConnected");
  return supportConnectedImpl(g, x);
}

MatrixXd laplacian(const Multigraph& g, const VectorXd& x) {
  checkWeights(g, x, "laplacian");
  MatrixXd L = MatrixXd::Zero(g.n, g.n);
  for (int j = 0; j < g.m(); ++j) {
    const auto& e = g.edges[j];
    if (e.u == e.v) continue;
    const double w = x[j] * e.information;
    L(e.u, e.u) += w;
    L(e.v, e.v) += w;
    L(e.u, e.v) -= w;
    L(e.v, e.u) -= w;
  }
  return L;
}

VectorXd reducedSpectrum(const Multigraph& g, const VectorXd& x) {
  if (g.n < 2) return VectorXd();
  Design D;
  D.graph = true;
  D.N = g.n;
  return D.spectrum(laplacian(g, x));
}

double powerMean(const VectorXd& mu, double p) {
  const int k = static_cast<int>(mu.size());
  if (k == 0) return 0;
  if (p == 1.0) return mu.mean();
  const double lo = mu.minCoeff();
  if (p <= 0 && !(lo > 0)) return 0;
  if (p == kCriterionE) return lo;
  if (p == 0) return std::exp(mu.array().log().mean());
  const double ref = p < 0 ? lo : mu.maxCoeff();
  if (!(ref > 0)) return 0;
  return ref * std::pow((mu / ref).array().pow(p).mean(), 1.0 / p);
}

Information information(const Multigraph& g, const VectorXd& x, double p) {
  checkWeights(g, x, "information");
  if (std::isnan(p) || p > 1) throw InputError("information: criterion p must be <= 1");
  Information r;
  r.total = x.sum();
  r.connected = supportConnectedImpl(g, x);
  if (!r.connected) return r;
  r.value = std::max(0.0, powerMean(reducedSpectrum(g, x), p));
  r.rate = r.total > 0 ? r.value / r.total : 0;
  return r;
}

VectorXd walkEdgeCounts(const Multigraph& g, const std::vector<int>& seq) {
  VectorXd c = VectorXd::Zero(g.m());
  int at = -1;  // unknown until the first two edges fix the direction
  for (std::size_t i = 0; i < seq.size(); ++i) {
    const int j = seq[i];
    if (j < 0 || j >= g.m())
      throw InputError("walk: edge index " + std::to_string(j) + " at position " +
                       std::to_string(i) + " is not an edge (m = " + std::to_string(g.m()) + ")");
    const auto& e = g.edges[j];
    if (i == 0) {
      // Start at the end not shared with the next edge (either, if both or none are).
      at = e.v;
      if (seq.size() > 1 && seq[1] >= 0 && seq[1] < g.m()) {
        const auto& f = g.edges[seq[1]];
        if ((e.u == f.u || e.u == f.v) && !(e.v == f.u || e.v == f.v)) at = e.u;
      }
    } else {
      if (e.u == at) {
        at = e.v;
      } else if (e.v == at) {
        at = e.u;
      } else {
        throw InputError("walk: edge " + std::to_string(j) + " at position " + std::to_string(i) +
                         " does not start at node " + std::to_string(at + 1) +
                         " where the walk is");
      }
    }
    c[j] += 1;
  }
  return c;
}

Information walkInformation(const Multigraph& g, const std::vector<int>& seq, double p) {
  return information(g, walkEdgeCounts(g, seq), p);
}

double efficiency(const Multigraph& g, const VectorXd& counts, double p, double optimum) {
  if (!(optimum > 0)) return 0;
  return information(g, counts, p).rate / optimum;
}

namespace {

// Parallel edges add information only through sum_j x_j alpha_j over the pair, so on the
// simplex a pair's weight is best spent on its most informative edge(s): the optimum is found
// on one edge per node pair (the largest alpha) and shared equally among that pair's ties.
// Without this, the Newton steps move weight along directions of zero curvature.
struct ParallelReduction {
  Multigraph reduced;
  std::vector<std::vector<int>> ties;  // reduced edge -> original edges sharing its weight
};

ParallelReduction reduceParallelEdges(const Multigraph& g) {
  ParallelReduction r;
  r.reduced.n = g.n;
  std::map<std::pair<int, int>, int> pair_index;
  for (int j = 0; j < g.m(); ++j) {
    const auto& e = g.edges[j];
    if (e.u == e.v) continue;
    const auto key = std::minmax(e.u, e.v);
    const auto [it, added] = pair_index.emplace(key, r.reduced.m());
    if (added) {
      r.reduced.edges.push_back(e);
      r.ties.push_back({j});
      continue;
    }
    Edge& rep = r.reduced.edges[it->second];
    auto& tie = r.ties[it->second];
    if (e.information > rep.information * (1 + 1e-12)) {
      rep = e;
      tie = {j};
    } else if (e.information >= rep.information * (1 - 1e-12)) {
      tie.push_back(j);
    }
  }
  return r;
}

}  // namespace

OptimalDesign optimalDesign(const Multigraph& g, double p, const DesignOptions& opt) {
  if (std::isnan(p) || p > 1) throw InputError("optimal design: criterion p must be <= 1");
  const auto t0 = std::chrono::steady_clock::now();
  checkEdgeInformation(g, "optimal design");
  {
    ParallelReduction pr = reduceParallelEdges(g);
    if (pr.reduced.m() < g.m()) {
      OptimalDesign r = optimalDesign(pr.reduced, p, opt);
      Eigen::VectorXd w = Eigen::VectorXd::Zero(g.m());
      for (int a = 0; a < pr.reduced.m(); ++a)
        for (int j : pr.ties[a]) w[j] = r.weights[a] / pr.ties[a].size();
      r.weights = w;
      r.time_ms = msSince(t0);
      return r;
    }
  }
  OptimalDesign r;
  r.p = p;
  std::vector<int> kept;
  const Design D = graphDesign(g, kept);
  r.weights = VectorXd::Zero(g.m());
  for (int j : kept) r.weights[j] = 1.0 / kept.size();
  r.connected = !kept.empty() && g.connected();
  if (!r.connected) {
    r.converged = true;
    r.time_ms = msSince(t0);
    return r;
  }
  const bool isE = p == kCriterionE;
  const double tol = opt.tolerance > 0 ? opt.tolerance : (isE ? 5e-6 : 5e-7);
  const int k = g.n - 1;
  if (p == 1.0) {
    // T = trace(L(x)) / k = 2 sum_j x_j alpha_j / k: linear, so the optimum puts all weight
    // on the most informative edges (shared equally among ties).
    double best = 0;
    for (int j : kept) best = std::max(best, g.edges[j].information);
    std::vector<int> top;
    for (int j : kept)
      if (g.edges[j].information >= best * (1 - 1e-12)) top.push_back(j);
    r.weights.setZero();
    for (int j : top) r.weights[j] = 1.0 / top.size();
    r.value = r.upper_bound = 2.0 * best / k;
  } else if (isE) {
    const EResult e = solveE(D, tol, opt.max_iterations, opt.on_iteration);
    for (std::size_t a = 0; a < kept.size(); ++a) r.weights[kept[a]] = e.x[a];
    r.value = e.value;
    r.upper_bound = e.bound;
    r.dual = e.W;
    r.iterations = e.iterations;
  } else {
    const SmoothResult s = solveSmooth(D, p, tol, opt.max_iterations, opt.on_iteration);
    for (std::size_t a = 0; a < kept.size(); ++a) r.weights[kept[a]] = s.x[a];
    r.value = s.value;
    r.upper_bound = s.bound;
    r.iterations = s.iterations;
  }
  r.upper_bound = std::max(r.upper_bound, r.value);
  r.gap = r.upper_bound - r.value;
  r.relative_gap = r.upper_bound > 0 ? r.gap / r.upper_bound : 0;
  r.converged = r.relative_gap <= tol;
  r.time_ms = msSince(t0);
  return r;
}

OptimalDesign optimalDesignE(const MatrixXd& A, const DesignOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  if (A.rows() < 1 || A.cols() < 1) throw InputError("optimalDesignE: empty design matrix");
  Design D;
  D.graph = false;
  D.N = static_cast<int>(A.cols());
  D.m = static_cast<int>(A.rows());
  D.A = A;
  const double tol = opt.tolerance > 0 ? opt.tolerance : 5e-6;
  OptimalDesign r;
  r.p = kCriterionE;
  r.connected = true;
  const EResult e = solveE(D, tol, opt.max_iterations, opt.on_iteration);
  r.weights = e.x;
  r.value = e.value;
  r.upper_bound = std::max(e.bound, e.value);
  r.dual = e.W;
  r.iterations = e.iterations;
  r.gap = r.upper_bound - r.value;
  r.relative_gap = r.upper_bound > 0 ? r.gap / r.upper_bound : 0;
  r.converged = r.relative_gap <= tol;
  r.time_ms = msSince(t0);
  return r;
}

double dualBoundE(const Multigraph& g, const MatrixXd& W) {
  if (W.rows() != g.n || W.cols() != g.n)
    throw InputError("dualBoundE: W must be " + std::to_string(g.n) + " x " + std::to_string(g.n));
  std::vector<int> kept;
  const Design D = graphDesign(g, kept);
  if (D.m == 0) return 0;
  const MatrixXd Pi = D.pi();
  const MatrixXd Wp = Pi * (0.5 * (W + W.transpose())) * Pi;
  const double tr = Wp.trace();
  if (!(tr > 0)) throw InputError("dualBoundE: W has no positive trace on 1-perp");
  return D.diagQuad(Wp).maxCoeff() / tr;
}

double certificateBound(const Multigraph& g, const VectorXd& x, double p, double cluster_tol) {
  checkWeights(g, x, "certificateBound");
  if (std::isnan(p) || p > 1) throw InputError("certificateBound: criterion p must be <= 1");
  if (!supportConnectedImpl(g, x)) return 0;
  std::vector<int> kept;
  const Design D = graphDesign(g, kept);
  VectorXd y(D.m);
  for (int a = 0; a < D.m; ++a) y[a] = x[kept[a]];
  y /= y.sum();
  const int k = g.n - 1;
  if (p == 1.0) {
    double best = 0;
    for (const auto& e : g.edges)
      if (e.u != e.v) best = std::max(best, e.information);
    return 2.0 * best / k;
  }
  if (p != kCriterionE) {
    const SmoothEval ev = evalSmooth(D, y, p, true);
    if (!ev.ok) return 0;
    return ev.phi * ev.g.maxCoeff() / y.dot(ev.g);
  }
  const MatrixXd L = D.sumOuter(y);
  MatrixXd Y = L;
  D.pad(Y, 2.0 * L.cwiseAbs().rowwise().sum().maxCoeff() + 1e-300);
  Eigen::SelfAdjointEigenSolver<MatrixXd> es(Y);
  const VectorXd mu = es.eigenvalues().head(k);
  int r = 1;
  while (r < k && mu[r] <= mu[0] * (1 + cluster_tol) + 1e-14 * mu[k - 1]) ++r;
  const MatrixXd B = D.rows(es.eigenvectors().leftCols(r));  // b_j = V_r^T a_j
  if (r == 1) return B.col(0).cwiseAbs2().maxCoeff();
  DesignOptions o;
  o.tolerance = 1e-9;
  return optimalDesignE(B, o).upper_bound;
}

}  // namespace asf::graph
