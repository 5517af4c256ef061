// Core of the sparse_lm back-end (see sparse_se2.h and README.md): the CHOLMOD factorization
// and the Levenberg-Marquardt iterations; the covariances are in sparse_se2_marginals.cpp.
#include "sparse_se2.h"

#include <asf/errors.h>
#include <asf/se2_edge.h>
#include <asf/text.h>
#include <cholmod.h>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <memory>
#include <optional>
#include <queue>
#include <sstream>

#include "lago_guess.h"
#include "sparse_problem.h"
#include "sparse_se2_impl.h"

namespace asf::sparse_lm {

using namespace detail;

using asf::NodeId;

namespace {

cholmod_sparse viewSparse(const Structure& S, const double* x) {
  cholmod_sparse A{};
  A.nrow = A.ncol = static_cast<std::size_t>(S.dim());
  A.nzmax = S.Ai.size();
  A.p = const_cast<int*>(S.Ap.data());
  A.i = const_cast<int*>(S.Ai.data());
  A.x = const_cast<double*>(x);
  A.stype = 1;  // upper triangle stored
  A.itype = CHOLMOD_INT;
  A.xtype = x ? CHOLMOD_REAL : CHOLMOD_PATTERN;
  A.dtype = CHOLMOD_DOUBLE;
  A.sorted = 1;
  A.packed = 1;
  return A;
}

cholmod_dense viewDense(double* x, std::size_t nrow, std::size_t ncol) {
  cholmod_dense B{};
  B.nrow = nrow;
  B.ncol = ncol;
  B.nzmax = nrow * ncol;
  B.d = nrow;
  B.x = x;
  B.xtype = CHOLMOD_REAL;
  B.dtype = CHOLMOD_DOUBLE;
  return B;
}

}  // namespace

void SparseSe2::Impl::prepare(Structure S_new, const Options& o) {
  const Timer timer(counters.t_analysis);
  if (L && S_new.sameAs(S)) {
    ++counters.reused;
    last_symbolic = "reused";
    S = std::move(S_new);  // same pattern; edge slots may differ (edges added in place)
    return;
  }
  const bool grew = L && S_new.grewFrom(S);
  std::vector<int> order;  // free indices in elimination order
  if (grew) {
    std::vector<char> seen(S_new.nfree, 0);
    const int* perm = static_cast<const int*>(L->Perm);
    for (std::size_t k = 0; k < L->n; ++k) {
      const int blk = perm[k] / 3;
      if (!seen[blk]) {
        seen[blk] = 1;
        order.push_back(blk);
      }
    }
    for (int j = S.nfree; j < S_new.nfree; ++j) order.push_back(j);
  }
  cholmod_factor* Lnew = analyze(S_new, order);
  double fill = cm.lnz / static_cast<double>(S_new.Ai.size());
  if (grew && fill > o.reorder_fill_ratio * fill_at_fresh) {
    cholmod_free_factor(&Lnew, &cm);
    Lnew = analyze(S_new, {});
    fill = cm.lnz / static_cast<double>(S_new.Ai.size());
    ++counters.fresh_orderings;
    last_symbolic = "fresh ordering (extended one had too much fill)";
    fill_at_fresh = fill;
  } else if (grew) {
    ++counters.extended_orderings;
    last_symbolic = "extended ordering";
  } else {
    ++counters.fresh_orderings;
    last_symbolic = "fresh ordering";
    fill_at_fresh = fill;
  }
  if (L) cholmod_free_factor(&L, &cm);
  L = Lnew;
  factor_valid = false;
  S = std::move(S_new);
  diag.resize(S.dim());
  for (int k = 0; k < S.dim(); ++k) diag[k] = S.Ap[k + 1] - 1;  // last entry of a column
}

cholmod_factor* SparseSe2::Impl::analyze(const Structure& s, std::vector<int> order) {
  const int nb = s.nfree;
  if (order.empty()) {
    std::vector<int> Bp(s.col_begin), Bi(s.blocks.size());
    for (std::size_t k = 0; k < s.blocks.size(); ++k) Bi[k] = s.blocks[k].second;
    cholmod_sparse B{};
    B.nrow = B.ncol = static_cast<std::size_t>(nb);
    B.nzmax = Bi.size();
    B.p = Bp.data();
    B.i = Bi.data();
    B.stype = 1;
    B.itype = CHOLMOD_INT;
    B.xtype = CHOLMOD_PATTERN;
    B.dtype = CHOLMOD_DOUBLE;
    B.sorted = 1;
    B.packed = 1;
    order.resize(nb);
    if (!cholmod_amd(&B, nullptr, 0, order.data(), &cm)) cholmodFailed("AMD ordering");
  }
  std::vector<int> perm(3 * nb);
  for (int k = 0; k < nb; ++k)
    for (int c = 0; c < 3; ++c) perm[3 * k + c] = 3 * order[k] + c;
  cm.nmethods = 1;
  cm.method[0].ordering = CHOLMOD_GIVEN;
  cm.postorder = 1;
  cholmod_sparse A = viewSparse(s, nullptr);
  cholmod_factor* F = cholmod_analyze_p(&A, perm.data(), nullptr, 0, &cm);
  if (!F) cholmodFailed("symbolic analysis");
  return F;
}

double SparseSe2::Impl::linearize(const Problem& P, const Poses& x, const Options& o) {
  const Timer timer(counters.t_linearize);
  H.assign(S.Ai.size(), 0.0);
  b.assign(S.dim(), 0.0);
  double F = 0;
  auto addDiag = [&](int j, const Eigen::Matrix3d& M) {
    const int k = S.diagBlock(j);
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r <= c; ++r) H[S.pos(j, k, r, c)] += M(r, c);
  };
  for (std::size_t k = 0; k < P.edges.size(); ++k) {
    const auto& e = P.edges[k];
    const auto lin = asf::se2::linearizeEdge(x[e.from], x[e.to], e.z);
    const double s = lin.e.dot(e.W * lin.e);
    F += robustCost(e.kernel, o.robust_delta, s);
    const Eigen::Matrix3d W = robustWeight(e.kernel, o.robust_delta, s) * e.W;
    const int a = S.free[e.from], c = S.free[e.to];
    if (a >= 0 && a == c) {  // self-loop: both Jacobians act on one pose
      const Eigen::Matrix3d J = lin.Ji + lin.Jj;
      addDiag(a, J.transpose() * W * J);
      Eigen::Map<Eigen::Vector3d>(&b[3 * a]) += J.transpose() * W * lin.e;
      continue;
    }
    const Eigen::Matrix3d WJj = W * lin.Jj;
    if (a >= 0) {
      const Eigen::Matrix3d JiTW = lin.Ji.transpose() * W;
      addDiag(a, JiTW * lin.Ji);
      Eigen::Map<Eigen::Vector3d>(&b[3 * a]) += JiTW * lin.e;
      if (c >= 0) {
        const Eigen::Matrix3d M = lin.Ji.transpose() * WJj;  // rows of a, columns of c
        const int blk = S.off[k];
        const int j = std::max(a, c), kk = blk - S.col_begin[j];
        for (int cc = 0; cc < 3; ++cc)
          for (int r = 0; r < 3; ++r) H[S.pos(j, kk, r, cc)] += a < c ? M(r, cc) : M(cc, r);
      }
    }
    if (c >= 0) {
      addDiag(c, lin.Jj.transpose() * WJj);
      Eigen::Map<Eigen::Vector3d>(&b[3 * c]) += lin.Jj.transpose() * W * lin.e;
    }
  }
  return F;
}

