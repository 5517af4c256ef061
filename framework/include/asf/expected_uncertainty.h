#pragma once
/// \file expected_uncertainty.h
/// Path planning in the pose graph under uncertainty (thesis chapter 3): the expected
/// covariance at the end of a path when the robot may relocalize at every node (Algorithm 1,
/// O(m^2) in the path length m), the relocalization probability (Gaussian mass of the
/// robot->node relative pose inside a window, times a place-recognition probability), the
/// baseline criteria (mechanical work, sum of D-optimality, distance), and the search over
/// all simple paths of the reduced graph that every criterion shares.
///
/// Conventions: covariances are 3x3 over additive (x, y, phi) in the map frame, like
/// Marginals::node; the robot's estimate along a path is the nodes' current estimates, its
/// motion between consecutive nodes the relative pose of those estimates, with the
/// covariance of the edge(s) joining them (parallel edges fused by adding information).
#include <asf/key_spec.h>
#include <asf/planner.h>
#include <asf/pose_graph.h>

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace asf {
class Params;
}

namespace asf::eu {

// ---------------------------------------------------------------------------------------
// Gaussian rectangle probability

struct BoxProbability {
  double value = 0;
  double error = 0;  ///< standard error over the randomized lattice shifts (0 if exact)
};

/// P(lower <= x <= upper) for x ~ N(mean, cov), any dimension, cov positive semi-definite
/// (a degenerate direction is handled as a point mass). Genz's separation of variables: the
/// first variable integrated exactly, the rest by a randomized rank-1 (Richtmyer) lattice of
/// `points` points split in `shifts` random shifts drawn from `seed`. Exact (error 0) when
/// cov is diagonal. Throws asf::Error when cov is not symmetric PSD or sizes differ.
BoxProbability gaussianBoxProbability(const Eigen::VectorXd& mean, const Eigen::MatrixXd& cov,
                                      const Eigen::VectorXd& lower,
                                      const Eigen::VectorXd& upper, int points = 256,
                                      int shifts = 8, std::uint64_t seed = 1);

// ---------------------------------------------------------------------------------------
// A path prepared for evaluation

/// Everything the criteria need about one path n_0..n_m, gathered once.
struct PathModel {
  std::vector<NodeId> nodes;                 ///< n_0..n_m
  std::vector<mrpt::poses::CPose2D> pose;    ///< node estimates
  std::vector<Eigen::Matrix3d> sigma;        ///< node marginals Sigma_{n_t}
  /// motion[t], t >= 1: relative pose of n_t's estimate in n_{t-1}'s frame; motion_cov[t]:
  /// its covariance in n_{t-1}'s frame. Index 0 unused (identity / zero).
  std::vector<mrpt::poses::CPose2D> motion;
  std::vector<Eigen::Matrix3d> motion_cov;
  const Marginals* marginals = nullptr;      ///< for cross-covariance blocks
  std::size_t steps() const { return nodes.empty() ? 0 : nodes.size() - 1; }
};

/// Throws asf::Error when a node does not exist, two consecutive nodes share no edge, or
/// `marginals` lacks a node block (pass nullptr: sigma is zero, for distance only).
PathModel makePathModel(const PoseGraph& g, const Marginals* marginals,
                        const std::vector<NodeId>& path);

/// Cov(x_a, x_b) from marginals (node block when a == b; cross block (a, b) or the
/// transpose of (b, a)). Returns false (and zero) when not available.
bool crossCovariance(const Marginals& m, NodeId a, NodeId b, Eigen::Matrix3d& out);

// ---------------------------------------------------------------------------------------
// Algorithm 1

/// The robot arrives at step t of the path having last relocalized at step k (k = 0: the
/// start, where it is as certain as node n_0). robot_cov: its propagated covariance;
/// chain: the product of the motion Jacobians since step k, so that
/// Cov(robot, x) = chain * Cov(x_{n_k}, x) for any map node x.
struct RelocQuery {
  std::size_t k, t;
  const Eigen::Matrix3d& robot_cov;
  const Eigen::Matrix3d& chain;
};
/// Probability in [0, 1] of relocalizing at step t under hypothesis k.
using RelocProbFn = std::function<double(const RelocQuery&)>;

struct ExpectedCovariance {
  Eigen::Matrix3d mean = Eigen::Matrix3d::Zero();  ///< E[C] at the goal
  /// prob[k]: probability that the last relocalization was at step k (0 = none).
  std::vector<double> prob;
  std::size_t evaluations = 0;   ///< calls of the probability function
  double pruned_mass = 0;        ///< probability of hypotheses dropped below prune_below
};

/// Algorithm 1: hypotheses h_k (last relocalization at step k) propagate by first-order
/// composition and are weighted by 1 - p; the new hypothesis h_t takes Sigma_{n_t} and the
/// relocalized mass. Hypotheses whose probability falls below `prune_below` are dropped
/// (their mass reported; 0 keeps all: exactly O(m^2)).
ExpectedCovariance expectedCovariance(const PathModel& path, const RelocProbFn& p,
                                      double prune_below = 0);
/// The oracle: all 2^m relocalization sequences enumerated (m <= 24). O(m 2^m).
Eigen::Matrix3d expectedCovarianceBruteForce(const PathModel& path, const RelocProbFn& p);

// ---------------------------------------------------------------------------------------
// Relocalization probability

struct RelocalizationOptions {
  /// Half sizes of the localization window around the node: x, y [m] and phi [rad].
  double half_x = 0.3, half_y = 0.3, half_phi = 0.5235987755982988;
  double p_recognition = 1;                    ///< for nodes not in the table
  std::map<NodeId, double> p_recognition_by_node;
  int points = 128, shifts = 8;                ///< lattice of gaussianBoxProbability
  std::uint64_t seed = 1;
  /// Use Cov(x_{n_k}, x_{n_t}) from the marginals (else treat robot and node as independent).
  bool use_cross = true;
};

/// Reads "node_id p" lines ('#' comments and blank lines allowed); throws asf::InputError
/// naming file:line for a malformed line, p outside [0, 1] or a repeated id.
std::map<NodeId, double> readRecognitionProbabilities(const std::string& path);

/// p_t = p_recognition(n_t) * p_localization, where p_localization is the mass of
/// N(0, C_d) inside the window and C_d the covariance of the robot->node relative pose:
/// C_d = M (C_r - X - X^T + Sigma_t) M^T with X = chain * Cov(x_{n_k}, x_{n_t}) and M the
/// rotation into the node's frame. `missing_cross` (if given) counts queries whose cross
/// block the marginals lacked (treated as zero).
RelocProbFn relocalizationProbability(const PathModel& path, const RelocalizationOptions& o,
                                      std::size_t* missing_cross = nullptr);

// ---------------------------------------------------------------------------------------
// Criteria

enum class Criterion { ExpectedUncertainty, MechanicalWork, SumDopt, Distance };
const char* criterionName(Criterion c);  ///< "expected_uncertainty", ...
/// Scalar of a covariance: det, trace, or det^(1/3).
enum class Scalar { Det, Trace, DetCbrt };
double scalarOf(const Eigen::Matrix3d& c, Scalar s);
const char* scalarName(Scalar s);  ///< "det", "trace", "det_cbrt"
bool parseScalar(const std::string& s, Scalar& out);

struct CriterionOptions {
  Scalar scalar = Scalar::Det;         ///< of E[C] (expected_uncertainty) and of Sigma (sum_dopt)
  RelocalizationOptions reloc;
  double prune_below = 1e-12;
  /// > 0: p_recognition of the nodes with a scan and not in p_recognition_file by Monte
  /// Carlo with this many ICP samples each (place_recognition.h); 0: the constant.
  int recognition_samples = 0;
  double recognition_map_radius = 6.0;  ///< local map of the Monte Carlo [m]
};

/// Reads the keys this module defines from a plugin's params, when present: scalar,
/// window_x, window_y, window_phi_deg, p_recognition, p_recognition_file, qmc_points,
/// qmc_shifts, use_cross, prune_below, recognition_samples, recognition_map_radius; the seed
/// is ctx_seed unless a `seed` key is non-zero.
/// Throws ConfigError (naming the key) for a bad scalar or recognition file.
CriterionOptions criterionOptionsFrom(const Params& params, std::uint64_t ctx_seed);

struct PathCost {
  double cost = 0;
  std::string label;                      ///< e.g. "det(E[C])"
  Eigen::Matrix3d expected = Eigen::Matrix3d::Zero();  ///< E[C] (expected_uncertainty only)
  std::size_t missing_cross = 0;
};

/// expected_uncertainty: scalar(E[C]). mechanical_work (Valencia et al.): sum of positive
/// increments of U_t = det((O_t^-1 + Sigma_t^-1)^-1) = det(Sigma_t) det(O_t) / det(O_t +
/// Sigma_t), O_t the motion covariance into n_t (n_0 uses O_1). sum_dopt (Carrillo et al.):
/// sum over the path's nodes of scalar(Sigma_t). distance: sum of Euclidean steps.
PathCost evaluatePath(Criterion c, const PathModel& path, const CriterionOptions& o);

// ---------------------------------------------------------------------------------------
// Search

/// Reduced graph: parallel edges merged, self-loops dropped, chains of degree-2 nodes
/// collapsed into one edge holding its interior nodes (start and goal are always kept).
struct ReducedGraph {
  struct Edge {
    NodeId a, b;
    std::vector<NodeId> interior;  ///< nodes strictly between a and b, in order a -> b
  };
  std::vector<NodeId> kept;           ///< nodes of the reduced graph
  std::vector<Edge> edges;
};
ReducedGraph reduceGraph(const PoseGraph& g, NodeId start, NodeId goal);

/// The path-search keys every criterion planner plugin declares (max_paths, reduce,
/// max_seconds), one definition for their docs and defaults.
constexpr KeySpec keyMaxPaths() {
  return keyInt("max_paths", "10000", "Candidate simple paths evaluated at most", 1, 1e9);
}
constexpr KeySpec keyReduce() {
  return keyBool("reduce", "true", "Search the reduced graph (degree-2 chains collapsed)");
}
constexpr KeySpec keyMaxSeconds() {
  return keyDouble("max_seconds", "10",
                   "Time budget of the path search and, again, of the evaluation of the "
                   "candidates; the best found so far is kept (0: no limit) [s]",
                   0, 1e6);
}

struct PathSearchOptions {
  std::size_t max_paths = 10000;  ///< stop after this many paths (reported as capped)
  bool reduce = true;             ///< search the reduced graph (false: the simple graph)
  /// The search and then planBest's evaluation of the candidates each stop after this many
  /// seconds (0: no limit), keeping what they have and saying so in the note: a loopy graph
  /// has more paths than time allows.
  double max_seconds = 0;
};
/// The search keys of a planner's params, when present (max_paths, reduce, max_seconds).
PathSearchOptions pathSearchOptionsFrom(const Params& params);

struct PathSearchResult {
  std::vector<std::vector<NodeId>> paths;  ///< expanded node sequences start..goal
  bool capped = false;     ///< stopped at max_paths or by the time budget
  bool timed_out = false;  ///< stopped by max_seconds
  std::size_t reduced_nodes = 0, reduced_edges = 0;
};
/// All simple paths from start to goal (depth-first over the reduced graph, expanded back).
/// Throws asf::Error for nodes that do not exist.
PathSearchResult allSimplePaths(const PoseGraph& g, NodeId start, NodeId goal,
                                const PathSearchOptions& o = {});

/// The planners' common body: every candidate path evaluated under `c`, the cheapest
/// returned (ties: fewer nodes, then the first found). Missing graph, marginals (for the
/// uncertainty criteria) or bad ids give found = false with a reason. `note` receives a
/// line about the cap or missing cross blocks, if any.
PlanResult planBest(const PlanRequest& req, Criterion c, const CriterionOptions& o,
                    const PathSearchOptions& search, std::string* note = nullptr);

/// The planner plugins of this library (expected_uncertainty, mechanical_work, sum_dopt)
/// differ only in their criterion and key table: each is this class with its criterion.
/// configure() reads the criterion keys the table declares plus `max_paths` and `reduce`;
/// plan() is planBest(), with the note logged as a warning and errors as found = false.
class CriterionPlanner : public Planner {
 public:
  explicit CriterionPlanner(Criterion c) : criterion_(c) {}
  void configure(const Params& params, const PluginContext& ctx) override;
  PlanResult plan(const PlanRequest& req) override;

 private:
  Criterion criterion_;
  CriterionOptions options_;
  PathSearchOptions search_;
  /// Monte Carlo p_recognition per node, for the graph revision it was computed on.
  std::map<NodeId, double> recognition_;
  std::uint64_t recognition_revision_ = 0;
};

// ---------------------------------------------------------------------------------------
// Drawing

struct RenderOptions {
  int max_size = 1200;         ///< longest image side [px] (when no map is given)
  bool ellipses = false;       ///< 3-sigma position ellipses of the marginals
  std::string map_png;         ///< optional background (row 0 = top, origin (0, 0))
  double map_resolution = 0.05;
};
/// Draws the graph (metres, y up) with `path` highlighted to a PNG; throws asf::Error
/// naming the file when it cannot be written.
void renderPlan(const std::string& png, const PoseGraph& g, const Marginals* marginals,
                const std::vector<NodeId>& path, const RenderOptions& o);

}  // namespace asf::eu
