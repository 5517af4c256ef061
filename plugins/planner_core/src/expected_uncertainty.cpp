// Expected-uncertainty path planning (thesis chapter 3): Algorithm 1, the relocalization
// probability, the baseline criteria, the reduced-graph path search and the plan drawing.
#include <asf/errors.h>
#include <asf/expected_uncertainty.h>
#include <asf/segmentation_eval.h>
#include <asf/place_recognition.h>
#include <asf/params.h>

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

namespace asf::eu {

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

/// Edges by unordered node pair, built once per graph.
struct EdgeIndex {
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> by_pair;
  static std::uint64_t key(NodeId a, NodeId b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(a) << 32) | b;
  }
  explicit EdgeIndex(const PoseGraph& g) {
    for (std::size_t i = 0; i < g.edges.size(); ++i)
      by_pair[key(g.edges[i].from, g.edges[i].to)].push_back(i);
  }
  const std::vector<std::size_t>* find(NodeId a, NodeId b) const {
    auto it = by_pair.find(key(a, b));
    return it == by_pair.end() ? nullptr : &it->second;
  }
};

/// Virtual edges by unordered node pair.
struct VirtualIndex {
  std::unordered_map<std::uint64_t, const gvg::VirtualEdge*> by_pair;
  explicit VirtualIndex(const std::vector<gvg::VirtualEdge>* v) {
    if (v)
      for (const auto& e : *v) by_pair.emplace(EdgeIndex::key(e.a, e.b), &e);
  }
  const gvg::VirtualEdge* find(NodeId a, NodeId b) const {
    auto it = by_pair.find(EdgeIndex::key(a, b));
    return it == by_pair.end() ? nullptr : it->second;
  }
};

PathModel makePathModel(const PoseGraph& g, const EdgeIndex& index, const Marginals* m,
                        const std::vector<NodeId>& path, const VirtualIndex* virt = nullptr) {
  PathModel p;
  p.nodes = path;
  p.marginals = m;
  const std::size_t n = g.size();
  for (NodeId v : path)
    if (v >= n)
      throw Error("path: node " + std::to_string(v) + " does not exist (the graph has " +
                  std::to_string(n) + " nodes)");
  if (m && m->node.size() != n)
    throw Error("path: the marginals have " + std::to_string(m->node.size()) +
                " node blocks for " + std::to_string(n) + " nodes");
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
    const gvg::VirtualEdge* ve = (!edges && virt && a != b) ? virt->find(a, b) : nullptr;
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
                std::to_string(t) + " (hypothesis " + std::to_string(k) +
                ") is outside [0, 1]");
  return p;
}

}  // namespace

// ---------------------------------------------------------------------------------------

