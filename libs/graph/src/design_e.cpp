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

}  // namespace

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
    const double tau = Z.cwiseProduct(Sinv).sum();           // tr(Z S^-1)
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

}  // namespace asf::graph::detail
