#pragma once
/// \file information.h
/// Information of walks on graphs and certified optimal edge weights (thesis chapter 5).
///
/// Conventions (the thesis', eq. 5.57 and 5.61):
/// - Edge j = (u, v) of a Multigraph has E_j = (e_u - e_v)(e_u - e_v)^T; the weighted
///   Laplacian is L(x) = sum_j x_j alpha_j E_j, alpha_j = Edge::information (1 unless the
///   edges carry different information: the bounded-noise model, eq. 5.53, see
///   pose_graph_information.h). Self-loops contribute nothing; parallel edges add.
/// - mu_2 <= ... <= mu_n are the n-1 eigenvalues of L(x) on the subspace orthogonal to the
///   all-ones vector (the "non-zero" eigenvalues when the support of x is connected).
/// - ||L||_p is their *normalised* power mean: ((1/(n-1)) sum mu_i^p)^(1/p) for p != 0,
///   (prod mu_i)^(1/(n-1)) for p = 0, mu_2 for p = -inf. p = 1 is T (mean degree / ...),
///   0 is D (spanning trees), -1 is A (Kirchhoff index), -inf is E (algebraic connectivity).
///   So ||L||_p <= 2 sum(x alpha) / (n-1) for every p <= 1, with equality for K_n and uniform x
///   and alpha.
/// - The information rate of x is ||L(x)||_p / sum(x) (scale invariant); the optimum of a
///   criterion is the maximum of ||L(x)||_p over the simplex sum x = 1, x >= 0, which is also
///   the best information rate; the efficiency of a walk is its rate divided by the optimum.
/// - A graph (or the support of x) that does not connect all n nodes has information 0 and
///   `connected = false`; a graph with one node has no eigenvalues and is reported the same way.
#include <asf/graph/multigraph.h>

#include <Eigen/Core>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace asf::graph {

/// Orders p of the named criteria.
constexpr double kCriterionT = 1.0;
constexpr double kCriterionD = 0.0;
constexpr double kCriterionA = -1.0;
constexpr double kCriterionE = -std::numeric_limits<double>::infinity();

/// "T", "D", "A", "E" (any case) or a number p <= 1 ("-2", "0.5", "-inf"). Throws InputError
/// naming the text for anything else.
double parseCriterion(const std::string& text);
/// "T", "D", "A", "E" for those orders, else "p=<value>".
std::string criterionName(double p);

/// True when the edges with x_j > 0 (self-loops aside) connect all n >= 2 nodes.
bool supportConnected(const Multigraph& g, const Eigen::VectorXd& x);
/// Dense n x n weighted Laplacian. x has one entry per edge (size checked: InputError).
Eigen::MatrixXd laplacian(const Multigraph& g, const Eigen::VectorXd& x);
/// The n-1 eigenvalues of L(x) on the complement of the all-ones vector, ascending.
Eigen::VectorXd reducedSpectrum(const Multigraph& g, const Eigen::VectorXd& x);
/// Normalised power mean of order p (p <= 1, -inf allowed) of positive eigenvalues; 0 if any
/// is <= 0 and p <= 0. Empty input gives 0.
double powerMean(const Eigen::VectorXd& mu, double p);

struct Information {
  double value = 0;        ///< ||L(x)||_p (0 when not connected)
  double rate = 0;         ///< value / sum(x) (0 when sum(x) = 0)
  double total = 0;        ///< sum(x)
  bool connected = false;  ///< edges with x_j > 0 (self-loops aside) connect all n >= 2 nodes
};

/// Information of edge weights (or traversal counts) x >= 0 (InputError if negative/NaN).
Information information(const Multigraph& g, const Eigen::VectorXd& x, double p);
/// ||L(x)||_0 (D) of any size: the product of mu_2..mu_n is n det(L(x) without node 0) (the
/// matrix-tree theorem), taken from a sparse Cholesky factorization, so a graph of thousands
/// of nodes costs milliseconds where information(g, x, kCriterionD) is O(n^3). The same value
/// (0 when the support of x does not connect every node or n < 2); InputError as there.
double dOptimalitySparse(const Multigraph& g, const Eigen::VectorXd& x);
/// Traversal counts of a walk given as its sequence of edge indices: consecutive edges must
/// share the node the walk is at (parallel edges make node sequences ambiguous). Throws
/// InputError for an index out of range or a sequence that is not a walk.
Eigen::VectorXd walkEdgeCounts(const Multigraph& g, const std::vector<int>& edge_sequence);
/// information(g, walkEdgeCounts(g, edges), p).
Information walkInformation(const Multigraph& g, const std::vector<int>& edge_sequence, double p);
/// Efficiency of traversal counts: information rate / optimum (0 if optimum <= 0).
double efficiency(const Multigraph& g, const Eigen::VectorXd& counts, double p, double optimum);

/// Certified optimum of max ||L(x)||_p over the simplex.
struct OptimalDesign {
  double p = 0;
  bool connected = false;   ///< false: every x has information 0 (optimum 0, gap 0)
  double value = 0;         ///< ||L(x)||_p at `weights` (a lower bound of the optimum)
  double upper_bound = 0;   ///< from the dual certificate: optimum <= upper_bound
  double gap = 0;           ///< upper_bound - value >= 0
  double relative_gap = 0;  ///< gap / upper_bound (0 when upper_bound = 0)
  /// x on the simplex. Self-loops get 0; of parallel edges only those of the pair's largest
  /// information get weight (equal shares): the pair's information is sum x_j alpha_j.
  Eigen::VectorXd weights;
  /// E only: the dual matrix W (n x n, PSD, W 1 = 0, trace 1) with upper_bound =
  /// max_j <W, E_j>. Empty for the other criteria, whose certificate is the gradient:
  /// upper_bound = value * max_j g_j / sum_j x_j g_j, g_j = a_j^T L^(p-1) a_j.
  Eigen::MatrixXd dual;
  int iterations = 0;
  bool converged = false;  ///< relative_gap <= the tolerance asked for
  double time_ms = 0;
};

