// Information of walks on graphs and certified optimal edge weights (thesis chapter 5).
// The solvers' numerics are in design_solvers.h and design_{numerics,e,smooth}.cpp.
#include <asf/errors.h>
#include <asf/graph/information.h>
#include <asf/text.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <unordered_set>

#include "design_solvers.h"

namespace asf::graph {

using Eigen::MatrixXd;
using Eigen::VectorXd;

using namespace detail;

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

double dOptimalitySparse(const Multigraph& g, const VectorXd& x) {
  checkWeights(g, x, "dOptimalitySparse");
  if (g.n < 2 || !supportConnectedImpl(g, x)) return 0;
  // L(x) without node 0's row and column: node v > 0 is unknown v - 1.
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(4 * g.edges.size());
  for (int j = 0; j < g.m(); ++j) {
    const auto& e = g.edges[j];
    const double w = x[j] * e.information;
    if (e.u == e.v || w == 0) continue;
    for (const int a : {e.u, e.v})
      if (a > 0) t.emplace_back(a - 1, a - 1, w);
    if (e.u > 0 && e.v > 0) {
      t.emplace_back(e.u - 1, e.v - 1, -w);
      t.emplace_back(e.v - 1, e.u - 1, -w);
    }
  }
  Eigen::SparseMatrix<double> L0(g.n - 1, g.n - 1);
  L0.setFromTriplets(t.begin(), t.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(L0);
  if (ldlt.info() != Eigen::Success) return 0;
  const VectorXd d = ldlt.vectorD();
  if (!(d.minCoeff() > 0)) return 0;
  const double log_pdet = std::log(static_cast<double>(g.n)) + d.array().log().sum();
  return std::exp(log_pdet / (g.n - 1));
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
