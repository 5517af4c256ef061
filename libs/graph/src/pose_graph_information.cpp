// The information matrix of a 2D pose graph against Theorem 5.2.1 and the bounded-noise
// model of the thesis' section 5.2.4.
#include <asf/errors.h>
#include <asf/graph/information.h>
#include <asf/graph/pose_graph_information.h>
#include <asf/se2_edge.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <limits>

namespace asf::graph {

namespace {

using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Triplets = std::vector<Eigen::Triplet<double>>;

Vector3d poseVector(const mrpt::poses::CPose2D& p) { return {p.x(), p.y(), p.phi()}; }

se2::EdgeLinearization linearize(const PoseGraph& g, const PoseEdge& e) {
  return se2::linearizeEdge(poseVector(g.nodes[e.from].pose), poseVector(g.nodes[e.to].pose),
                            poseVector(e.mean));
}

// Adds the 3x3 blocks [A B; B^T C] of one edge between nodes i and j.
void addEdgeBlocks(Triplets& t, std::size_t i, std::size_t j, const Matrix3d& Aii,
                   const Matrix3d& Aij, const Matrix3d& Ajj) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      t.emplace_back(3 * i + r, 3 * i + c, Aii(r, c));
      t.emplace_back(3 * j + r, 3 * j + c, Ajj(r, c));
      t.emplace_back(3 * i + r, 3 * j + c, Aij(r, c));
      t.emplace_back(3 * j + r, 3 * i + c, Aij(c, r));
    }
}

Eigen::SparseMatrix<double> fromTriplets(std::size_t nodes, const Triplets& t) {
  const auto N = static_cast<Eigen::Index>(3 * nodes);
  Eigen::SparseMatrix<double> Y(N, N);
  Y.setFromTriplets(t.begin(), t.end());
  return Y;
}

// Sum over edges of E_j (x) W_j, W_j from `block(edge index)`.
template <class Block>
Eigen::SparseMatrix<double> kroneckerSum(const PoseGraph& g, Block block) {
  Triplets t;
  t.reserve(g.edges.size() * 36);
  for (std::size_t k = 0; k < g.edges.size(); ++k) {
    const auto& e = g.edges[k];
    if (e.from == e.to) continue;
    const Matrix3d W = block(k);
    addEdgeBlocks(t, e.from, e.to, W, -W, W);
  }
  return fromTriplets(g.size(), t);
}

