// Expected-uncertainty path planning (thesis chapter 3), first part: Algorithm 1 (the expected
// covariance over relocalization hypotheses), the relocalization probability and the baseline
// criteria. The reduced-graph path search is in path_search.cpp, the planner and the plan
// drawing in criterion_planner.cpp.
#include <asf/errors.h>
#include <asf/planning/expected_uncertainty.h>
#include <asf/params.h>
#include <asf/planning/place_recognition.h>
#include <asf/io/image_io.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <boost/math/special_functions/erf.hpp>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <queue>
#include <random>
#include <set>
#include <sstream>
#include <unordered_map>

#include "path_index.h"

namespace asf::planning {

namespace {

using Mat3 = Eigen::Matrix3d;
using mrpt::poses::CPose2D;

double normalCdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

double normalQuantile(double p) {
  // Clamped so that a probability of exactly 0 or 1 from round-off stays finite.
  p = std::clamp(p, 1e-300, 1.0 - 1e-16);
  return -std::sqrt(2.0) * boost::math::erfc_inv(2.0 * p);
}

/// Lower-triangular L with L L^T = cov; pivots below tol (relative) become zero columns,
/// i.e. a point mass along that direction. Throws on a clearly negative pivot.
Eigen::MatrixXd semiCholesky(const Eigen::MatrixXd& cov) {
  const Eigen::Index n = cov.rows();
  const double scale = std::max(cov.diagonal().cwiseAbs().maxCoeff(), 1e-300);
  const double tol = 1e-12 * scale;
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    double d = cov(j, j) - L.row(j).head(j).squaredNorm();
    if (d < -1e-8 * scale)
      throw Error("gaussianBoxProbability: covariance is not positive semi-definite (pivot " +
                  std::to_string(d) + " at " + std::to_string(j) + ")");
    if (d <= tol) continue;  // degenerate direction
    L(j, j) = std::sqrt(d);
    for (Eigen::Index i = j + 1; i < n; ++i)
      L(i, j) = (cov(i, j) - L.row(i).head(j).dot(L.row(j).head(j))) / L(j, j);
  }
  return L;
}

/// Generator of a rank-1 lattice: fractional parts of square roots of primes (Richtmyer).
double latticeGenerator(int dim) {
  static const int kPrimes[] = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53};
  const double r = std::sqrt(static_cast<double>(kPrimes[dim % 16]));
  return r - std::floor(r);
}

/// Rotation of the translation part: blockdiag(R(phi), 1).
Mat3 rot3(double phi) {
  Mat3 R = Mat3::Identity();
  const double c = std::cos(phi), s = std::sin(phi);
  R.topLeftCorner<2, 2>() << c, -s, s, c;
  return R;
}

Mat3 symmetric(const Mat3& m) { return 0.5 * (m + m.transpose()); }

/// Covariance of edge e's mean as additive (x, y, phi) in the frame of e.from (the inverse
/// of edgeInformation's mapping, without its floor).
Mat3 edgeCovarianceForward(const PoseEdge& e) {
  const Mat3 cov_err = e.information.inverse();
  const Mat3 R = rot3(e.mean.phi());
  return symmetric(R * cov_err * R.transpose());
}

/// Covariance of the inverse relative pose (-)d, in the frame of d's end.
Mat3 invertedCovariance(const CPose2D& d, const Mat3& cov) {
  const double c = std::cos(d.phi()), s = std::sin(d.phi()), x = d.x(), y = d.y();
  Mat3 J;
  J << -c, -s, x * s - y * c,  //
      s, -c, x * c + y * s,    //
      0, 0, -1;
  return symmetric(J * cov * J.transpose());
}

/// Jacobians of a (+) b with respect to a and b (as in composeWithCov).
void composeJacobians(const CPose2D& a, const CPose2D& b, Mat3& Ja, Mat3& Jb) {
  const double c = std::cos(a.phi()), s = std::sin(a.phi());
  Ja = Mat3::Identity();
  Ja(0, 2) = -s * b.x() - c * b.y();
  Ja(1, 2) = c * b.x() - s * b.y();
  Jb = rot3(a.phi());
}

