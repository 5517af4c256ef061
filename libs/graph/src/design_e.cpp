// E-optimal design: a primal-dual interior point method with a rigorous certificate.
#include <asf/errors.h>

#include <algorithm>
#include <cmath>

#include "design_solvers.h"

namespace asf::graph::detail {

namespace {

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

/// The interior point method's state: the primal (x, t, S = L(x) - t Pi), the dual (Z, z, nu),
/// their Cholesky factors, and the Newton system of the current iteration.
class ESolver {
 public:
  ESolver(const Design& D, double tol, const IterationReport& report)
      : D_(D), m_(D.m), N_(D.N), k_(D.k()), Pi_(D.pi()), tol_(tol), report_(report) {}

  EResult run(int max_iter) {
    start();
    for (int it = 1; it <= max_iter; ++it) {
      if (!okS_) break;  // lost interiority (numerical end)
      const Step s = iterate(it);
      if (s == Step::Converged) return best_;
      if (s == Step::Stop) break;
    }
    consider(x_, Z_, best_.iterations);
    return best_;
  }

 private:
  enum class Step { Continue, Converged, Stop };
  struct Dir {
    VectorXd dx, dz;
    double dt = 0, dnu = 0;
    MatrixXd dS, dZ;
  };

  // Start: x uniform, t = lambda_min / 2, and the centred dual Z = S^-1 / tr S^-1 (Z S is a
  // multiple of Pi), which also puts Z's weight on the low eigenvectors of L(x), so the
  // starting bound is already of the order of the optimum.
  void start() {
    x_ = VectorXd::Constant(m_, 1.0 / m_);
    const double lmin0 = D_.spectrum(D_.sumOuter(x_))[0];
    if (!(lmin0 > 0)) throw Error("E-optimal design: the design vectors do not span the space");
    t_ = 0.5 * lmin0;
    S_ = D_.sumOuter(x_) - t_ * Pi_;
    if (!factorPD(D_, S_, cS_)) throw Error("E-optimal design: no interior starting point");
    Z_ = inverseFromLLT(cS_);
    D_.pad(Z_, -1.0);
    Z_ /= Z_.trace();
    const VectorXd za = D_.diagQuad(Z_);
    nu_ = za.maxCoeff() + lmin0;  // dual feasible, z of the order of the gap
    z_ = (nu_ - za.array()).matrix();
    best_.bound = kInf;
    okZ_ = factorPD(D_, Z_, cZ_);
    H_.resize(m_ + 1, m_ + 1);
  }

  /// Keeps the best certificate and the best primal separately, then pairs them; true when
  /// their gap is within the tolerance.
  bool consider(const VectorXd& xc, const MatrixXd& Zc, int it) {
    EResult r;
    certifyE(D_, xc, Zc, r);
    r.iterations = it;
    if (best_.bound == kInf || r.bound < best_.bound) {
      best_.bound = r.bound;
      best_.W = r.W;
    }
    if (best_.x.size() == 0 || r.value > best_.value) {
      best_.value = r.value;
      best_.x = r.x;
    }
    best_.iterations = it;
    return (best_.bound - best_.value) <= tol_ * best_.bound;
  }

  Step iterate(int it) {
    Sinv_ = inverseFromLLT(cS_);
    D_.pad(Sinv_, -1.0);
    const double mu = ((Z_.cwiseProduct(S_)).sum() + x_.dot(z_)) / (k_ + m_);
    // Certificate estimate at no cost: S > 0 gives lambda_min(L(x)) >= t, and a positive
    // definite Z gives the bound max_j a_j^T Z a_j / tr Z; certifyE then does it exactly.
    const VectorXd za = D_.diagQuad(Z_);
    const double lo = t_ / x_.sum(), hi = okZ_ ? za.maxCoeff() / Z_.trace() : nu_;
    if (report_) report_(it, lo, hi);
    if (hi - lo <= 0.2 * tol_ * hi || mu <= 0) {
      if (consider(x_, Z_, it)) return Step::Converged;
      if (mu <= 0) return Step::Stop;
    }
    if (!newtonSystem()) return Step::Stop;
    // Predictor (its steps only set sigma: a rough estimate will do), then corrector.
    const Dir aff = direction(0.0, nullptr);
    double ap, ad;
    steps(aff, ap, ad, 6);
    ap = std::min(1.0, ap);
    ad = std::min(1.0, ad);
    const MatrixXd Sa = S_ + ap * aff.dS, Za = Z_ + ad * aff.dZ;
    const double mu_aff =
        ((Za.cwiseProduct(Sa)).sum() + (x_ + ap * aff.dx).dot(z_ + ad * aff.dz)) / (k_ + m_);
    const double sigma = std::clamp(std::pow(mu_aff / mu, 3.0), 0.0, 1.0);
    const Dir d = direction(sigma * mu, &aff);
    steps(d, ap, ad, 40);
    acceptPrimal(d, std::min(1.0, 0.98 * ap));
    acceptDual(d, std::min(1.0, 0.98 * ad));
    best_.iterations = it;
    return Step::Continue;
  }