BoxProbability gaussianBoxProbability(const Eigen::VectorXd& mean, const Eigen::MatrixXd& cov,
                                      const Eigen::VectorXd& lower,
                                      const Eigen::VectorXd& upper, int points, int shifts,
                                      std::uint64_t seed) {
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

  // The part of each variable's interval left once the previous y's are fixed.
  auto interval = [&](Eigen::Index i, double s, double& d, double& e) {
    if (L(i, i) > 0) {
      d = normalCdf((a(i) - s) / L(i, i));
      e = normalCdf((b(i) - s) / L(i, i));
    } else {  // point mass at s
      d = 0;
      e = (a(i) <= s && s <= b(i)) ? 1 : 0;
    }
  };
  double d0, e0;
  interval(0, 0, d0, e0);
  // Exact when the variables decouple (diagonal factor) or in one dimension.
  const bool diagonal = L.isDiagonal(0.0) || n == 1;
  if (diagonal) {
    double v = e0 - d0;
    for (Eigen::Index i = 1; i < n; ++i) {
      double d, e;
      interval(i, 0, d, e);
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
    for (int q = 1; q <= per_shift; ++q) {
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
      acc += std::max(f, 0.0);
    }
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
                        const std::vector<gvg::VirtualEdge>* virtual_edges) {
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
    const BoxProbability b =
        gaussianBoxProbability(Eigen::Vector3d::Zero(), Cd, -half, half, o.points, o.shifts, o.seed);
    return std::clamp(p_rec * b.value, 0.0, 1.0);
  };
}

// ---------------------------------------------------------------------------------------

const char* criterionName(Criterion c) {
  switch (c) {
    case Criterion::ExpectedUncertainty: return "expected_uncertainty";
    case Criterion::MechanicalWork: return "mechanical_work";
    case Criterion::SumDopt: return "sum_dopt";
    case Criterion::Distance: return "distance";
  }
  return "?";
}

const char* scalarName(Scalar s) {
  switch (s) {
    case Scalar::Det: return "det";
    case Scalar::Trace: return "trace";
    case Scalar::DetCbrt: return "det_cbrt";
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
    case Scalar::Det: return c.determinant();
    case Scalar::Trace: return c.trace();
    case Scalar::DetCbrt: return std::cbrt(c.determinant());
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

// ---------------------------------------------------------------------------------------

namespace {

/// Neighbour sets without self-loops and without repeats (parallel edges merged).
std::vector<std::vector<NodeId>> simpleAdjacency(const PoseGraph& g) {
  std::vector<std::set<NodeId>> s(g.size());
  for (const auto& e : g.edges) {
    if (e.from == e.to || e.from >= g.size() || e.to >= g.size()) continue;
    s[e.from].insert(e.to);
    s[e.to].insert(e.from);
  }
  std::vector<std::vector<NodeId>> adj(g.size());
  for (std::size_t v = 0; v < g.size(); ++v) adj[v].assign(s[v].begin(), s[v].end());
  return adj;
}

ReducedGraph reduce(const std::vector<std::vector<NodeId>>& adj, NodeId start, NodeId goal,
                    bool collapse) {
  ReducedGraph r;
  const std::size_t n = adj.size();
  std::vector<char> kept(n, 0);
  for (std::size_t v = 0; v < n; ++v)
    kept[v] = !collapse || adj[v].size() != 2 || v == start || v == goal;
  for (std::size_t v = 0; v < n; ++v)
    if (kept[v]) r.kept.push_back(static_cast<NodeId>(v));
  for (NodeId a : r.kept)
    for (NodeId first : adj[a]) {
      ReducedGraph::Edge e{a, 0, {}};
      NodeId prev = a, cur = first;
      while (!kept[cur]) {
        e.interior.push_back(cur);
        const NodeId next = adj[cur][0] == prev ? adj[cur][1] : adj[cur][0];
        prev = cur;
        cur = next;
      }
      e.b = cur;
      // Each chain is met from both ends: keep it once; a chain back to a is never simple.
      if (e.b == a) continue;
      if (a > e.b) continue;
      r.edges.push_back(std::move(e));
    }
  return r;
}

}  // namespace

ReducedGraph reduceGraph(const PoseGraph& g, NodeId start, NodeId goal) {
  return reduce(simpleAdjacency(g), start, goal, true);
}

const char* searchMethodName(SearchMethod m) {
  switch (m) {
    case SearchMethod::Auto: return "auto";
    case SearchMethod::All: return "all";
    case SearchMethod::Yen: return "yen";
  }
  return "?";
}

namespace {

double planarDistance(const PoseGraph& g, NodeId a, NodeId b) {
  return std::hypot(g.nodes[a].pose.x() - g.nodes[b].pose.x(),
                    g.nodes[a].pose.y() - g.nodes[b].pose.y());
}

/// A loop closure for the alias merge: so marked, or joining nodes that are not consecutive
/// in the trajectory (readG2o marks them so; hand-built graphs may not).
bool isLoopClosure(const PoseEdge& e) {
  const NodeId gap = e.from > e.to ? e.from - e.to : e.to - e.from;
  return e.kind == EdgeKind::LoopClosure || gap > 1;
}

void checkNodes(const PoseGraph& g, NodeId start, NodeId goal) {
  const std::size_t n = g.size();
  if (start >= n || goal >= n)
    throw Error("node " + std::to_string(start >= n ? start : goal) +
                " does not exist (the graph has " + std::to_string(n) + " nodes)");
}

/// Dijkstra over the pose graph (edge length: distance between the estimates) from `start`
/// to `goal`, moving from v to w only when allowed(v, w). Empty when goal is unreachable.
/// Ties resolve by node id, so the result is deterministic.
template <class Allowed>
std::vector<NodeId> dijkstraNodes(const PoseGraph& g,
                                  const std::vector<std::vector<NodeId>>& adj, NodeId start,
                                  NodeId goal, const Allowed& allowed) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const std::size_t n = g.size();
  std::vector<double> dist(n, kInf);
  std::vector<NodeId> prev(n, 0);
  using Item = std::pair<double, NodeId>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  dist[start] = 0;
  open.emplace(0.0, start);
  while (!open.empty()) {
    const auto [d, v] = open.top();
    open.pop();
    if (d > dist[v]) continue;
    if (v == goal) break;
    for (NodeId w : adj[v]) {
      if (!allowed(v, w)) continue;
      const double nd = d + planarDistance(g, v, w);
      if (nd < dist[w]) {
        dist[w] = nd;
        prev[w] = v;
        open.emplace(nd, w);
      }
    }
  }
  std::vector<NodeId> path;
  if (dist[goal] == kInf) return path;
  for (NodeId v = goal;; v = prev[v]) {
    path.push_back(v);
    if (v == start) break;
  }
  std::reverse(path.begin(), path.end());
  return path;
}

}  // namespace

namespace {

/// buildSearchGraph; edges at index >= first_virtual are virtual: never loop closures.
SearchGraph buildSearchGraphImpl(const PoseGraph& g, NodeId start, NodeId goal,
                                 double merge_radius, bool collapse, std::size_t first_virtual) {
  checkNodes(g, start, goal);
  const std::size_t n = g.size();
  // Clusters with explicit member lists: label[v] is v's cluster, relabelled on merges
  // (smaller into larger), so a lookup is O(1) and all merges O(n log n).
  std::vector<NodeId> label(n);
  std::vector<std::vector<NodeId>> mem(n);
  for (std::size_t v = 0; v < n; ++v) {
    label[v] = static_cast<NodeId>(v);
    mem[v] = {static_cast<NodeId>(v)};
  }
  if (merge_radius > 0) {
    std::vector<std::pair<double, std::size_t>> closures;
    for (std::size_t i = 0; i < g.edges.size(); ++i) {
      const PoseEdge& e = g.edges[i];
      if (i >= first_virtual || e.from == e.to || e.from >= n || e.to >= n || !isLoopClosure(e))
        continue;
      const double d = planarDistance(g, e.from, e.to);
      if (d <= merge_radius) closures.emplace_back(d, i);
    }
    std::sort(closures.begin(), closures.end());
    for (const auto& [d, i] : closures) {
      NodeId ca = label[g.edges[i].from], cb = label[g.edges[i].to];
      if (ca == cb) continue;
      const NodeId cs = label[start], cg = label[goal];
      if ((ca == cs && cb == cg) || (ca == cg && cb == cs)) continue;
      bool close = true;
      for (NodeId a : mem[ca]) {
        for (NodeId b : mem[cb])
          if (planarDistance(g, a, b) > merge_radius) {
            close = false;
            break;
          }
        if (!close) break;
      }
      if (!close) continue;
      if (mem[ca].size() < mem[cb].size()) std::swap(ca, cb);
      for (NodeId v : mem[cb]) label[v] = ca;
      mem[ca].insert(mem[ca].end(), mem[cb].begin(), mem[cb].end());
      mem[cb].clear();
    }
  }
  // Vertices numbered in the order of their smallest node.
  SearchGraph sg;
  sg.vertex_of.assign(n, 0);
  std::vector<NodeId> vertex_of_label(n, std::numeric_limits<NodeId>::max());
  for (std::size_t v = 0; v < n; ++v) {
    NodeId& id = vertex_of_label[label[v]];
    if (id == std::numeric_limits<NodeId>::max()) {
      id = static_cast<NodeId>(sg.members.size());
      sg.members.push_back(mem[label[v]]);
      std::sort(sg.members.back().begin(), sg.members.back().end());
    }
    sg.vertex_of[v] = id;
  }
  for (const auto& m : sg.members) {
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (NodeId v : m) c += Eigen::Vector2d(g.nodes[v].pose.x(), g.nodes[v].pose.y());
    sg.centre.push_back(c / static_cast<double>(m.size()));
    if (m.size() > 1) ++sg.merged_vertices;
  }
  sg.start = sg.vertex_of[start];
  sg.goal = sg.vertex_of[goal];
  std::vector<std::set<NodeId>> s(sg.members.size());
  for (const auto& e : g.edges) {
    if (e.from >= n || e.to >= n) continue;
    const NodeId a = sg.vertex_of[e.from], b = sg.vertex_of[e.to];
    if (a == b) continue;
    s[a].insert(b);
    s[b].insert(a);
  }
  std::vector<std::vector<NodeId>> adj(s.size());
  for (std::size_t v = 0; v < s.size(); ++v) adj[v].assign(s[v].begin(), s[v].end());
  sg.reduced = reduce(adj, sg.start, sg.goal, collapse);
  for (const auto& e : sg.reduced.edges) {
    double len = 0;
    NodeId prev = e.a;
    for (NodeId v : e.interior) {
      len += (sg.centre[v] - sg.centre[prev]).norm();
      prev = v;
    }
    sg.length.push_back(len + (sg.centre[e.b] - sg.centre[prev]).norm());
  }
  return sg;
}

}  // namespace

SearchGraph buildSearchGraph(const PoseGraph& g, NodeId start, NodeId goal, double merge_radius,
                             bool collapse) {
  return buildSearchGraphImpl(g, start, goal, merge_radius, collapse,
                              std::numeric_limits<std::size_t>::max());
}

std::vector<NodeId> routeVertices(const SearchGraph& sg,
                                  const std::vector<std::pair<std::size_t, bool>>& edges) {
  std::vector<NodeId> seq{sg.start};
  for (const auto& [i, fwd] : edges) {
    const auto& e = sg.reduced.edges.at(i);
    if (seq.back() != (fwd ? e.a : e.b))
      throw Error("routeVertices: reduced edge " + std::to_string(i) +
                  " does not continue the route");
    if (fwd)
      seq.insert(seq.end(), e.interior.begin(), e.interior.end());
    else
      seq.insert(seq.end(), e.interior.rbegin(), e.interior.rend());
    seq.push_back(fwd ? e.b : e.a);
  }
  return seq;
}

std::vector<NodeId> expandRoute(const PoseGraph& g, const SearchGraph& sg,
                                const std::vector<NodeId>& vertices, NodeId start, NodeId goal) {
  checkNodes(g, start, goal);
  if (sg.vertex_of.size() != g.size())
    throw Error("expandRoute: the search graph belongs to another pose graph");
  if (vertices.empty() || vertices.front() != sg.vertex_of[start] ||
      vertices.back() != sg.vertex_of[goal])
    throw Error("expandRoute: the route does not run from the start's to the goal's vertex");
  std::vector<int> pos(sg.members.size(), -1);
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (vertices[i] >= sg.members.size() || pos[vertices[i]] >= 0)
      throw Error("expandRoute: vertex " + std::to_string(vertices[i]) +
                  " is missing or repeated in the route");
    pos[vertices[i]] = static_cast<int>(i);
  }
  const auto adj = simpleAdjacency(g);
  const auto path = dijkstraNodes(g, adj, start, goal, [&](NodeId v, NodeId w) {
    const int pw = pos[sg.vertex_of[w]], pv = pos[sg.vertex_of[v]];
    return pw >= 0 && (pw == pv || pw == pv + 1);
  });
  if (path.empty())
    throw Error("expandRoute: the route is not realizable in the pose graph (consecutive "
                "vertices not adjacent)");
  return path;
}

std::vector<NodeId> shortestPath(const PoseGraph& g, NodeId start, NodeId goal) {
  checkNodes(g, start, goal);
  return dijkstraNodes(g, simpleAdjacency(g), start, goal, [](NodeId, NodeId) { return true; });
}

std::vector<std::vector<std::size_t>> kShortestSimplePaths(std::size_t n,
                                                           const std::vector<WeightedEdge>& e,
                                                           std::uint32_t s, std::uint32_t t,
                                                           std::size_t k) {
  using EdgePath = std::vector<std::size_t>;
  std::vector<std::vector<std::pair<std::uint32_t, std::size_t>>> adj(n);
  for (std::size_t i = 0; i < e.size(); ++i) {
    if (e[i].a >= n || e[i].b >= n)
      throw Error("kShortestSimplePaths: edge " + std::to_string(i) + " names a vertex >= " +
                  std::to_string(n));
    if (!(e[i].w >= 0)) throw Error("kShortestSimplePaths: negative or NaN weight");
    if (e[i].a == e[i].b) continue;  // never on a simple path
    adj[e[i].a].emplace_back(e[i].b, i);
    adj[e[i].b].emplace_back(e[i].a, i);
  }
  std::vector<EdgePath> A;
  if (s >= n || t >= n || k == 0) return A;
  if (s == t) {
    A.emplace_back();
    return A;
  }
  auto cost = [&](const EdgePath& p) {
    double c = 0;
    for (std::size_t i : p) c += e[i].w;
    return c;
  };
  // Dijkstra from src to t avoiding banned vertices and edges; ties by (distance, vertex).
  std::vector<char> banned_v(n, 0), banned_e(e.size(), 0);
  auto dijkstra = [&](std::uint32_t src, EdgePath& out) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    std::vector<double> dist(n, kInf);
    std::vector<std::size_t> via(n, 0);
    using Item = std::pair<double, std::uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
    dist[src] = 0;
    open.emplace(0.0, src);
    while (!open.empty()) {
      const auto [d, v] = open.top();
      open.pop();
      if (d > dist[v]) continue;
      if (v == t) break;
      for (const auto& [w, i] : adj[v]) {
        if (banned_v[w] || banned_e[i]) continue;
        if (d + e[i].w < dist[w]) {
          dist[w] = d + e[i].w;
          via[w] = i;
          open.emplace(dist[w], w);
        }
      }
    }
    out.clear();
    if (dist[t] == kInf) return false;
    for (std::uint32_t v = t; v != src;) {
      out.push_back(via[v]);
      v = e[via[v]].a == v ? e[via[v]].b : e[via[v]].a;
    }
    std::reverse(out.begin(), out.end());
    return true;
  };
  struct Candidate {
    double cost;
    EdgePath path;
    bool operator<(const Candidate& o) const {
      if (cost != o.cost) return cost < o.cost;
      if (path.size() != o.path.size()) return path.size() < o.path.size();
      return path < o.path;
    }
  };
  EdgePath first;
  if (!dijkstra(s, first)) return A;
  A.push_back(first);
  std::set<EdgePath> seen{first};
  std::set<Candidate> B;
  while (A.size() < k) {
    const EdgePath prev = A.back();
    std::vector<std::uint32_t> verts{s};
    for (std::size_t i : prev)
      verts.push_back(e[i].a == verts.back() ? e[i].b : e[i].a);
    for (std::size_t i = 0; i < prev.size(); ++i) {
      // Root: prev's first i edges; spur vertex verts[i]. Ban the root's vertices (simple
      // paths) and the next edge of every accepted path sharing this root.
      std::fill(banned_v.begin(), banned_v.end(), 0);
      std::fill(banned_e.begin(), banned_e.end(), 0);
      for (std::size_t j = 0; j < i; ++j) banned_v[verts[j]] = 1;
      for (const EdgePath& p : A)
        if (p.size() > i && std::equal(p.begin(), p.begin() + static_cast<long>(i), prev.begin()))
          banned_e[p[i]] = 1;
      EdgePath spur;
      if (!dijkstra(verts[i], spur)) continue;
      EdgePath total(prev.begin(), prev.begin() + static_cast<long>(i));
      total.insert(total.end(), spur.begin(), spur.end());
      if (seen.insert(total).second) B.insert({cost(total), std::move(total)});
    }
    if (B.empty()) break;
    A.push_back(B.begin()->path);
    B.erase(B.begin());
  }
  return A;
}