struct DesignOptions {
  /// Target relative gap; <= 0 picks the default: 5e-7 for smooth criteria, 5e-6 for E
  /// (both under the promised 1e-6 and 1e-5).
  double tolerance = 0;
  int max_iterations = 200;
  /// Called once per iteration with the iteration, a lower and an upper bound of the optimum
  /// at that point (smooth criteria: the iterate's value and its gradient bound, from
  /// iteration 0; E: the interior point's estimates t / sum x and max_j <Z, E_j> / tr Z, from
  /// iteration 1). For progress reports; empty: not called.
  std::function<void(int iteration, double lower, double upper)> on_iteration;
};

/// Maximizes ||L(x)||_p over the simplex for any p <= 1 (p = -inf: E). Smooth criteria:
/// three multiplicative steps, then Newton steps on F_p(x) = tr(L^p)/p (log det for p = 0) with
/// the exact Hessian (closed form for D and A, Daleckii-Krein for other p: O(m^2 n^2), meant for
/// small graphs) over the free edges, along the projection arc (negative weights clipped to
/// zero) with an Armijo search; certified by the gradient bound above (Pukelsheim's general
/// equivalence theorem, a Hoelder inequality between ||.||_p and its polar). E: primal-dual
/// interior point method (HKM direction, Mehrotra predictor-corrector) on the SDP
/// max t s.t. L(x) >= t (I - 11^T/n), sum x = 1, x >= 0, whose dual gives W.
/// p = 1 is linear on the simplex (2 sum x_j alpha_j / (n-1)): all weight goes to the edges
/// of largest information (uniform weights when every alpha_j = 1).
/// A graph with fewer than 2 nodes, no non-loop edge or not connected: connected = false,
/// value = upper_bound = 0, uniform weights over the non-loop edges. Throws InputError for
/// p > 1 or NaN. Deterministic.
OptimalDesign optimalDesign(const Multigraph& g, double p, const DesignOptions& options = {});

/// An upper bound on the optimum of criterion p from the weights x alone (normalized to the
/// simplex): the gradient bound for smooth p; for E the best W = V Z V^T over the eigenvectors
/// V of the cluster of eigenvalues within `cluster_tol` (relative) of mu_2 (a small SDP in Z).
/// A bound equal to information(x) certifies x optimal; larger means x is not (proven) optimal.
/// Returns 0 for a disconnected x.
double certificateBound(const Multigraph& g, const Eigen::VectorXd& x, double p,
                        double cluster_tol = 1e-6);
/// max_j <W, E_j> / trace(W restricted to 1-perp): the E upper bound of any PSD W.
double dualBoundE(const Multigraph& g, const Eigen::MatrixXd& W);

/// E-optimal design for arbitrary design vectors: max over the simplex of
/// lambda_min(sum_j y_j a_j a_j^T), the rows of A being the a_j (spanning R^k). Same solver
/// and certificate as optimalDesign(g, -inf); `dual` is the k x k W.
OptimalDesign optimalDesignE(const Eigen::MatrixXd& A, const DesignOptions& options = {});

/// --- Exhaustive search of traversals (thesis figures 5.6 - 5.10) ---------------------

enum class TraversalKind {
  Multiset,    ///< any multiset of d edges (figs 5.6, 5.7: no traversability constraint)
  Walk,        ///< edge sequences of walks with d traversals (figs 5.8 - 5.10)
  ClosedWalk,  ///< walks that end where they started
};

struct ExhaustiveOptions {
  TraversalKind kind = TraversalKind::Walk;
  int start = -1;  ///< walks: 0-based start node, -1 = any node
  int max_d = 12;  ///< d = 1 .. max_d
  std::vector<double> criteria{kCriterionT, kCriterionD, kCriterionA, kCriterionE};
  /// Bound on distinct states (count vector, end node) per d; above it Error is thrown.
  std::size_t max_states = 2000000;
};

struct ExhaustiveResult {
  std::vector<double> criteria;
  std::vector<int> d;  ///< 1 .. max_d
  /// information(i, c): best ||L(x)||_p over the traversals with exactly d[i] edges;
  /// rate(i, c) = information(i, c) / d[i] (every candidate has sum x = d).
  Eigen::MatrixXd information, rate;
  /// best(i)[c]: counts reaching information(i, c) (the first found).
  std::vector<std::vector<Eigen::VectorXd>> best;
  std::vector<std::size_t> candidates;  ///< distinct count vectors evaluated per d
};

/// Enumerates every traversal of d = 1..max_d edges (distinct count vectors; walks are
/// expanded by DP over (start, end node, counts) so repeated prefixes cost nothing).
ExhaustiveResult exhaustiveSearch(const Multigraph& g, const ExhaustiveOptions& options);

/// Writes an SVG with two panels: best information vs d and best information rate vs d, one
/// polyline per criterion, and (if given, one per criterion) the relaxed optimum as dashed
/// lines in the rate panel. Throws Error if the file cannot be written.
void writeExhaustiveSvg(const ExhaustiveResult& r, const std::string& path,
                        const std::string& title, const std::vector<double>& optimum = {});

}  // namespace asf::graph