double checkedProbability(double p, std::size_t k, std::size_t t) {
  if (!(p >= 0 && p <= 1))
    throw Error("relocalization probability " + std::to_string(p) + " at step " +
                std::to_string(t) + " (hypothesis " + std::to_string(k) + ") is outside [0, 1]");
  return p;
}

}  // namespace

namespace detail {

PathModel makePathModel(const PoseGraph& g, const EdgeIndex& index, const Marginals* m,
                        const std::vector<NodeId>& path, const VirtualIndex* virt) {
  PathModel p;
  p.nodes = path;
  p.marginals = m;
  const std::size_t n = g.size();
  for (NodeId v : path)
    if (v >= n)
      throw Error("path: node " + std::to_string(v) + " does not exist (the graph has " +
                  std::to_string(n) + " nodes)");
  if (m && m->node.size() != n)
    throw Error("path: the marginals have " + std::to_string(m->node.size()) + " node blocks for " +
                std::to_string(n) + " nodes");
  p.pose.reserve(path.size());
  p.sigma.reserve(path.size());
  p.motion.assign(path.size(), CPose2D());
  p.motion_cov.assign(path.size(), Mat3::Zero());
  for (std::size_t t = 0; t < path.size(); ++t) {
    p.pose.push_back(g.nodes[path[t]].pose);
    p.sigma.push_back(m ? m->node[path[t]] : Mat3::Zero());
    if (t == 0) continue;
    const NodeId a = path[t - 1], b = path[t];
    const auto* edges = index.find(a, b);
    const VirtualEdge* ve = (!edges && virt && a != b) ? virt->find(a, b) : nullptr;
    if ((!edges && !ve) || a == b)
      throw Error("path: nodes " + std::to_string(a) + " and " + std::to_string(b) +
                  " are consecutive but share no edge" + (virt ? " (nor a virtual edge)" : ""));
    CPose2D d = p.pose[t] - p.pose[t - 1];  // b's estimate in a's frame
    d.normalizePhi();
    p.motion[t] = d;
    if (ve) {
      // A virtual edge: odometry only, its covariance in the frame of the step's start.
      if (p.virtual_step.empty()) {
        p.virtual_step.assign(path.size(), 0);
        p.virtual_length.assign(path.size(), 0.0);
      }
      p.virtual_step[t] = 1;
      p.virtual_length[t] = ve->length;
      p.motion_cov[t] = a == ve->a ? ve->covariance_ab : ve->covariance_ba;
      continue;
    }
    // Parallel edges are independent measurements of the same motion: add information.
    Mat3 info = Mat3::Zero();
    for (std::size_t i : *edges) {
      const PoseEdge& e = g.edges[i];
      const Mat3 fwd = edgeCovarianceForward(e);
      info += (e.from == a ? fwd : invertedCovariance(e.mean, fwd)).inverse();
    }
    p.motion_cov[t] = symmetric(info.inverse());
  }
  return p;
}

}  // namespace detail

using namespace detail;

// ---------------------------------------------------------------------------------------

namespace {

/// Genz's separation of variables for P(a <= L y <= b), y standard normal and L lower
/// triangular: one variable at a time, each on the part of its interval the previous ones leave.
struct GenzSeparation {
  const Eigen::MatrixXd& L;
  const Eigen::VectorXd& a;
  const Eigen::VectorXd& b;

  /// The part of variable i's interval left once the previous y's are fixed (their sum s).
  void interval(Eigen::Index i, double s, double& d, double& e) const {
    if (L(i, i) > 0) {
      d = normalCdf((a(i) - s) / L(i, i));
      e = normalCdf((b(i) - s) / L(i, i));
    } else {  // point mass at s
      d = 0;
      e = (a(i) <= s && s <= b(i)) ? 1 : 0;
    }
  }