bool SparseSe2::Impl::factorize(const std::vector<double>& values) {
  const Timer timer(counters.t_factorize);
  cholmod_sparse A = viewSparse(S, values.data());
  const int ok = cholmod_factorize(&A, L, &cm);
  ++counters.factorizations;
  if (cm.status < 0 || (!ok && cm.status != CHOLMOD_NOT_POSDEF)) cholmodFailed("factorization");
  factor_valid = cm.status == CHOLMOD_OK && L->minor == L->n;
  return factor_valid;
}

std::vector<double> SparseSe2::Impl::solve(std::vector<double> B, std::size_t ncol) {
  const Timer timer(counters.t_solve);
  const std::size_t n = static_cast<std::size_t>(S.dim());
  cholmod_dense Bd = viewDense(B.data(), n, ncol);
  cholmod_dense* X = cholmod_solve(CHOLMOD_A, L, &Bd, &cm);
  if (!X) cholmodFailed("solve");
  const double* xv = static_cast<const double*>(X->x);
  std::copy(xv, xv + n * ncol, B.begin());
  cholmod_free_dense(&X, &cm);
  return B;
}

Eigen::MatrixXd SparseSe2::Impl::columns(const std::vector<int>& cols) {
  const std::size_t dim = static_cast<std::size_t>(S.dim());
  constexpr std::size_t kChunk = 16;  // pose columns per solve: 48 right-hand sides
  Eigen::MatrixXd X(dim, 3 * cols.size());
  for (std::size_t first = 0; first < cols.size(); first += kChunk) {
    const std::size_t k = std::min(kChunk, cols.size() - first);
    std::vector<double> B(dim * 3 * k, 0.0);
    for (std::size_t c = 0; c < 3 * k; ++c) B[c * dim + 3 * cols[first + c / 3] + c % 3] = 1;
    const std::vector<double> Y = solve(std::move(B), 3 * k);
    X.middleCols(3 * first, 3 * k) = Eigen::Map<const Eigen::MatrixXd>(Y.data(), dim, 3 * k);
  }
  return X;
}

