#pragma once
/// \file sparse_se2.h
/// The numerical core of the `sparse_lm` back-end: SE(2) pose-graph least squares with sparse
/// normal equations factorized by CHOLMOD (supernodal), and marginal covariances from the
/// sparse inverse subset of the factor. Compiled into the plugin and into its tests (which
/// check the pieces the plugin interface does not show: counters, pattern membership).
#include <asf/backend.h>
#include <asf/pose_graph.h>

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace asf::sparse_lm {

enum class Method {
  LevenbergMarquardt,  ///< trust region by damping, Nielsen's update of lambda
  GaussNewton,         ///< full steps; stops at the first step that does not lower the cost
};
enum class Kernel { None, Huber, Cauchy, Dcs };
/// The edges a kernel applies to (the others keep their quadratic cost): wrong loop
/// closures are what a robust back-end must disown, the odometry chain it must keep.
enum class RobustEdges {
  All,
  LoopClosures,  ///< EdgeKind::LoopClosure only
  /// Every edge but those between consecutive nodes (the odometry / scan-matching chain):
  /// loop closures and matches against older keyframes nearby.
  CrossLinks,
};

struct Options {
  Method method = Method::LevenbergMarquardt;
  int max_iterations = 100;   ///< linearizations (LM may try several dampings on each)
  double tolerance = 1e-5;    ///< stop when an accepted step lowers the cost by less (relative)
  double lambda_init = 1e-6;  ///< initial damping, relative to diag(H) (Marquardt scaling)
  /// Also build a LAGO-style initial guess (orientations by linear least squares over
  /// unwrapped relative rotations, positions composed down a spanning tree) and start from it
  /// when its cost is below that of the graph's poses.
  bool lago_init = true;
  Kernel kernel = Kernel::None;
  double robust_delta = 2.8;  ///< kernel width, in units of sqrt(e^T Omega e)
  RobustEdges robust_edges = RobustEdges::All;
  /// Growth keeps the previous elimination order (new nodes last) unless the factor then has
  /// more than this times the fill (nnz(L)/nnz(H)) of the last fresh ordering.
  double reorder_fill_ratio = 1.3;
  /// Let CHOLMOD's OpenMP loops use their own team (else serialized in the calling thread).
  bool cholmod_openmp = false;
  int verbosity = 0;  ///< 0 quiet, 1 one line per optimize(), 2 one line per step
  std::function<void(const std::string&)> log;  ///< receives the lines of `verbosity`
};

/// What happened to CHOLMOD's symbolic analysis, counted over the object's life.
struct Counters {
  long fresh_orderings = 0;     ///< block AMD + symbolic analysis (structure new or changed)
  long extended_orderings = 0;  ///< growth: previous order + new nodes, symbolic analysis redone
  long reused = 0;              ///< same structure as the previous call: symbolic factor kept
  long factorizations = 0;      ///< numeric factorizations
  /// Seconds spent in each phase, summed over calls (for profiling).
  double t_analysis = 0, t_linearize = 0, t_factorize = 0, t_solve = 0, t_cost = 0, t_inverse = 0,
         t_init = 0;
};

/// Cost rho(s) of one edge with squared Mahalanobis error s = e^T Omega e (g2o's kernels:
/// Huber rho = s below delta^2, 2 delta sqrt(s) - delta^2 above; Cauchy rho = delta^2
/// log(1 + s / delta^2)), and the weight rho'(s) that scales Omega in the normal equations.
/// Dcs: dynamic covariance scaling (Agarwal, Tipaldi, Spinello, Stachniss, Burgard, ICRA
/// 2013) with Phi = delta^2: Omega scaled by s_dcs^2, s_dcs = min(1, 2 Phi / (Phi + s)), the
/// closed-form optimum of switchable constraints; its cost, rho = s below Phi and
/// Phi (3 s - Phi) / (Phi + s) above (bounded by 3 Phi), has that weight as derivative.
double robustCost(Kernel k, double delta, double s);
double robustWeight(Kernel k, double delta, double s);

class SparseSe2 {
 public:
  SparseSe2();
  ~SparseSe2();
  SparseSe2(const SparseSe2&) = delete;
  SparseSe2& operator=(const SparseSe2&) = delete;

  /// The backend.h contract. With a kernel, the report's chi2 values are the robust cost
  /// sum rho(e^T Omega e) (the objective minimized); without, the g2o chi2.
  asf::OptimizeReport optimize(asf::PoseGraph& g, const Options& o);

  /// Marginal covariances at the graph's current poses (kernel weights included when a
  /// kernel is set). Throws asf::Error for a node not connected to node 0 or a fixed node.
  asf::Marginals marginals(const asf::PoseGraph& g,
                           const std::vector<std::pair<asf::NodeId, asf::NodeId>>& cross,
                           const Options& o);

  /// Optimizes only the nodes in `window` (node 0 and g.fixed stay held even there), over
  /// the edges g.edges[k], k in `edges` (those touching the window; the others cannot move
  /// it). Every other node is held where it is. The report's chi2 values are those edges'.
  /// Uses (and replaces) this object's factor: a window solver is a SparseSe2 of its own.
  asf::OptimizeReport optimizeWindow(asf::PoseGraph& g, const std::vector<asf::NodeId>& window,
                                     const std::vector<std::size_t>& edges, const Options& o);

  /// b^T H0^-1 b, where b = J^T W e is the gradient of g's cost at its poses over the nodes of
  /// the last factorized matrix H0 (the first factorNodes() nodes; later nodes are left out)
  /// and H0 that matrix (from the last optimize() or marginals()). When g holds H0's edges
  /// plus others and b vanishes on the later nodes, this bounds the decrease of chi2 a
  /// Gauss-Newton step on the whole of g would make: g's information on the old nodes after
  /// eliminating the new ones is at least H0's. nullopt without a valid factor or if the
  /// gauge / fixed nodes differ.
  std::optional<double> decrementBound(const asf::PoseGraph& g, const Options& o);
  /// Columns of H0^-1 (H0: the last factorized matrix) for `nodes`, free nodes of H0, as a
  /// (3 factorNodes()) x (3 nodes.size()) matrix with rows by node id (held nodes' rows
  /// zero). H0 is the information matrix only after marginals(): optimize() leaves a damped
  /// one. Throws asf::Error for a node outside the factor or held.
  Eigen::MatrixXd covarianceColumns(const std::vector<asf::NodeId>& nodes, const Options& o);
  /// Number of nodes of the graph the current factor belongs to (0: none).
  std::size_t factorNodes() const;

  const Counters& counters() const;
  /// How the last optimize()/marginals() obtained its symbolic factor: "reused",
  /// "extended ordering" or "fresh ordering" (or "none" for a problem without variables).
  const std::string& lastSymbolic() const;
  /// Of the cross blocks requested in the last marginals() call, how many were outside the
  /// factor's pattern (computed by solving for their columns instead).
  std::size_t lastCrossSolved() const;
  /// nnz of the last factor (supernodal storage, including amalgamation zeros).
  std::size_t factorNonzeros() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace asf::sparse_lm