// World-frame information of edge k (Theorem 5.2.1): B^T Omega B, B = d e / d x_j.
Matrix3d worldInformation(const PoseGraph& g, std::size_t k) {
  const auto& e = g.edges[k];
  const Matrix3d B = linearize(g, e).Jj;
  return B.transpose() * e.information * B;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

NoiseReference parseNoiseReference(const std::string& text, const std::string& key) {
  if (text == "median") return NoiseReference::Median;
  if (text == "identity") return NoiseReference::Identity;
  throw InputError(key + " = '" + text + "': expected median or identity");
}

const char* noiseReferenceName(NoiseReference r) {
  return r == NoiseReference::Median ? "median" : "identity";
}

BoundedNoise boundedNoise(const PoseGraph& g, NoiseReference reference) {
  if (g.edges.empty()) throw InputError("bounded-noise weights: the pose graph has no edges");
  std::vector<double> trans, rot;
  for (std::size_t k = 0; k < g.edges.size(); ++k) {
    const Matrix3d& O = g.edges[k].information;
    Eigen::LLT<Matrix3d> llt(O);
    if (!O.allFinite() ||
        (O - O.transpose()).cwiseAbs().maxCoeff() > 1e-9 * O.cwiseAbs().maxCoeff() ||
        llt.info() != Eigen::Success)
      throw InputError("bounded-noise weights: edge " + std::to_string(k) + " (" +
                       std::to_string(g.edges[k].from) + " -> " + std::to_string(g.edges[k].to) +
                       ") has an information matrix that is not symmetric positive definite");
    trans.push_back(0.5 * (O(0, 0) + O(1, 1)));
    rot.push_back(O(2, 2));
  }
  BoundedNoise b;
  const double a = reference == NoiseReference::Median ? median(trans) : 1.0;
  const double c = reference == NoiseReference::Median ? median(rot) : 1.0;
  // Sigma^(1/2) of diag(a, a, c) is diag(a, a, c)^(-1/2); it commutes with the edge's world
  // rotation, so alpha_j can be taken on Omega_j in its own frame.
  const Vector3d half(1 / std::sqrt(a), 1 / std::sqrt(a), 1 / std::sqrt(c));
  double smallest = std::numeric_limits<double>::infinity();
  for (const auto& e : g.edges) {
    const Matrix3d S = half.asDiagonal() * e.information * half.asDiagonal();
    const Vector3d ev = Eigen::SelfAdjointEigenSolver<Matrix3d>(0.5 * (S + S.transpose()),
                                                                Eigen::EigenvaluesOnly)
                            .eigenvalues();
    b.alpha.push_back(ev[2]);
    b.sharpness.push_back(ev[0] / ev[2]);
    smallest = std::min(smallest, ev[2]);
  }
  for (double& x : b.alpha) x /= smallest;
  b.reference = Vector3d(a, a, c).asDiagonal();
  b.reference *= smallest;
  return b;
}

Multigraph poseGraphAsMultigraph(const PoseGraph& g, const std::vector<double>& alpha) {
  if (!alpha.empty() && alpha.size() != g.edges.size())
    throw InputError("poseGraphAsMultigraph: " + std::to_string(alpha.size()) +
                     " weights for " + std::to_string(g.edges.size()) + " edges");
  Multigraph m;
  m.n = static_cast<int>(g.size());
  for (std::size_t k = 0; k < g.edges.size(); ++k) {
    const auto& e = g.edges[k];
    const double len = g.nodes[e.from].pose.distanceTo(g.nodes[e.to].pose);
    m.edges.push_back({static_cast<int>(e.from), static_cast<int>(e.to), len,
                       alpha.empty() ? 1.0 : alpha[k]});
  }
  return m;
}

Eigen::SparseMatrix<double> fisherInformation(const PoseGraph& g) {
  Triplets t;
  t.reserve(g.edges.size() * 36);
  for (const auto& e : g.edges) {
    if (e.from == e.to) continue;
    const se2::EdgeLinearization L = linearize(g, e);
    const Matrix3d OJi = e.information * L.Ji, OJj = e.information * L.Jj;
    addEdgeBlocks(t, e.from, e.to, L.Ji.transpose() * OJi, L.Ji.transpose() * OJj,
                  L.Jj.transpose() * OJj);
  }
  return fromTriplets(g.size(), t);
}

Eigen::SparseMatrix<double> edgeSumInformation(const PoseGraph& g) {
  return kroneckerSum(g, [&](std::size_t k) { return worldInformation(g, k); });
}

Eigen::SparseMatrix<double> boundInformation(const PoseGraph& g, const BoundedNoise& b) {
  if (b.alpha.size() != g.edges.size())
    throw InputError("boundInformation: " + std::to_string(b.alpha.size()) + " weights for " +
                     std::to_string(g.edges.size()) + " edges");
  return kroneckerSum(g, [&](std::size_t k) { return Matrix3d(b.alpha[k] * b.reference); });
}

double informationFunction(const Eigen::SparseMatrix<double>& Y, const Eigen::MatrixXd& gauge,
                           double p) {
  const Eigen::Index N = Y.rows();
  if (N < 6 || gauge.rows() != N || gauge.cols() != 3)
    throw InputError("informationFunction: needs a 3n x 3n matrix (n >= 2) and a 3n x 3 gauge");
  // Lift the gauge's null space above every other eigenvalue (Gershgorin) and drop it: the
  // eigenvalues left are those of Y on the complement, without a round-off threshold.
  MatrixXd D = MatrixXd(Y);
  D = 0.5 * (D + D.transpose());
  const double lift = 2.0 * D.cwiseAbs().rowwise().sum().maxCoeff() + 1e-300;
  const Eigen::HouseholderQR<MatrixXd> qr(gauge);
  const MatrixXd Q = qr.householderQ() * MatrixXd::Identity(N, 3);
  D.noalias() += lift * Q * Q.transpose();
  const Eigen::VectorXd ev =
      Eigen::SelfAdjointEigenSolver<MatrixXd>(D, Eigen::EigenvaluesOnly).eigenvalues();
  return powerMean(ev.head(N - 3), p);
}

Eigen::MatrixXd translationGauge(std::size_t nodes) {
  MatrixXd K = MatrixXd::Zero(3 * nodes, 3);
  for (std::size_t i = 0; i < nodes; ++i) K.block<3, 3>(3 * i, 0).setIdentity();
  return K;
}

Eigen::MatrixXd rigidMotionGauge(const PoseGraph& g) {
  MatrixXd K = translationGauge(g.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    // A rotation by d about the origin moves node i by d (-y, x) and turns it by d.
    K(3 * i, 2) = -g.nodes[i].pose.y();
    K(3 * i + 1, 2) = g.nodes[i].pose.x();
  }
  return K;
}

double logPseudoDeterminant(const Eigen::SparseMatrix<double>& Y, const Eigen::MatrixXd& gauge) {
  const Eigen::Index N = Y.rows();
  if (N < 6 || gauge.rows() != N || gauge.cols() != 3)
    throw InputError("logPseudoDeterminant: needs a 3n x 3n matrix (n >= 2) and a 3n x 3 gauge");
  const Eigen::SparseMatrix<double> R = Y.bottomRightCorner(N - 3, N - 3);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(R);
  if (ldlt.info() != Eigen::Success) return -std::numeric_limits<double>::infinity();
  const Eigen::VectorXd d = ldlt.vectorD();
  if (!(d.minCoeff() > 0)) return -std::numeric_limits<double>::infinity();
  const double logdetR = d.array().log().sum();
  const Matrix3d KtK = gauge.transpose() * gauge;
  const Matrix3d K0 = gauge.topRows<3>();
  return logdetR + std::log(KtK.determinant()) - 2 * std::log(std::abs(K0.determinant()));
}

double dOptimality(const Eigen::SparseMatrix<double>& Y, const Eigen::MatrixXd& gauge) {
  const double l = logPseudoDeterminant(Y, gauge);
  if (!std::isfinite(l)) return 0;
  return std::exp(l / static_cast<double>(Y.rows() - 3));
}

TheoremCheck checkTheorem(const PoseGraph& g, const BoundedNoise& b, double p,
                          std::size_t max_dense) {
  if (g.size() < 2) throw InputError("checkTheorem: the pose graph has fewer than 2 nodes");
  TheoremCheck c;
  c.p = p;
  // A graph that does not connect every pose has zero information under every criterion.
  if (!poseGraphAsMultigraph(g, {}).connected()) return c;
  if (p != kCriterionD && 3 * g.size() > max_dense)
    throw InputError("checkTheorem: criterion " + criterionName(p) + " needs a dense " +
                     std::to_string(3 * g.size()) + "x" + std::to_string(3 * g.size()) +
                     " eigen-decomposition (limit " + std::to_string(max_dense) +
                     "); only D is computed at any size");
  const Eigen::SparseMatrix<double> exact = fisherInformation(g);
  const Eigen::SparseMatrix<double> sum = edgeSumInformation(g);
  if (p == kCriterionD) {
    // ||L_alpha (x) Sigma^-1||_0 = ||L_alpha||_0 ||Sigma^-1||_0 (eq. 5.50), sparse at any size.
    // The exact information is taken anchored the same way (det without node 0, times n^3):
    // its own pseudo-determinant carries a factor 1 + sum |t_i - mean t|^2 / n from the
    // rotation gauge, a property of the poses' spread, not of the measurements.
    const Eigen::MatrixXd K = translationGauge(g.size());
    c.exact = dOptimality(exact, K);
    c.edge_sum = dOptimality(sum, K);
    c.bound = dOptimality(boundInformation(g, b), K);
    return c;
  }
  const Multigraph m = poseGraphAsMultigraph(g, b.alpha);
  c.bound = information(m, Eigen::VectorXd::Ones(m.m()), p).value *
            powerMean(b.reference.diagonal(), p);
  c.exact = informationFunction(exact, rigidMotionGauge(g), p);
  c.edge_sum = informationFunction(sum, translationGauge(g.size()), p);
  return c;
}

}  // namespace asf::graph