std::vector<std::vector<std::size_t>> diversePaths(std::size_t n,
                                                   const std::vector<WeightedEdge>& e,
                                                   std::uint32_t s, std::uint32_t t,
                                                   std::size_t count, double penalty) {
  if (!(penalty > 0)) throw Error("diversePaths: the penalty must be positive");
  std::vector<WeightedEdge> w = e;
  std::vector<std::vector<std::size_t>> out;
  std::set<std::vector<std::size_t>> seen;
  for (std::size_t i = 0; i < count; ++i) {
    const auto p = kShortestSimplePaths(n, w, s, t, 1);
    if (p.empty()) break;
    if (seen.insert(p[0]).second) out.push_back(p[0]);
    for (std::size_t k : p[0]) w[k].w *= 1 + penalty;
  }
  return out;
}

namespace {

/// `g` plus the virtual edges as pose-graph edges (mean: the relative pose of the estimates;
/// information from the a -> b covariance), appended after g's own edges.
PoseGraph withVirtualEdges(const PoseGraph& g, const std::vector<gvg::VirtualEdge>& v) {
  PoseGraph a = g;
  for (const auto& e : v) {
    if (e.a >= g.size() || e.b >= g.size() || e.a == e.b)
      throw Error("virtual edge " + std::to_string(e.a) + " - " + std::to_string(e.b) +
                  ": not two distinct nodes of the graph");
    PoseEdge pe;
    pe.from = e.a;
    pe.to = e.b;
    pe.mean = g.nodes[e.b].pose - g.nodes[e.a].pose;
    pe.mean.normalizePhi();
    pe.information = edgeInformation(pe.mean, e.covariance_ab, Mat3::Identity() * 1e-12);
    pe.kind = EdgeKind::Odometry;
    a.edges.push_back(pe);
  }
  return a;
}

PathSearchResult searchPathsImpl(const PoseGraph& g, NodeId start, NodeId goal,
                                 const PathSearchOptions& o, std::size_t first_virtual);

}  // namespace

