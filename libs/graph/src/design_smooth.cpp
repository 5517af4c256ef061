// Optimal design for the smooth criteria (p < 1, p != -inf): damped Newton on the simplex.
#include <asf/errors.h>

#include <algorithm>
#include <cmath>

#include "design_solvers.h"

namespace asf::graph::detail {

namespace {

/// p = 0 (log det, D) and p = -1 (minus the trace of the inverse, A): one Cholesky factor.
SmoothEval evalByCholesky(const Design& D, const MatrixXd& L, double p, bool derivatives,
                          bool gradient_only) {
  SmoothEval r;
  const int k = D.k();
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

/// General p: spectral decomposition on the problem space.
SmoothEval evalSpectral(const Design& D, const MatrixXd& L, double p, bool derivatives,
                        bool gradient_only) {
  SmoothEval r;
  const int k = D.k(), m = D.m;
  MatrixXd Y = L;
  double s = 0;
  if (D.graph) {
    s = 2.0 * L.cwiseAbs().rowwise().sum().maxCoeff() + 1e-300;
    D.pad(Y, s);
  }
  Eigen::SelfAdjointEigenSolver<MatrixXd> es(
      Y, derivatives ? Eigen::ComputeEigenvectors : Eigen::EigenvaluesOnly);
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

}  // namespace

SmoothEval evalSmooth(const Design& D, const VectorXd& x, double p, bool derivatives,
                      bool gradient_only) {
  derivatives = derivatives || gradient_only;
  const MatrixXd L = D.sumOuter(x);
  if (p == 0.0 || p == -1.0) return evalByCholesky(D, L, p, derivatives, gradient_only);
  return evalSpectral(D, L, p, derivatives, gradient_only);
}

namespace {

// Warm start: multiplicative updates x_j <- x_j (g_j / x^T g)^(1/(1-p)) (Silvey-Titterington-
// Torsney; monotone for D) are cheap (no Hessian) and remove most of the initial error.
void warmStart(const Design& D, double p, VectorXd& x) {
  for (int w = 0; w < 3; ++w) {
    SmoothEval e0 = evalSmooth(D, x, p, false, true);
    if (!e0.ok) break;
    const double lam = x.dot(e0.g);
    VectorXd xt = x.cwiseProduct((e0.g / lam).array().pow(1.0 / (1.0 - p)).matrix());
    xt /= xt.sum();
    x = xt;
  }
}

/// Factors K = -H on the free set F (regularized; more if the first attempt fails).
void factorNewton(const SmoothEval& ev, const std::vector<int>& F, Eigen::LLT<MatrixXd>& c) {
  const int f = static_cast<int>(F.size());
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

/// The Newton step on the free set F: K d = g - l 1 with sum d = 0. Zero weights whose step
/// would be negative are then fixed at zero; the system without them is solved with the
/// same Cholesky factor through the bordered (capacitance) formula, not refactored: with E
/// the columns of the fixed variables and C = E^T K^-1 E, the solution of the reduced system
/// is K^-1 r - K^-1 E C^-1 E^T K^-1 r (zero on the fixed variables).
VectorXd newtonStep(const Eigen::LLT<MatrixXd>& c, const SmoothEval& ev, const std::vector<int>& F,
                    const VectorXd& x) {
  const int f = static_cast<int>(F.size()), m = static_cast<int>(x.size());
  VectorXd gF(f);
  for (int b = 0; b < f; ++b) gF[b] = ev.g[F[b]];
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
  return d;
}

/// Projection arc (Bertsekas): x(a) = P_simplex-ish(x + a d) by clipping at zero, so several
/// weights can reach zero in one step; Armijo test along the arc. False when no step is
/// accepted; `ev` is brought up to the new x.
bool arcSearch(const Design& D, double p, const VectorXd& d, double ratio, VectorXd& x,
               SmoothEval& ev) {
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
  if (!accepted) return false;
  if (!evaluated) ev = evalSmooth(D, x, p, true);
  return ev.ok;
}

}  // namespace

SmoothResult solveSmooth(const Design& D, double p, double tol, int max_iter,
                         const IterationReport& report) {
  const int m = D.m;
  VectorXd x = VectorXd::Constant(m, 1.0 / m);
  SmoothResult out;
  warmStart(D, p, x);
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
    // Close to the optimum (relative gap below 1e-4) with an unchanged free set, the factor
    // of the previous Hessian is reused (a chord step: it converges fast there, and the
    // certificate does not depend on it); the step after a chord step uses a fresh Hessian.
    const bool chord = F == Fprev && ratio - 1.0 < 1e-4 * ratio && !lastChord;
    if (!chord) factorNewton(ev, F, c);
    lastChord = chord;
    Fprev = F;
    const VectorXd d = newtonStep(c, ev, F, x);
    if (!(ev.g.dot(d) > 0)) break;  // no ascent left at machine precision
    if (!arcSearch(D, p, d, ratio, x, ev)) break;
  }
  return out;
}

}  // namespace asf::graph::detail