  /// The integrand at lattice point q of generator gen under the shift; y is scratch space.
  double at(int q, const std::vector<double>& gen, const std::vector<double>& shift, double d0,
            double e0, Eigen::VectorXd& y) const {
    const Eigen::Index n = L.rows();
    double f = e0 - d0;
    double d = d0, e = e0;
    for (Eigen::Index i = 0; i < n && f > 0; ++i) {
      if (i > 0) {
        const double s = L.row(i).head(i).dot(y.head(i));
        interval(i, s, d, e);
        f *= e - d;
        if (f <= 0) break;
      }
      if (i + 1 < n) {
        // Baker's tent transform of the shifted lattice point: periodizes the integrand.
        double w = std::fmod(q * gen[i] + shift[i], 1.0);
        w = 1 - std::abs(2 * w - 1);
        y(i) = L(i, i) > 0 ? normalQuantile(d + w * (e - d)) : 0.0;
      }
    }
    return f;
  }
};

}  // namespace

BoxProbability gaussianBoxProbability(const Eigen::VectorXd& mean, const Eigen::MatrixXd& cov,
                                      const Eigen::VectorXd& lower, const Eigen::VectorXd& upper,
                                      int points, int shifts, std::uint64_t seed) {
  const Eigen::Index n = mean.size();
  if (cov.rows() != n || cov.cols() != n || lower.size() != n || upper.size() != n)
    throw Error("gaussianBoxProbability: sizes differ");
  if (!cov.isApprox(cov.transpose(), 1e-9) && !(cov - cov.transpose()).isZero(1e-12))
    throw Error("gaussianBoxProbability: covariance is not symmetric");
  BoxProbability r;
  for (Eigen::Index i = 0; i < n; ++i)
    if (!(lower(i) < upper(i))) return r;
  if (n == 0) {
    r.value = 1;
    return r;
  }
  const Eigen::MatrixXd L = semiCholesky(cov);
  const Eigen::VectorXd a = lower - mean, b = upper - mean;
  const GenzSeparation genz{L, a, b};
  double d0, e0;
  genz.interval(0, 0, d0, e0);
  // Exact when the variables decouple (diagonal factor) or in one dimension.
  const bool diagonal = L.isDiagonal(0.0) || n == 1;
  if (diagonal) {
    double v = e0 - d0;
    for (Eigen::Index i = 1; i < n; ++i) {
      double d, e;
      genz.interval(i, 0, d, e);
      v *= e - d;
    }
    r.value = v;
    return r;
  }
  points = std::max(points, 2);
  shifts = std::max(shifts, 2);
  const int per_shift = std::max(points / shifts, 1);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unif(0, 1);
  std::vector<double> gen(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) gen[i] = latticeGenerator(static_cast<int>(i));
  std::vector<double> shift(static_cast<std::size_t>(n));
  Eigen::VectorXd y(n);
  double sum = 0, sum2 = 0;
  for (int sh = 0; sh < shifts; ++sh) {
    for (auto& v : shift) v = unif(rng);
    double acc = 0;
    for (int q = 1; q <= per_shift; ++q) acc += std::max(genz.at(q, gen, shift, d0, e0, y), 0.0);
    const double est = acc / per_shift;
    sum += est;
    sum2 += est * est;
  }
  r.value = sum / shifts;
  const double var = std::max(sum2 / shifts - r.value * r.value, 0.0) * shifts / (shifts - 1);
  r.error = std::sqrt(var / shifts);
  return r;
}

// ---------------------------------------------------------------------------------------

PathModel makePathModel(const PoseGraph& g, const Marginals* marginals,
                        const std::vector<NodeId>& path,
                        const std::vector<VirtualEdge>* virtual_edges) {
  const VirtualIndex vi(virtual_edges);
  return makePathModel(g, EdgeIndex(g), marginals, path, virtual_edges ? &vi : nullptr);
}