void detail::validate(const asf::PoseGraph& g) {
  for (const auto& e : g.edges)
    if (e.from >= g.size() || e.to >= g.size())
      throw asf::Error("sparse_lm: edge " + std::to_string(e.from) + " -> " + std::to_string(e.to) +
                       " names a node that does not exist");
  for (NodeId f : g.fixed)
    if (f >= g.size())
      throw asf::Error("sparse_lm: fixed node " + std::to_string(f) + " does not exist");
}

/// Levenberg-Marquardt (or Gauss-Newton) iterations on P from x, at most o.max_iterations
/// linearizations counted in r.iterations; r.converged and r.message say how it ended.
/// Returns the cost at the final x.
double SparseSe2::Impl::iterate(const Problem& P, Poses& x, const Options& o,
                                asf::OptimizeReport& r, int& steps, int& accepted) {
  const int n = S.dim();
  const bool lm = o.method == Method::LevenbergMarquardt;

  r.converged = false;
  r.message = "reached max_iterations";
  LmState s;
  s.lambda = lm ? o.lambda_init : 0.0;
  s.F = cost(P, x, o);
  s.D.resize(n);
  s.x_new = x;
  bool stop = false;
  while (!stop && r.iterations < o.max_iterations) {
    // One iteration = one linearization; LM may try several dampings on it.
    s.F = linearize(P, x, o);
    ++r.iterations;
    double dmax = 0;
    for (int k = 0; k < n; ++k) dmax = std::max(dmax, H[diag[k]]);
    // Marquardt scaling; the floor keeps a direction without information damped.
    for (int k = 0; k < n; ++k) s.D[k] = std::max(H[diag[k]], 1e-9 * std::max(dmax, 1.0));
    s.xmax = 0;
    for (const auto& p : x) s.xmax = std::max(s.xmax, p.cwiseAbs().maxCoeff());
    stop = dampedSteps(P, x, s, o, r, steps, accepted);
  }
  return s.F;
}