PathSearchResult searchPaths(const PoseGraph& g, NodeId start, NodeId goal,
                             const PathSearchOptions& o,
                             const std::vector<gvg::VirtualEdge>* virtual_edges) {
  if (!virtual_edges || virtual_edges->empty())
    return searchPathsImpl(g, start, goal, o, std::numeric_limits<std::size_t>::max());
  checkNodes(g, start, goal);
  return searchPathsImpl(withVirtualEdges(g, *virtual_edges), start, goal, o, g.edges.size());
}

namespace {

PathSearchResult searchPathsImpl(const PoseGraph& g, NodeId start, NodeId goal,
                                 const PathSearchOptions& o, std::size_t first_virtual) {
  checkNodes(g, start, goal);
  PathSearchResult out;
  out.method = o.method == SearchMethod::Yen ? SearchMethod::Yen : SearchMethod::All;
  if (start == goal) {
    out.paths.push_back({start});
    return out;
  }
  const SearchGraph sg =
      buildSearchGraphImpl(g, start, goal, o.merge_radius, o.reduce, first_virtual);
  out.reduced_nodes = sg.reduced.kept.size();
  out.reduced_edges = sg.reduced.edges.size();
  out.merged_vertices = sg.merged_vertices;
  const std::size_t nv = sg.members.size();
  std::vector<std::vector<std::pair<std::size_t, bool>>> routes;  // reduced edges taken

  if (o.method != SearchMethod::Yen) {
    // Depth-first enumeration of the simple routes. search = auto gives up (for Yen's) once
    // it has more than max_paths routes or has spent 64 x max_paths expansions: a loopy
    // graph can hide few routes in a huge search tree.
    const bool automatic = o.method == SearchMethod::Auto;
    const std::size_t max_expansions =
        automatic ? std::max<std::size_t>(64 * o.max_paths, 4096) : 0;
    std::vector<std::vector<std::pair<std::size_t, bool>>> inc(nv);
    for (std::size_t i = 0; i < sg.reduced.edges.size(); ++i) {
      inc[sg.reduced.edges[i].a].emplace_back(i, true);
      inc[sg.reduced.edges[i].b].emplace_back(i, false);
    }
    std::vector<char> on_path(nv, 0);
    std::vector<std::pair<std::size_t, bool>> stack;
    bool stop = false;
    const auto t0 = std::chrono::steady_clock::now();
    std::size_t expansions = 0;
    std::function<void(NodeId)> dfs = [&](NodeId v) {
      if (stop) return;
      ++expansions;
      if (o.max_seconds > 0 && (expansions & 4095) == 0 &&
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() >
              o.max_seconds) {
        out.timed_out = true;
        stop = true;
        return;
      }
      if (automatic && expansions > max_expansions) {
        out.fell_back = true;
        stop = true;
        return;
      }
      if (v == sg.goal) {
        if (routes.size() >= o.max_paths) {
          if (automatic)
            out.fell_back = true;
          else
            out.capped = true;
          stop = true;
          return;
        }
        routes.push_back(stack);
        return;
      }
      on_path[v] = 1;
      for (const auto& [i, fwd] : inc[v]) {
        const NodeId w = fwd ? sg.reduced.edges[i].b : sg.reduced.edges[i].a;
        if (on_path[w]) continue;
        stack.emplace_back(i, fwd);
        dfs(w);
        stack.pop_back();
        if (stop) break;
      }
      on_path[v] = 0;
    };
    dfs(sg.start);
    if (automatic && out.timed_out) out.fell_back = true;
    if (out.timed_out && !automatic) out.capped = true;
    if (out.fell_back) {
      routes.clear();
      out.timed_out = false;
    }
  }
  if (o.method == SearchMethod::Yen || out.fell_back) {
    out.method = SearchMethod::Yen;
    std::vector<WeightedEdge> we;
    for (std::size_t i = 0; i < sg.reduced.edges.size(); ++i)
      we.push_back({sg.reduced.edges[i].a, sg.reduced.edges[i].b, sg.length[i]});
    auto edge_paths = kShortestSimplePaths(nv, we, sg.start, sg.goal, o.k_paths);
    if (o.diverse_paths > 0) {
      std::set<std::vector<std::size_t>> have(edge_paths.begin(), edge_paths.end());
      for (auto& p : diversePaths(nv, we, sg.start, sg.goal, o.diverse_paths, o.diverse_penalty))
        if (have.insert(p).second) {
          edge_paths.push_back(std::move(p));
          ++out.diverse_added;
        }
    }
    for (const auto& p : edge_paths) {
      std::vector<std::pair<std::size_t, bool>> r;
      NodeId at = sg.start;
      for (std::size_t i : p) {
        const bool fwd = sg.reduced.edges[i].a == at;
        r.emplace_back(i, fwd);
        at = fwd ? sg.reduced.edges[i].b : sg.reduced.edges[i].a;
      }
      routes.push_back(std::move(r));
    }
  }
  std::set<std::vector<NodeId>> seen;
  for (const auto& r : routes) {
    auto p = expandRoute(g, sg, routeVertices(sg, r), start, goal);
    if (seen.insert(p).second) out.paths.push_back(std::move(p));
  }
  if (o.add_shortest) {
    auto p = shortestPath(g, start, goal);
    if (!p.empty() && seen.insert(p).second) {
      out.paths.push_back(std::move(p));
      out.added_shortest = true;
    }
  }
  return out;
}

}  // namespace