double pathLength(const PathModel& path) {
  double d = 0;
  for (std::size_t t = 1; t < path.nodes.size(); ++t)
    d += path.isVirtual(t) ? path.virtual_length[t] : path.motion[t].norm();
  return d;
}

bool crossCovariance(const Marginals& m, NodeId a, NodeId b, Eigen::Matrix3d& out) {
  if (a == b && a < m.node.size()) {
    out = m.node[a];
    return true;
  }
  auto it = m.cross.find({a, b});
  if (it != m.cross.end()) {
    out = it->second;
    return true;
  }
  it = m.cross.find({b, a});
  if (it != m.cross.end()) {
    out = it->second.transpose();
    return true;
  }
  out.setZero();
  return false;
}

// ---------------------------------------------------------------------------------------

ExpectedCovariance expectedCovariance(const PathModel& path, const RelocProbFn& p,
                                      double prune_below) {
  struct Hypothesis {
    std::size_t k;
    Mat3 C, chain;
    double prob;
  };
  ExpectedCovariance out;
  const std::size_t m = path.steps();
  out.prob.assign(m + 1, 0.0);
  if (path.nodes.empty()) return out;
  std::vector<Hypothesis> H;
  H.reserve(m + 1);
  H.push_back({0, path.sigma[0], Mat3::Identity(), 1.0});
  for (std::size_t t = 1; t <= m; ++t) {
    Mat3 Ja, Jb;
    composeJacobians(path.pose[t - 1], path.motion[t], Ja, Jb);
    const Mat3 Q = Jb * path.motion_cov[t] * Jb.transpose();
    double relocalized = 0;
    std::size_t kept = 0;
    for (Hypothesis& h : H) {
      h.C = symmetric(Ja * h.C * Ja.transpose() + Q);
      h.chain = Ja * h.chain;
      double pt = 0;  // no relocalization on a virtual step
      if (!path.isVirtual(t)) {
        pt = checkedProbability(p(RelocQuery{h.k, t, h.C, h.chain}), h.k, t);
        ++out.evaluations;
      }
      relocalized += h.prob * pt;
      h.prob *= 1 - pt;
      if (prune_below > 0 && h.prob < prune_below) {
        out.pruned_mass += h.prob;
        continue;
      }
      H[kept++] = h;
    }
    H.resize(kept);
    H.push_back({t, path.sigma[t], Mat3::Identity(), relocalized});
  }
  for (const Hypothesis& h : H) {
    out.mean += h.prob * h.C;
    out.prob[h.k] = h.prob;
  }
  out.mean = symmetric(out.mean);
  return out;
}

Eigen::Matrix3d expectedCovarianceBruteForce(const PathModel& path, const RelocProbFn& p) {
  const std::size_t m = path.steps();
  if (m > 24) throw Error("expectedCovarianceBruteForce: 2^" + std::to_string(m) + " is too many");
  Mat3 sum = Mat3::Zero();
  if (path.nodes.empty()) return sum;
  for (std::uint64_t mask = 0; mask < (std::uint64_t{1} << m); ++mask) {
    Mat3 C = path.sigma[0], chain = Mat3::Identity();
    std::size_t k = 0;
    double prob = 1;
    for (std::size_t t = 1; t <= m; ++t) {
      Mat3 Ja, Jb;
      composeJacobians(path.pose[t - 1], path.motion[t], Ja, Jb);
      C = Ja * C * Ja.transpose() + Jb * path.motion_cov[t] * Jb.transpose();
      chain = Ja * chain;
      const double pt =
          path.isVirtual(t) ? 0.0 : checkedProbability(p(RelocQuery{k, t, C, chain}), k, t);
      if (mask >> (t - 1) & 1) {
        prob *= pt;
        C = path.sigma[t];
        chain = Mat3::Identity();
        k = t;
      } else {
        prob *= 1 - pt;
      }
    }
    sum += prob * C;
  }
  return symmetric(sum);
}