bool SparseSe2::Impl::dampedSteps(const Problem& P, Poses& x, LmState& s, const Options& o,
                                  asf::OptimizeReport& r, int& steps, int& accepted) {
  const int n = S.dim();
  const bool lm = o.method == Method::LevenbergMarquardt;
  auto log = [&](const std::string& line) {
    if (o.log) o.log(line);
  };
  double &F = s.F, &lambda = s.lambda, &nu = s.nu;
  for (;;) {
    Ax = H;
    for (int k = 0; k < n; ++k) Ax[diag[k]] += lambda * s.D[k];
    ++steps;
    if (!factorize(Ax)) {
      // Not positive definite: H is singular (part of the graph not anchored to node 0)
      // or rounding at a tiny lambda. Damp more and retry.
      lambda = lambda > 0 ? lambda * nu : 1e-9;
      nu *= 2;
      if (o.verbosity >= 2)
        log("sparse_lm: iteration " + std::to_string(r.iterations) +
            ": matrix not positive definite, lambda -> " + asf::formatSignificant(lambda, 8));
      if (lambda > 1e16) {
        r.message = "the normal matrix is not positive definite at any damping";
        return true;
      }
      continue;
    }
    const Trial t = tryStep(P, x, s.x_new, o, lambda, s.D);
    const double F_new = t.F_new, hmax = t.hmax;
    const double rho = (F - F_new) / t.pred;
    const bool ok = std::isfinite(F_new) && F_new < F;
    // A step at the resolution of the doubles cannot improve anything.
    const bool tiny = hmax <= 1e-12 * (1 + s.xmax);
    if (o.verbosity >= 2)
      log("sparse_lm: iteration " + std::to_string(r.iterations) + ": chi2 " +
          asf::formatSignificant(F_new, 8) + (ok ? " accepted" : " rejected") + ", lambda " +
          asf::formatSignificant(lambda, 8) + ", gain ratio " + asf::formatSignificant(rho, 8) +
          ", max|dx| " + asf::formatSignificant(hmax, 8));
    if (ok) {
      const double rel = (F - F_new) / F;
      x.swap(s.x_new);
      s.x_new = x;
      F = F_new;
      ++accepted;
      if (lm) {
        lambda *= std::max(1.0 / 3, 1 - std::pow(2 * rho - 1, 3));
        nu = 2;
      }
      if (rel < o.tolerance || tiny || !(F > 0)) {
        r.converged = true;
        r.message = !(F > 0) ? "chi2 is zero"
                    : tiny   ? "step below numerical resolution"
                             : "relative chi2 decrease below tolerance";
        return true;
      }
      return false;
    }
    if (tiny) {
      r.converged = true;
      r.message = "step below numerical resolution";
      return true;
    }
    if (!lm) {
      // Gauss-Newton has no fallback: keep the best estimate and stop.
      r.message = "Gauss-Newton step does not lower chi2";
      return true;
    }
    lambda = lambda > 0 ? lambda * nu : 1e-9;
    nu *= 2;
    // lambda is relative to diag(H): beyond this the step is below rounding anyway.
    if (lambda > 1e16) {
      r.converged = true;
      r.message =
          "no step lowers chi2 further (lambda " + asf::formatSignificant(lambda, 8) + ")";
      return true;
    }
  }
}

SparseSe2::Impl::Trial SparseSe2::Impl::tryStep(const Problem& P, const Poses& x, Poses& x_new,
                                                const Options& o, double lambda,
                                                const std::vector<double>& D) {
  const int n = S.dim();
  std::vector<double> rhs(n);
  for (int k = 0; k < n; ++k) rhs[k] = -b[k];
  const std::vector<double> h = solve(rhs, 1);
  Trial t;
  for (int k = 0; k < n; ++k) {
    t.pred += -b[k] * h[k] + lambda * D[k] * h[k] * h[k];
    t.hmax = std::max(t.hmax, std::abs(h[k]));
  }
  for (std::size_t i = 0; i < x.size(); ++i) {
    const int f = S.free[i];
    if (f < 0) continue;
    x_new[i] = x[i] + Eigen::Vector3d(h[3 * f], h[3 * f + 1], h[3 * f + 2]);
    x_new[i].z() = asf::se2::wrapAngle(x_new[i].z());
  }
  const Timer timer(counters.t_cost);
  t.F_new = cost(P, x_new, o);
  return t;
}

asf::OptimizeReport SparseSe2::Impl::optimize(asf::PoseGraph& g, const Options& o) {
  validate(g);
  const Problem P(g, o);
  return run(g, P, Structure::of(g), o, o.lago_init);
}

asf::OptimizeReport SparseSe2::Impl::optimizeWindow(asf::PoseGraph& g,
                                                    const std::vector<NodeId>& window,
                                                    const std::vector<std::size_t>& edges,
                                                    const Options& o) {
  validate(g);
  for (std::size_t k : edges)
    if (k >= g.edges.size())
      throw asf::Error("sparse_lm: window edge " + std::to_string(k) + " does not exist");
  std::vector<char> held(g.size(), 1);
  for (NodeId v : window) {
    if (v >= g.size())
      throw asf::Error("sparse_lm: window node " + std::to_string(v) + " does not exist");
    held[v] = 0;
  }
  const std::vector<char> gauge = Structure::heldNodes(g);
  for (std::size_t i = 0; i < held.size(); ++i) held[i] = held[i] || gauge[i];
  const Problem P(g, edges, o);
  return run(g, P, Structure::of(held, P), o, false);
}