PathSearchResult allSimplePaths(const PoseGraph& g, NodeId start, NodeId goal,
                                const PathSearchOptions& o) {
  PathSearchOptions a = o;
  a.method = SearchMethod::All;
  a.add_shortest = false;
  return searchPaths(g, start, goal, a);
}

PlanResult planBest(const PlanRequest& req, Criterion c, const CriterionOptions& o,
                    const PathSearchOptions& search, std::string* note) {
  PlanResult res;
  res.criterion = criterionName(c);
  if (!req.graph) {
    res.reason = "no pose graph given";
    return res;
  }
  const PoseGraph& g = *req.graph;
  if (req.start >= g.size() || req.goal >= g.size()) {
    res.reason = "node " + std::to_string(req.start >= g.size() ? req.start : req.goal) +
                 " does not exist (the graph has " + std::to_string(g.size()) + " nodes)";
    return res;
  }
  const bool needs_marginals = c != Criterion::Distance;
  if (needs_marginals && (!req.marginals || req.marginals->node.size() != g.size())) {
    res.reason = std::string(criterionName(c)) +
                 " needs the node marginal covariances (none given, or not one per node)";
    return res;
  }
  // Partially explored maps: the virtual edges of the map's GVG.
  std::vector<gvg::VirtualEdge> virtual_edges;
  std::string voronoi_note;
  if (search.voronoi_edges) {
    if (req.map && req.map->grid) {
      // How many were found is not a warning: `asf plan --json` reports it (virtual_edges).
      virtual_edges = gvg::computeVirtualEdges(g, *req.map, search.voronoi).edges;
    } else {
      voronoi_note = "voronoi_edges: the request has no map; pose-graph edges only. ";
    }
  }
  const PathSearchResult paths = searchPaths(g, req.start, req.goal, search, &virtual_edges);
  if (paths.paths.empty()) {
    res.reason = "node " + std::to_string(req.goal) + " is not connected to node " +
                 std::to_string(req.start);
    return res;
  }
  const EdgeIndex index(g);
  const VirtualIndex vindex(&virtual_edges);
  // Thesis eq. 3.25: with virtual edges, expected uncertainty weighs E[C] by the distance.
  const bool by_distance = search.voronoi_edges && c == Criterion::ExpectedUncertainty;
  std::size_t missing = 0, evaluated = 0;
  const auto t0 = std::chrono::steady_clock::now();
  bool out_of_time = false;
  struct Scored {
    double cost, distance;
    std::size_t index;
    std::string label;
  };
  std::vector<Scored> scored;
  for (std::size_t i = 0; i < paths.paths.size(); ++i) {
    const auto& p = paths.paths[i];
    if (search.max_seconds > 0 && evaluated > 0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() >
            search.max_seconds) {
      out_of_time = true;
      break;
    }
    ++evaluated;
    const PathModel model =
        makePathModel(g, index, needs_marginals ? req.marginals : nullptr, p, &vindex);
    PathCost pc = evaluatePath(c, model, o);
    missing += pc.missing_cross;
    const double distance = pathLength(model);
    if (by_distance) {
      pc.cost *= distance;
      pc.label = "distance*" + pc.label;
    }
    scored.push_back({pc.cost, distance, i, pc.label});
  }
  // The cheapest; costs within tie_tolerance (relative) of it are equally good, and the
  // shortest of those (metres, then fewer nodes, then the first found) is chosen.
  if (!scored.empty()) {
    double best = scored[0].cost;
    for (const auto& sc : scored) best = std::min(best, sc.cost);
    const double limit = best + o.tie_tolerance * std::abs(best);
    const Scored* pick = nullptr;
    for (const auto& sc : scored) {
      if (!(sc.cost <= limit)) continue;
      const auto& p = paths.paths[sc.index];
      if (!pick || sc.distance < pick->distance ||
          (sc.distance == pick->distance && p.size() < paths.paths[pick->index].size()))
        pick = &sc;
    }
    res.found = true;
    res.cost = pick->cost;
    res.nodes = paths.paths[pick->index];
    res.criterion = pick->label;
  }
  if (note) {
    *note = voronoi_note;
    if (paths.timed_out)
      *note += "path search stopped by the time budget (" + std::to_string(search.max_seconds) +
               " s) after " + std::to_string(paths.paths.size()) + " paths; the best may be missing. ";
    else if (paths.capped)
      *note += "path search capped at " + std::to_string(search.max_paths) +
               " paths (reduced graph: " + std::to_string(paths.reduced_nodes) + " vertices, " +
               std::to_string(paths.reduced_edges) + " edges); the best may be missing. ";
    else if (paths.fell_back)
      *note += "enumeration given up past " + std::to_string(search.max_paths) +
               " simple routes or " +
               std::to_string(std::max<std::size_t>(64 * search.max_paths, 4096)) +
               " expansions (reduced graph: " + std::to_string(paths.reduced_nodes) +
               " vertices, " + std::to_string(paths.reduced_edges) + " edges): Yen's " +
               std::to_string(search.k_paths) + " shortest routes (and " +
               std::to_string(paths.diverse_added) +
               " of the penalty method) evaluated instead. ";
    if (out_of_time)
      *note += "time budget of " + std::to_string(search.max_seconds) + " s spent after " +
               std::to_string(evaluated) + " of " + std::to_string(paths.paths.size()) +
               " candidate paths; the best may be missing. ";
    if (missing)
      *note += std::to_string(missing) +
               " relocalization queries lacked a cross-covariance block (treated as zero).";
  }
  return res;
}