// ---------------------------------------------------------------------------------------

std::map<NodeId, double> readRecognitionProbabilities(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the recognition probability file");
  std::map<NodeId, double> out;
  std::string line;
  for (int lineno = 1; std::getline(in, line); ++lineno) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream ss(line);
    std::string first;
    if (!(ss >> first)) continue;  // blank or comment
    const std::string where = path + ":" + std::to_string(lineno) + ": ";
    long long id = -1;
    double p = 0;
    std::string extra;
    std::istringstream ids(first);
    if (!(ids >> id) || !ids.eof() || id < 0 || id > std::numeric_limits<NodeId>::max() ||
        !(ss >> p) || (ss >> extra))
      throw InputError(where + "expected 'node_id probability', got '" + line + "'");
    if (!(p >= 0 && p <= 1))
      throw InputError(where + "probability " + std::to_string(p) + " is outside [0, 1]");
    if (!out.emplace(static_cast<NodeId>(id), p).second)
      throw InputError(where + "node " + std::to_string(id) + " is listed twice");
  }
  return out;
}

RelocProbFn relocalizationProbability(const PathModel& path, const RelocalizationOptions& o,
                                      std::size_t* missing_cross) {
  const Eigen::Vector3d half(o.half_x, o.half_y, o.half_phi);
  return [&path, o, half, missing_cross](const RelocQuery& q) {
    const NodeId node = path.nodes[q.t];
    auto it = o.p_recognition_by_node.find(node);
    const double p_rec = it == o.p_recognition_by_node.end() ? o.p_recognition : it->second;
    if (p_rec <= 0) return 0.0;
    Mat3 X = Mat3::Zero();  // Cov(robot, x_{n_t})
    if (o.use_cross && path.marginals) {
      Mat3 cross;
      if (crossCovariance(*path.marginals, path.nodes[q.k], node, cross))
        X = q.chain * cross;
      else if (missing_cross)
        ++*missing_cross;
    }
    // Relative pose robot -> node at the mean (robot on the node): d = M (x_t - r).
    const Mat3 M = rot3(path.pose[q.t].phi()).transpose();
    Mat3 Cd = symmetric(M * (q.robot_cov - X - X.transpose() + path.sigma[q.t]) * M.transpose());
    // Round-off can leave tiny negative eigenvalues; the mass is taken of the PSD part.
    Eigen::SelfAdjointEigenSolver<Mat3> es(Cd);
    Cd = es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).asDiagonal() *
         es.eigenvectors().transpose();
    const BoxProbability b = gaussianBoxProbability(Eigen::Vector3d::Zero(), Cd, -half, half,
                                                    o.points, o.shifts, o.seed);
    return std::clamp(p_rec * b.value, 0.0, 1.0);
  };
}

// ---------------------------------------------------------------------------------------

const char* criterionName(Criterion c) {
  switch (c) {
    case Criterion::ExpectedUncertainty:
      return "expected_uncertainty";
    case Criterion::MechanicalWork:
      return "mechanical_work";
    case Criterion::SumDopt:
      return "sum_dopt";
    case Criterion::Distance:
      return "distance";
  }
  return "?";
}

const char* scalarName(Scalar s) {
  switch (s) {
    case Scalar::Det:
      return "det";
    case Scalar::Trace:
      return "trace";
    case Scalar::DetCbrt:
      return "det_cbrt";
  }
  return "?";
}

bool parseScalar(const std::string& s, Scalar& out) {
  for (Scalar v : {Scalar::Det, Scalar::Trace, Scalar::DetCbrt})
    if (s == scalarName(v)) {
      out = v;
      return true;
    }
  return false;
}