asf::OptimizeReport SparseSe2::Impl::run(asf::PoseGraph& g, const Problem& P, Structure S_new,
                                         const Options& o, bool lago) {
  const SerialOpenMp serial(!o.cholmod_openmp);
  asf::OptimizeReport r;
  Poses x = posesOf(g);
  double F = cost(P, x, o);
  if (!std::isfinite(F))
    throw asf::Error("sparse_lm: the initial chi2 is not finite (non-finite pose or edge?)");
  r.initial_chi2 = r.final_chi2 = F;
  r.converged = true;
  if (g.size() < 2 || P.edges.empty()) {
    r.message = "nothing to optimize";
    return r;
  }
  if (S_new.nfree == 0) {
    r.message = "nothing to optimize (every node is fixed)";
    return r;
  }
  if (!(F > 0)) {
    r.message = "chi2 is zero";
    return r;
  }
  std::string start = "from the graph's poses";
  if (lago) {
    const Timer timer(counters.t_init);
    Poses guess = x;
    if (lagoGuess(P, S_new, guess)) {
      const double F_guess = cost(P, guess, o);
      if (F_guess < F) {
        x.swap(guess);
        start = "from the LAGO guess (chi2 " + asf::formatSignificant(F_guess, 8) + ")";
        F = F_guess;
      } else {
        start = "from the graph's poses (LAGO guess chi2 " + asf::formatSignificant(F_guess, 8) +
                " not lower)";
      }
    }
  }
  prepare(std::move(S_new), o);
  int steps = 0, accepted = 0;
  F = iterate(P, x, o, r, steps, accepted);
  if (F < r.initial_chi2) {
    for (std::size_t i = 0; i < x.size(); ++i)
      if (S.free[i] >= 0) g.nodes[i].pose = mrpt::poses::CPose2D(x[i].x(), x[i].y(), x[i].z());
    ++g.revision;
  }
  r.final_chi2 = F;
  r.message += "; " + std::to_string(steps) + " factorizations, " + std::to_string(accepted) +
               " steps accepted; started " + start + "; symbolic: " + last_symbolic + " (fresh " +
               std::to_string(counters.fresh_orderings) + ", extended " +
               std::to_string(counters.extended_orderings) + ", reused " +
               std::to_string(counters.reused) + ")";
  if (o.verbosity >= 1 && o.log)
    o.log("sparse_lm: chi2 " + asf::formatSignificant(r.initial_chi2, 8) + " -> " +
          asf::formatSignificant(r.final_chi2, 8) + " in " + std::to_string(r.iterations) +
          " iterations (" + r.message + ")");
  return r;
}

SparseSe2::SparseSe2() : impl_(std::make_unique<Impl>()) {}
SparseSe2::~SparseSe2() = default;

asf::OptimizeReport SparseSe2::optimize(asf::PoseGraph& g, const Options& o) {
  return impl_->optimize(g, o);
}

asf::Marginals SparseSe2::marginals(const asf::PoseGraph& g,
                                    const std::vector<std::pair<NodeId, NodeId>>& cross,
                                    const Options& o) {
  return impl_->marginals(g, cross, o);
}

asf::OptimizeReport SparseSe2::optimizeWindow(asf::PoseGraph& g, const std::vector<NodeId>& window,
                                              const std::vector<std::size_t>& edges,
                                              const Options& o) {
  return impl_->optimizeWindow(g, window, edges, o);
}

std::optional<double> SparseSe2::decrementBound(const asf::PoseGraph& g, const Options& o) {
  return impl_->decrementBound(g, o);
}

std::size_t SparseSe2::factorNodes() const {
  return impl_->L && impl_->factor_valid ? impl_->S.free.size() : 0;
}

const Counters& SparseSe2::counters() const { return impl_->counters; }
const std::string& SparseSe2::lastSymbolic() const { return impl_->last_symbolic; }
std::size_t SparseSe2::lastCrossSolved() const { return impl_->last_cross_solved; }
std::size_t SparseSe2::factorNonzeros() const { return impl_->L ? impl_->L->xsize : 0; }

}  // namespace asf::sparse_lm