// ---------------------------------------------------------------------------------------

void renderPlan(const std::string& png, const PoseGraph& g, const Marginals* marginals,
                const std::vector<NodeId>& path, const RenderOptions& o) {
  cv::Mat img;
  std::function<cv::Point(double, double)> px;
  double px_per_m = 1;
  if (!o.map_png.empty()) {
    GrayImage gray = readGrayImage(o.map_png);  // formats checked, errors name the file
    const cv::Mat map(gray.height, gray.width, CV_8U, gray.pixels.data());
    cv::cvtColor(map, img, cv::COLOR_GRAY2BGR);
    px_per_m = 1.0 / o.map_resolution;
    const int h = img.rows;
    const double ox = o.map_origin_x, oy = o.map_origin_y;
    px = [=](double x, double y) {
      return cv::Point(static_cast<int>(std::lround((x - ox) * px_per_m)),
                       static_cast<int>(std::lround(h - (y - oy) * px_per_m)));
    };
  } else {
    double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
    if (!g.empty()) {
      x0 = x1 = g.nodes[0].pose.x();
      y0 = y1 = g.nodes[0].pose.y();
      for (const auto& v : g.nodes) {
        x0 = std::min(x0, v.pose.x()), x1 = std::max(x1, v.pose.x());
        y0 = std::min(y0, v.pose.y()), y1 = std::max(y1, v.pose.y());
      }
    }
    const double span = std::max({x1 - x0, y1 - y0, 1e-3});
    const int margin = 30;
    px_per_m = (o.max_size - 2 * margin) / span;
    const int w = static_cast<int>((x1 - x0) * px_per_m) + 2 * margin;
    const int h = static_cast<int>((y1 - y0) * px_per_m) + 2 * margin;
    img = cv::Mat(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
    px = [=](double x, double y) {
      return cv::Point(static_cast<int>(std::lround(margin + (x - x0) * px_per_m)),
                       static_cast<int>(std::lround(h - margin - (y - y0) * px_per_m)));
    };
  }
  auto at = [&](NodeId v) { return px(g.nodes[v].pose.x(), g.nodes[v].pose.y()); };
  for (const auto& e : g.edges) {
    if (e.from >= g.size() || e.to >= g.size()) continue;
    const cv::Scalar colour = e.kind == EdgeKind::LoopClosure ? cv::Scalar(120, 200, 120)
                                                              : cv::Scalar(160, 160, 160);
    cv::line(img, at(e.from), at(e.to), colour, 1, cv::LINE_AA);
  }
  if (o.ellipses && marginals && marginals->node.size() == g.size()) {
    for (std::size_t v = 0; v < g.size(); ++v) {
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(marginals->node[v].topLeftCorner<2, 2>());
      const Eigen::Vector2d ev = es.eigenvalues().cwiseMax(0.0);
      const Eigen::Vector2d major = es.eigenvectors().col(1);
      // 3-sigma axes; image y points down, hence the negated angle.
      const double angle = -std::atan2(major.y(), major.x()) * 180.0 / M_PI;
      const cv::Size axes(static_cast<int>(3 * std::sqrt(ev(1)) * px_per_m) + 1,
                          static_cast<int>(3 * std::sqrt(ev(0)) * px_per_m) + 1);
      cv::ellipse(img, at(static_cast<NodeId>(v)), axes, angle, 0, 360,
                  cv::Scalar(230, 180, 120), 1, cv::LINE_AA);
    }
  }
  for (std::size_t v = 0; v < g.size(); ++v)
    cv::circle(img, at(static_cast<NodeId>(v)), 2, cv::Scalar(90, 90, 90), cv::FILLED);
  for (std::size_t t = 1; t < path.size(); ++t)
    if (path[t] < g.size() && path[t - 1] < g.size())
      cv::line(img, at(path[t - 1]), at(path[t]), cv::Scalar(0, 0, 220), 3, cv::LINE_AA);
  if (!path.empty() && path.front() < g.size() && path.back() < g.size()) {
    cv::circle(img, at(path.front()), 7, cv::Scalar(0, 170, 0), cv::FILLED);
    cv::circle(img, at(path.back()), 7, cv::Scalar(200, 60, 0), cv::FILLED);
  }
  bool ok = false;
  try {
    ok = cv::imwrite(png, img);
  } catch (const cv::Exception& e) {
    throw Error(png + ": cannot write the image: " + e.what());
  }
  if (!ok) throw Error(png + ": cannot write the image");
}

void CriterionPlanner::configure(const Params& params, const PluginContext& ctx) {
  options_ = criterionOptionsFrom(params, ctx.seed);
  search_ = pathSearchOptionsFrom(params);
}

PathSearchOptions pathSearchOptionsFrom(const Params& params) {
  PathSearchOptions o;
  if (params.has("search")) {
    const std::string m = params.getString("search");
    bool ok = false;
    for (SearchMethod v : {SearchMethod::Auto, SearchMethod::All, SearchMethod::Yen})
      if (m == searchMethodName(v)) {
        o.method = v;
        ok = true;
      }
    if (!ok) params.fail("search", "expected auto, all or yen");
  }
  if (params.has("max_paths")) o.max_paths = static_cast<std::size_t>(params.getInt("max_paths"));
  if (params.has("k_paths")) o.k_paths = static_cast<std::size_t>(params.getInt("k_paths"));
  if (params.has("diverse_paths"))
    o.diverse_paths = static_cast<std::size_t>(params.getInt("diverse_paths"));
  if (params.has("diverse_penalty")) o.diverse_penalty = params.getDouble("diverse_penalty");
  if (params.has("reduce")) o.reduce = params.getBool("reduce");
  if (params.has("merge_radius")) o.merge_radius = params.getDouble("merge_radius");
  if (params.has("add_shortest")) o.add_shortest = params.getBool("add_shortest");
  if (params.has("max_seconds")) o.max_seconds = params.getDouble("max_seconds");
  if (params.has("voronoi_edges")) o.voronoi_edges = params.getBool("voronoi_edges");
  if (params.has("voronoi_free_threshold"))
    o.voronoi.gvg.free_threshold = params.getDouble("voronoi_free_threshold");
  if (params.has("voronoi_clearance"))
    o.voronoi.gvg.clearance = params.getDouble("voronoi_clearance");
  if (params.has("voronoi_attach_radius"))
    o.voronoi.attach_radius = params.getDouble("voronoi_attach_radius");
  if (params.has("voronoi_detour")) o.voronoi.detour = params.getDouble("voronoi_detour");
  if (params.has("voronoi_cov_scale"))
    o.voronoi.covariance_scale = params.getDouble("voronoi_cov_scale");
  if (params.has("voronoi_odometry_step"))
    o.voronoi.odometry_step = params.getDouble("voronoi_odometry_step");
  if (!(o.voronoi.gvg.free_threshold >= 0 && o.voronoi.gvg.free_threshold < 1))
    params.fail("voronoi_free_threshold", "expected a value in [0, 1)");
  if (!(o.voronoi.detour >= 1)) params.fail("voronoi_detour", "expected a value >= 1");
  if (!(o.voronoi.covariance_scale > 0)) params.fail("voronoi_cov_scale", "expected > 0");
  return o;
}

PlanResult CriterionPlanner::plan(const PlanRequest& req) {
  std::string note;
  PlanResult r;
  CriterionOptions options = options_;
  if (options_.recognition_samples > 0 && req.graph) {
    // Place recognition by Monte Carlo for the nodes the file does not give, once per
    // graph revision (the local maps move with the optimized poses).
    if (req.graph->revision != recognition_revision_) {
      recognition_.clear();
      recognition_revision_ = req.graph->revision;
    }
    RecognitionMcOptions mc;
    mc.samples = options_.recognition_samples;
    mc.half_x = options_.reloc.half_x;
    mc.half_y = options_.reloc.half_y;
    mc.half_phi = options_.reloc.half_phi;
    mc.map_radius = options_.recognition_map_radius;
    mc.seed = options_.reloc.seed;
    std::size_t computed = 0;
    for (const PoseNode& n : req.graph->nodes) {
      if (!n.scan || options_.reloc.p_recognition_by_node.count(n.id)) continue;
      if (!recognition_.count(n.id)) {
        recognition_[n.id] = recognitionProbability(*req.graph, n.id, mc);
        ++computed;
      }
      options.reloc.p_recognition_by_node[n.id] = recognition_[n.id];
    }
    if (computed)
      MRPT_LOG_INFO_STREAM("place recognition by Monte Carlo: " << computed << " nodes x "
                                                                << mc.samples << " ICP samples");
  }
  try {
    r = planBest(req, criterion_, options, search_, &note);
  } catch (const Error& e) {  // e.g. a marginal block of the wrong size
    r = PlanResult{};
    r.criterion = criterionName(criterion_);
    r.reason = e.what();
  }
  if (!note.empty()) MRPT_LOG_WARN_STREAM(note);
  return r;
}

}  // namespace asf::eu
