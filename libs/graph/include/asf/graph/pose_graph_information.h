#pragma once
/// \file pose_graph_information.h
/// The information matrix of a 2D pose graph and its graph-structure approximations
/// (thesis section 5.2): Theorem 5.2.1 (Y ~ sum_j E_j (x) Sigma_j^-1) and the bounded-noise
/// model of section 5.2.4 (Sigma_j^-1 <= alpha_j Sigma^-1, eq. 5.52), which turns a pose graph
/// into a weighted graph with ||Y||_p <= ||L_w||_p ||Sigma^-1||_p (eq. 5.54).
///
/// Conventions:
/// - Unknowns are (x, y, phi) per node, additive, node i at rows 3i..3i+2 (as the back-ends).
/// - Every matrix here is un-anchored (3n x 3n, the gauge left free) and ||Y||_p is the
///   normalised power mean of order p of its 3(n-1) largest eigenvalues: the thesis removes
///   the b = 3 zero eigenvalues of the gauge instead of anchoring a node (eq. 5.42).
/// - An edge's world-frame information, Sigma_j^-1|w = B^T Omega_j B with B the rotation of
///   the edge error's frame (blockdiag(Rz^T Ri^T, 1)), is what Theorem 5.2.1 sums. The exact
///   linearization differs from it by the lever arm of edge j (d e_t / d phi_i, of the order
///   of the edge length): the theorem's "small error" approximation drops it (5.18-5.24 treat
///   the frame change as a rotation). fisherInformation() keeps it.
#include <asf/graph/multigraph.h>
#include <asf/pose_graph.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>
#include <vector>

namespace asf::graph {

/// How the common Sigma^-1 of eq. 5.52 is chosen. Both are diag(a, a, c), isotropic in
/// translation so that the bound does not depend on the edge's heading, and are scaled so
/// that min_j alpha_j = 1 (the thesis asks alpha_j >= 1).
enum class NoiseReference {
  Median,    ///< a, c: medians over the edges of (Omega_xx + Omega_yy) / 2 and Omega_phiphi
  Identity,  ///< a = c (eq. 5.55: every information matrix is bounded by nu_b I)
};
/// "median" | "identity"; InputError naming `key` otherwise.
NoiseReference parseNoiseReference(const std::string& text, const std::string& key);
const char* noiseReferenceName(NoiseReference r);

struct BoundedNoise {
  Eigen::Matrix3d reference = Eigen::Matrix3d::Identity();  ///< Sigma^-1 of eq. 5.52
  /// alpha_j = lambda_max(Sigma^(1/2) Omega_j Sigma^(1/2)): the smallest scalar with
  /// Omega_j <= alpha_j Sigma^-1. One per edge of the pose graph, >= 1.
  std::vector<double> alpha;
  /// lambda_min / lambda_max of the same matrix, in (0, 1]: 1 when the bound is sharp for the
  /// edge (Omega_j = alpha_j Sigma^-1, the equality case of eq. 5.54).
  std::vector<double> sharpness;
};

/// alpha_j of every edge. Throws InputError for a graph without edges or an edge whose
/// information is not symmetric positive definite (naming the edge).
BoundedNoise boundedNoise(const PoseGraph& g, NoiseReference reference);

/// The pose graph as a multigraph: one node per pose, one edge per measurement (self-loops
/// kept, they carry no information), Edge::information = alpha_j (or 1 when `alpha` is
/// empty), Edge::length = distance between the end poses' estimates.
Multigraph poseGraphAsMultigraph(const PoseGraph& g, const std::vector<double>& alpha);

/// Exact un-anchored information J^T Omega J at the current estimate (3n x 3n).
Eigen::SparseMatrix<double> fisherInformation(const PoseGraph& g);
/// Theorem 5.2.1: sum_j E_j (x) Sigma_j^-1|w (3n x 3n).
Eigen::SparseMatrix<double> edgeSumInformation(const PoseGraph& g);
/// Eq. 5.53's right side: L_alpha (x) Sigma^-1, alpha and Sigma^-1 from `b`.
Eigen::SparseMatrix<double> boundInformation(const PoseGraph& g, const BoundedNoise& b);

/// ||Y||_p of an un-anchored information matrix on the complement of its null space, whose
/// basis is the columns of `gauge` (3n x 3): the power mean of order p (any p <= 1, -inf: E)
/// of those 3(n-1) eigenvalues (0 for p <= 0 if one is not positive). Dense
/// eigen-decomposition: meant for 3n up to a few thousand.
double informationFunction(const Eigen::SparseMatrix<double>& Y, const Eigen::MatrixXd& gauge,
                           double p);
/// log of the pseudo-determinant of Y restricted to the complement of its null space, whose
/// basis is the columns of `gauge` (3n x 3): pdet(Y) = det(Y without node 0's rows/columns)
/// det(K^T K) / det(K_0)^2. Sparse Cholesky: any size. -inf if Y is singular there.
double logPseudoDeterminant(const Eigen::SparseMatrix<double>& Y, const Eigen::MatrixXd& gauge);
/// Null-space bases: translations and the rotation about the origin (fisherInformation), or
/// the three constant fields 1 (x) e_k (edgeSumInformation, boundInformation).
Eigen::MatrixXd rigidMotionGauge(const PoseGraph& g);
Eigen::MatrixXd translationGauge(std::size_t nodes);
/// ||Y||_0 = exp(logPseudoDeterminant / (3(n-1))): D-optimality of any size.
double dOptimality(const Eigen::SparseMatrix<double>& Y, const Eigen::MatrixXd& gauge);

/// One criterion of the theorem's chain for a pose graph: the exact information, the edge sum
/// of Theorem 5.2.1 and the bound ||L_alpha||_p ||Sigma^-1||_p of eq. 5.54.
struct TheoremCheck {
  double p = 0;
  /// ||J^T Omega J||_p. For D anchored like the edge sum: (n^3 det Y_r)^(1/(3(n-1))), Y_r
  /// without node 0 (both determinants are invariant to the parametrization; the un-anchored
  /// pseudo-determinant of J^T Omega J is not, through its rotation gauge).
  double exact = 0;
  double edge_sum = 0;  ///< ||sum_j E_j (x) Sigma_j^-1|w||_p
  double bound = 0;     ///< ||L_alpha||_p ||Sigma^-1||_p, >= edge_sum (eq. 5.54)
};
/// For D (p = 0) at any size through sparse Cholesky; other p densely (InputError when 3n >
/// `max_dense`, naming the size). A graph that does not connect every pose gives zeros.
TheoremCheck checkTheorem(const PoseGraph& g, const BoundedNoise& b, double p,
                          std::size_t max_dense = 3000);

}  // namespace asf::graph