double scalarOf(const Eigen::Matrix3d& c, Scalar s) {
  switch (s) {
    case Scalar::Det:
      return c.determinant();
    case Scalar::Trace:
      return c.trace();
    case Scalar::DetCbrt:
      return std::cbrt(c.determinant());
  }
  return 0;
}

CriterionOptions criterionOptionsFrom(const Params& params, std::uint64_t ctx_seed) {
  CriterionOptions o;
  o.reloc.seed = ctx_seed;
  if (params.has("scalar") && !parseScalar(params.getString("scalar"), o.scalar))
    params.fail("scalar", "expected det, trace or det_cbrt");
  if (params.has("window_x")) o.reloc.half_x = params.getDouble("window_x");
  if (params.has("window_y")) o.reloc.half_y = params.getDouble("window_y");
  if (params.has("window_phi_deg"))
    o.reloc.half_phi = params.getDouble("window_phi_deg") * M_PI / 180.0;
  if (params.has("p_recognition")) o.reloc.p_recognition = params.getDouble("p_recognition");
  if (params.has("p_recognition_file")) {
    const std::string f = params.getString("p_recognition_file");
    if (!f.empty()) {
      try {
        o.reloc.p_recognition_by_node = readRecognitionProbabilities(f);
      } catch (const InputError& e) {
        params.fail("p_recognition_file", e.what());
      }
    }
  }
  if (params.has("qmc_points")) o.reloc.points = static_cast<int>(params.getInt("qmc_points"));
  if (params.has("qmc_shifts")) o.reloc.shifts = static_cast<int>(params.getInt("qmc_shifts"));
  if (params.has("use_cross")) o.reloc.use_cross = params.getBool("use_cross");
  if (params.has("prune_below")) o.prune_below = params.getDouble("prune_below");
  if (params.has("seed") && params.getInt("seed") != 0)  // 0: the run's seed
    o.reloc.seed = static_cast<std::uint64_t>(params.getInt("seed"));
  if (params.has("tie_tolerance")) o.tie_tolerance = params.getDouble("tie_tolerance");
  if (params.has("recognition_samples"))
    o.recognition_samples = static_cast<int>(params.getInt("recognition_samples"));
  if (params.has("recognition_map_radius"))
    o.recognition_map_radius = params.getDouble("recognition_map_radius");
  return o;
}

PathCost evaluatePath(Criterion c, const PathModel& path, const CriterionOptions& o) {
  PathCost r;
  const std::size_t m = path.steps();
  switch (c) {
    case Criterion::ExpectedUncertainty: {
      const RelocProbFn p = relocalizationProbability(path, o.reloc, &r.missing_cross);
      r.expected = expectedCovariance(path, p, o.prune_below).mean;
      r.cost = scalarOf(r.expected, o.scalar);
      r.label = std::string(scalarName(o.scalar)) + "(E[C])";
      break;
    }
    case Criterion::MechanicalWork: {
      // U = det((O^-1 + Sigma^-1)^-1) written without inverses, so a zero Sigma (the gauge)
      // or a zero O gives U = 0 instead of a singular matrix.
      auto U = [&](std::size_t t, const Mat3& O) {
        const double den = (O + path.sigma[t]).determinant();
        return den > 0 ? path.sigma[t].determinant() * O.determinant() / den : 0.0;
      };
      double prev = m >= 1 ? U(0, path.motion_cov[1]) : 0.0;
      for (std::size_t t = 1; t <= m; ++t) {
        const double u = U(t, path.motion_cov[t]);
        r.cost += std::max(u - prev, 0.0);
        prev = u;
      }
      r.label = "work";
      break;
    }
    case Criterion::SumDopt:
      for (const Mat3& s : path.sigma) r.cost += scalarOf(s, o.scalar);
      r.label = std::string("sum ") + scalarName(o.scalar) + "(Sigma)";
      break;
    case Criterion::Distance:
      r.cost = pathLength(path);
      r.label = "distance";
      break;
  }
  return r;
}

}  // namespace asf::planning