  /// The reduced Newton matrix in (dx, dt) and its factor; false if it is not positive
  /// definite.
  bool newtonSystem() {
    Ws_ = D_.rows(Sinv_);
    const MatrixXd Wz = D_.rows(Z_);
    const MatrixXd Rz = D_.quadRows(Wz), Rs = D_.quadRows(Ws_);
    const VectorXd c = Wz.cwiseProduct(Ws_).rowwise().sum();  // a_j^T Z S^-1 a_j
    const double tau = Z_.cwiseProduct(Sinv_).sum();          // tr(Z S^-1)
    sinv_ = Rs.diagonal();
    trSinv_ = Sinv_.trace();
    H_.topLeftCorner(m_, m_) = Rz.cwiseProduct(Rs);
    H_.topLeftCorner(m_, m_).diagonal() += z_.cwiseQuotient(x_);
    H_.block(0, m_, m_, 1) = -c;
    H_.block(m_, 0, 1, m_) = -c.transpose();
    H_(m_, m_) = tau;
    cH_.compute(H_);
    if (cH_.info() != Eigen::Success) return false;
    e_ = VectorXd::Zero(m_ + 1);
    e_.head(m_).setOnes();
    He_ = cH_.solve(e_);
    eHe_ = e_.dot(He_);
    re_ = 1.0 - x_.sum();
    return true;
  }

  Dir direction(double sigma_mu, const Dir* aff) const {
    VectorXd rhs(m_ + 1);
    rhs.head(m_) = sigma_mu * (sinv_ + x_.cwiseInverse()) - VectorXd::Constant(m_, nu_);
    rhs[m_] = 1.0 - sigma_mu * trSinv_;
    MatrixXd M;  // Z dS (+ dZ_aff dS_aff): the product that meets S^-1
    if (aff) {
      // Second-order term G = dZ_aff dS_aff S^-1: a_j^T G a_j and tr G without forming G.
      M = D_.mulSum(aff->dZ, aff->dx) - aff->dt * D_.mulPi(aff->dZ);
      rhs.head(m_) -= D_.rows(M).cwiseProduct(Ws_).rowwise().sum() +
                      aff->dz.cwiseProduct(aff->dx).cwiseQuotient(x_);
      rhs[m_] += M.cwiseProduct(Sinv_).sum();
    }
    const VectorXd Hr = cH_.solve(rhs);
    Dir d;
    d.dnu = (e_.dot(Hr) - re_) / eHe_;
    const VectorXd sol = Hr - d.dnu * He_;
    d.dx = sol.head(m_);
    d.dt = sol[m_];
    d.dS = D_.sumOuter(d.dx) - d.dt * Pi_;
    if (aff)
      M += D_.mulSum(Z_, d.dx) - d.dt * D_.mulPi(Z_);
    else
      M = D_.mulSum(Z_, d.dx) - d.dt * D_.mulPi(Z_);
    MatrixXd T(N_, N_);
    T.noalias() = M * Sinv_;
    d.dZ = sigma_mu * Sinv_ - Z_ - 0.5 * (T + T.transpose());
    d.dz = (sigma_mu * x_.cwiseInverse() - z_ - z_.cwiseProduct(d.dx).cwiseQuotient(x_));
    if (aff) d.dz -= aff->dz.cwiseProduct(aff->dx).cwiseQuotient(x_);
    return d;
  }

  /// The longest primal (ap) and dual (ad) steps that keep x, z > 0 and S, Z positive
  /// definite.
  void steps(const Dir& d, double& ap, double& ad, int kcap) {
    ap = ad = kInf;
    for (int j = 0; j < m_; ++j) {
      if (d.dx[j] < 0) ap = std::min(ap, -x_[j] / d.dx[j]);
      if (d.dz[j] < 0) ad = std::min(ad, -z_[j] / d.dz[j]);
    }
    ap = std::min(ap, maxStepPD(cS_, d.dS, vS_, kcap));
    ad = std::min(ad, okZ_ ? maxStepPD(cZ_, d.dZ, vZ_, kcap) : 0.0);
  }

  // Accept the longest step (backtracking) whose new S, resp. Z, factors: those Cholesky
  // factors serve the next iteration.
  void acceptPrimal(const Dir& d, double ap) {
    okS_ = false;
    for (int back = 0; back < 30 && !okS_; ++back, ap *= 0.8) {
      const VectorXd xn = x_ + ap * d.dx;
      const double tn = t_ + ap * d.dt;
      MatrixXd Sn = D_.sumOuter(xn) - tn * Pi_;
      if (factorPD(D_, Sn, cS_)) {
        okS_ = true;
        x_ = xn;
        t_ = tn;
        S_.swap(Sn);
      }
    }
    if (!okS_) okS_ = factorPD(D_, S_, cS_);  // keep x, t (and the old factor)
  }

  void acceptDual(const Dir& d, double ad) {
    bool okZn = false;
    for (int back = 0; back < 30 && !okZn; ++back, ad *= 0.8) {
      MatrixXd Zn = Z_ + ad * d.dZ;
      Zn = 0.5 * (Zn + Zn.transpose()).eval();
      if (factorPD(D_, Zn, cZ_)) {
        okZn = true;
        Z_.swap(Zn);
        z_ += ad * d.dz;
        nu_ += ad * d.dnu;
      }
    }
    if (!okZn) okZ_ = factorPD(D_, Z_, cZ_);
  }

  const Design& D_;
  const int m_, N_, k_;
  const MatrixXd Pi_;
  const double tol_;
  const IterationReport& report_;
  VectorXd x_, z_, vS_, vZ_;  // vS_, vZ_: Lanczos warm starts (step lengths)
  double t_ = 0, nu_ = 0;
  MatrixXd S_, Z_, Sinv_, Ws_, H_;
  Eigen::LLT<MatrixXd> cS_, cZ_, cH_;
  bool okS_ = true, okZ_ = false;
  // The Newton system of the current iteration.
  VectorXd sinv_, e_, He_;
  double trSinv_ = 0, eHe_ = 0, re_ = 0;
  EResult best_;
};

}  // namespace

EResult solveE(const Design& D, double tol, int max_iter, const IterationReport& report) {
  return ESolver(D, tol, report).run(max_iter);
}

}  // namespace asf::graph::detail
