#pragma once
/// \file expected_uncertainty.h
/// Path planning in the pose graph under uncertainty (thesis chapter 3): the expected
/// covariance at the end of a path when the robot may relocalize at every node (Algorithm 1,
/// O(m^2) in the path length m), the relocalization probability (Gaussian mass of the
/// robot->node relative pose inside a window, times a place-recognition probability), the
/// baseline criteria (mechanical work, sum of D-optimality, distance), and the search over
/// candidate routes of the reduced, alias-merged graph that every criterion shares.
///
/// Conventions: covariances are 3x3 over additive (x, y, phi) in the map frame, like
/// Marginals::node; the robot's estimate along a path is the nodes' current estimates, its
/// motion between consecutive nodes the relative pose of those estimates, with the
/// covariance of the edge(s) joining them (parallel edges fused by adding information).
#include <asf/key_spec.h>
#include <asf/planner.h>
#include <asf/pose_graph.h>
#include <asf/planning/voronoi_graph.h>

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace asf {
class Params;
}

namespace asf::planning {

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
  /// Virtual steps (partially explored maps, voronoi_graph.h): virtual_step[t] != 0 when
  /// n_{t-1} -> n_t is a virtual edge of the GVG, not an edge of the pose graph; then
  /// motion[t] is still the relative pose of the estimates, motion_cov[t] the virtual
  /// edge's odometry covariance, virtual_length[t] its length through free space, and no
  /// relocalization is possible on it: expectedCovariance (and the brute force) take p = 0
  /// at step t without asking the probability function. Empty or all zero: no virtual step.
  std::vector<char> virtual_step;
  std::vector<double> virtual_length;
  std::size_t steps() const { return nodes.empty() ? 0 : nodes.size() - 1; }
  bool isVirtual(std::size_t t) const { return t < virtual_step.size() && virtual_step[t]; }
};

/// Throws asf::Error when a node does not exist, two consecutive nodes share no edge (nor,
/// when `virtual_edges` is given, a virtual edge), or `marginals` lacks a node block (pass
/// nullptr: sigma is zero, for distance only). A pose-graph edge is preferred to a virtual
/// edge between the same nodes.
PathModel makePathModel(const PoseGraph& g, const Marginals* marginals,
                        const std::vector<NodeId>& path,
                        const std::vector<VirtualEdge>* virtual_edges = nullptr);

/// Length of the path [m]: the Euclidean steps between the node estimates, except virtual
/// steps, which count their length through free space (VirtualEdge::length).
double pathLength(const PathModel& path);

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
  /// planBest: costs within this relative distance of the cheapest are ties, broken by
  /// distance. E[C] is the goal's marginal on every path along which the robot surely
  /// relocalizes near the goal; without it round-off would pick among those.
  double tie_tolerance = 1e-6;
};

/// Reads the keys this module defines from a plugin's params, when present: scalar,
/// window_x, window_y, window_phi_deg, p_recognition, p_recognition_file, qmc_points,
/// qmc_shifts, use_cross, prune_below, tie_tolerance, recognition_samples,
/// recognition_map_radius; the seed
/// is ctx_seed unless a `seed` key is non-zero.
/// Throws ConfigError (naming the key) for a bad scalar or recognition file.
CriterionOptions criterionOptionsFrom(const Params& params, std::uint64_t ctx_seed);

struct PathCost {
  double cost = 0;
  std::string label;                      ///< e.g. "det(E[C])"
  Eigen::Matrix3d expected = Eigen::Matrix3d::Zero();  ///< E[C] (expected_uncertainty only)
  std::size_t missing_cross = 0;
};

/// expected_uncertainty: scalar(E[C]) (planBest with voronoi_edges: pathLength x that, see
/// PathSearchOptions::voronoi_edges). mechanical_work (Valencia et al.): sum of positive
/// increments of U_t = det((O_t^-1 + Sigma_t^-1)^-1) = det(Sigma_t) det(O_t) / det(O_t +
/// Sigma_t), O_t the motion covariance into n_t (n_0 uses O_1). sum_dopt (Carrillo et al.):
/// sum over the path's nodes of scalar(Sigma_t). distance: pathLength (Euclidean steps).
PathCost evaluatePath(Criterion c, const PathModel& path, const CriterionOptions& o);

// ---------------------------------------------------------------------------------------
// Search

/// Reduced graph: parallel edges merged, self-loops dropped, chains of degree-2 nodes
/// collapsed into one edge holding its interior nodes (start and goal are always kept).
/// Also used over the vertices of a SearchGraph (ids are then vertex ids).
struct ReducedGraph {
  struct Edge {
    NodeId a, b;
    std::vector<NodeId> interior;  ///< nodes strictly between a and b, in order a -> b
  };
  std::vector<NodeId> kept;           ///< nodes of the reduced graph
  std::vector<Edge> edges;
};
ReducedGraph reduceGraph(const PoseGraph& g, NodeId start, NodeId goal);

/// The path-search keys every criterion planner plugin declares, one definition for their
/// docs and defaults.
constexpr KeySpec keyMaxPaths() {
  return keyInt("max_paths", "10000",
                "Exhaustive enumeration: at most this many simple routes (search = all: the "
                "cap, reported; search = auto: beyond it, Yen's k_paths shortest instead)",
                1, 1e9);
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
constexpr KeySpec keySearch() {
  return keyEnum("search", "auto", "auto|all|yen",
                 "Candidate routes: all (every simple route, capped at max_paths), yen "
                 "(Yen's k_paths shortest simple routes), auto (all while at most max_paths, "
                 "else yen)");
}
constexpr KeySpec keyKPaths() {
  return keyInt("k_paths", "20", "Yen's search: number of shortest simple routes", 1, 1e6);
}
constexpr KeySpec keyMergeRadius() {
  return keyDouble("merge_radius", "1.0",
                   "Aliased loop closures: nodes tied by loop closures and all within this "
                   "distance of each other are one vertex of the search graph (0: no merge) [m]",
                   0, 1e6);
}
constexpr KeySpec keyAddShortest() {
  return keyBool("add_shortest", "true",
                 "Add the shortest path of the pose graph (Dijkstra, metres) to the candidates");
}

constexpr KeySpec keyTieTolerance() {
  return keyDouble("tie_tolerance", "1e-6",
                   "Candidates whose cost is within this (relative) of the cheapest tie; the "
                   "shortest of them (metres) is chosen",
                   0, 1);
}
constexpr KeySpec keyDiversePaths() {
  return keyInt("diverse_paths", "10",
                "With Yen's search: also this many routes of the penalty method (each route's "
                "edges get longer by diverse_penalty x, then the next shortest), which reach "
                "other corridors where Yen's K are variants of one (0: none)",
                0, 1e6);
}
constexpr KeySpec keyDiversePenalty() {
  return keyDouble("diverse_penalty", "1.0",
                   "Penalty method: each use multiplies an edge's length by 1 + this", 1e-6, 1e6);
}

/// Virtual edges of the generalized Voronoi graph (partially explored maps, thesis 3.6).
constexpr KeySpec keyVoronoiEdges() {
  return keyBool("voronoi_edges", "false",
                 "With a map in the request: also search through virtual edges of the map's "
                 "generalized Voronoi graph between nodes the pose graph does not join (odometry "
                 "covariance, no relocalization on them); expected_uncertainty then scores every "
                 "candidate by distance x scalar(E[C]) (thesis eq. 3.25)");
}
constexpr KeySpec keyVoronoiFreeThreshold() {
  return keyDouble("voronoi_free_threshold", "0.65",
                   "Voronoi edges: a cell is free when p(free) > this (unknown 0.5 is not)", 0,
                   0.999);
}
constexpr KeySpec keyVoronoiClearance() {
  return keyDouble("voronoi_clearance", "0.2",
                   "Voronoi edges: robot clearance, the GVG keeps farther than this from "
                   "non-free cells [m]",
                   0, 100);
}
constexpr KeySpec keyVoronoiAttachRadius() {
  return keyDouble("voronoi_attach_radius", "1.0",
                   "Voronoi edges: a node attaches to the GVG cell nearest along free cells, "
                   "if within this [m]",
                   0, 1000);
}
constexpr KeySpec keyVoronoiDetour() {
  return keyDouble("voronoi_detour", "1.5",
                   "Voronoi edges: only where the pose graph's own route is longer than this x "
                   "the virtual edge (a shortcut)",
                   1, 1e6);
}
constexpr KeySpec keyVoronoiCovarianceScale() {
  return keyDouble("voronoi_cov_scale", "1.0",
                   "Voronoi edges: factor on the odometry covariance of a virtual edge (the "
                   "default odometry noise model of driving its length)",
                   1e-9, 1e12);
}

constexpr KeySpec keyVoronoiOdometryStep() {
  return keyDouble("voronoi_odometry_step", "0",
                   "Voronoi edges: > 0, the drive is this many metres per odometry increment, "
                   "their covariances composed (MRPT's model is per increment: its std grows "
                   "with the increment, so one long step overstates the drift; the source's "
                   "step, e.g. distance / frames of the run); 0: the whole edge as one "
                   "increment",
                   0, 1e6);
}

/// Every path-search key above, in the order the criterion planners declare them: put
/// `ASF_EU_PATH_SEARCH_KEYS` in a plugin's KeySpec table (one list, so the plugins agree).
#define ASF_EU_PATH_SEARCH_KEYS                                                               \
  asf::planning::keyMaxPaths(), asf::planning::keyReduce(), asf::planning::keyMaxSeconds(),   \
      asf::planning::keySearch(), asf::planning::keyKPaths(),                                 \
      asf::planning::keyTieTolerance(), asf::planning::keyDiversePaths(),                     \
      asf::planning::keyDiversePenalty(), asf::planning::keyMergeRadius(),                    \
      asf::planning::keyAddShortest()
/// The virtual-edge keys (voronoi_*), declared by the criterion planners after
/// ASF_EU_PATH_SEARCH_KEYS.
#define ASF_EU_VORONOI_KEYS                                                                   \
  asf::planning::keyVoronoiEdges(), asf::planning::keyVoronoiFreeThreshold(),                 \
      asf::planning::keyVoronoiClearance(), asf::planning::keyVoronoiAttachRadius(),          \
      asf::planning::keyVoronoiDetour(), asf::planning::keyVoronoiCovarianceScale(),          \
      asf::planning::keyVoronoiOdometryStep()

enum class SearchMethod { Auto, All, Yen };
const char* searchMethodName(SearchMethod m);  ///< "auto", "all", "yen"

struct PathSearchOptions {
  SearchMethod method = SearchMethod::Auto;
  /// All: stop after this many routes (reported as capped). Auto: enumerate while at most
  /// this many (and at most max(64 x max_paths, 4096) depth-first expansions), else Yen's.
  std::size_t max_paths = 10000;
  std::size_t k_paths = 20;       ///< Yen's K
  /// With Yen's: also this many routes of the penalty method (diversePaths), factor 1 + p.
  std::size_t diverse_paths = 10;
  double diverse_penalty = 1.0;
  bool reduce = true;             ///< collapse degree-2 chains of the search graph
  /// Merge radius of aliased loop closures [m] (0: the search graph is the pose graph).
  double merge_radius = 1.0;
  bool add_shortest = true;       ///< add the pose graph's Dijkstra shortest path
  /// The search and then planBest's evaluation of the candidates each stop after this many
  /// seconds (0: no limit), keeping what they have and saying so in the note: a loopy graph
  /// has more paths than time allows.
  double max_seconds = 0;
  /// Partially explored maps (thesis section 3.6): when the request has a map, planBest adds
  /// the virtual edges of its generalized Voronoi graph (computeVirtualEdges with
  /// `voronoi`) to the search graph; a chosen path may then step along a virtual edge
  /// (consecutive nodes without a pose-graph edge). The criterion switch is explicit: with
  /// voronoi_edges, expected_uncertainty scores every candidate -- with or without virtual
  /// steps, with or without a map -- by pathLength x scalar(E[C]) (label
  /// "distance*det(E[C])"), the thesis' eq. 3.25; the other criteria keep their cost, with
  /// the virtual steps' odometry covariance as their motion covariance.
  bool voronoi_edges = false;
  VirtualEdgeOptions voronoi;
};
/// The search keys of a planner's params, when present (search, max_paths, k_paths,
/// diverse_paths, diverse_penalty, reduce, merge_radius, add_shortest, max_seconds, and
/// voronoi_edges, voronoi_free_threshold, voronoi_clearance, voronoi_attach_radius,
/// voronoi_detour, voronoi_cov_scale).
PathSearchOptions pathSearchOptionsFrom(const Params& params);

/// The graph the candidate routes are searched in (thesis section 3.5). Vertices: clusters of
/// pose-graph nodes. Nodes tied by a loop closure (an edge of kind LoopClosure or between
/// ids more than 1 apart) whose estimates all lie within `merge_radius` of each other are
/// one vertex -- the aliases of one place a SLAM front-end links several times -- formed
/// greedily, shortest loop closures first; start and goal never share a vertex. Edges: the
/// pose-graph edges between different vertices, parallel ones merged; then degree-2 chains
/// are collapsed (`reduced`, over vertex ids). A simple route of vertices expands back to a
/// simple node path of the pose graph that visits the route's vertices in order
/// (expandRoute): so the simple routes here are exactly the distinct vertex sequences of
/// the simple paths of the pose graph that do not re-enter a vertex.
struct SearchGraph {
  std::vector<NodeId> vertex_of;             ///< pose-graph node -> vertex
  std::vector<std::vector<NodeId>> members;  ///< vertex -> its nodes (ascending)
  std::vector<Eigen::Vector2d> centre;       ///< vertex -> mean position of its nodes
  NodeId start = 0, goal = 0;                ///< vertices of the start and goal nodes
  ReducedGraph reduced;                      ///< over vertex ids
  /// Length of each reduced edge: centre-to-centre distance along its vertex chain [m].
  std::vector<double> length;
  std::size_t merged_vertices = 0;           ///< vertices holding more than one node
};
/// Throws asf::Error for nodes that do not exist.
SearchGraph buildSearchGraph(const PoseGraph& g, NodeId start, NodeId goal, double merge_radius,
                             bool reduce = true);

/// The vertex sequence of a route given as reduced edges (edge index, traversed a -> b?).
std::vector<NodeId> routeVertices(const SearchGraph& sg,
                                  const std::vector<std::pair<std::size_t, bool>>& edges);
/// A route (vertex sequence, simple, consecutive vertices adjacent, from sg.start to
/// sg.goal) as a pose-graph node path from `start` to `goal`: the shortest (metres) node
/// path that stays in the route's vertices and only moves from one vertex to the same or
/// the next. Throws asf::Error when the route is not realizable.
std::vector<NodeId> expandRoute(const PoseGraph& g, const SearchGraph& sg,
                                const std::vector<NodeId>& vertices, NodeId start, NodeId goal);

/// Yen's K shortest simple paths in an undirected multigraph with non-negative weights:
/// edge index sequences from s to t, by increasing total weight (ties: fewer edges, then
/// lexicographic edge indices). Fewer than K when there are fewer simple paths.
struct WeightedEdge {
  std::uint32_t a, b;
  double w;
};
std::vector<std::vector<std::size_t>> kShortestSimplePaths(std::size_t n,
                                                           const std::vector<WeightedEdge>& e,
                                                           std::uint32_t s, std::uint32_t t,
                                                           std::size_t k);

/// The penalty method for alternative routes: `count` times, the shortest s -> t path under
/// the current weights, whose edges then get their weight multiplied by (1 + penalty).
/// Distinct simple paths (edge index sequences) in the order found; the first is the
/// shortest path.
std::vector<std::vector<std::size_t>> diversePaths(std::size_t n,
                                                   const std::vector<WeightedEdge>& e,
                                                   std::uint32_t s, std::uint32_t t,
                                                   std::size_t count, double penalty);

/// The shortest node path (metres between estimates; Dijkstra) or empty when disconnected.
std::vector<NodeId> shortestPath(const PoseGraph& g, NodeId start, NodeId goal);

struct PathSearchResult {
  std::vector<std::vector<NodeId>> paths;  ///< expanded node sequences start..goal, distinct
  SearchMethod method = SearchMethod::All;  ///< the one that produced the routes
  bool capped = false;     ///< search = all: stopped at max_paths or by the time budget
  bool timed_out = false;  ///< stopped by max_seconds
  /// search = auto: the enumeration exceeded max_paths (or its expansion limit), Yen's used.
  bool fell_back = false;
  bool added_shortest = false;  ///< the Dijkstra path was not among the routes: appended
  std::size_t diverse_added = 0;  ///< routes of the penalty method not among Yen's
  std::size_t reduced_nodes = 0, reduced_edges = 0, merged_vertices = 0;
};
/// The candidate paths of the criterion planners (see PathSearchOptions and SearchGraph).
/// With `virtual_edges`, the search graph also has those edges (never loop closures for the
/// alias merge), and a path may step along them. Throws asf::Error for nodes that do not
/// exist.
PathSearchResult searchPaths(const PoseGraph& g, NodeId start, NodeId goal,
                             const PathSearchOptions& o = {},
                             const std::vector<VirtualEdge>* virtual_edges = nullptr);
/// searchPaths with method = all and add_shortest = false: every simple route of the search
/// graph (depth-first), expanded; with merge_radius = 0, every simple path of the graph.
PathSearchResult allSimplePaths(const PoseGraph& g, NodeId start, NodeId goal,
                                const PathSearchOptions& o = {});

/// The planners' common body: every candidate path evaluated under `c`, the cheapest
/// returned (ties, i.e. costs within o.tie_tolerance relative of the cheapest: the shortest
/// in metres, then fewer nodes, then the first found). Missing graph, marginals (for the
/// uncertainty criteria) or bad ids give found = false with a reason. `note` receives a
/// line about the cap or missing cross blocks, if any. With search.voronoi_edges and a map
/// in the request, the candidates include paths through the map's virtual edges (see
/// PathSearchOptions::voronoi_edges; the note says how many there were); without a map the
/// note says so and only the pose graph is searched.
PlanResult planBest(const PlanRequest& req, Criterion c, const CriterionOptions& o,
                    const PathSearchOptions& search, std::string* note = nullptr);

/// The planner plugins of this library (expected_uncertainty, mechanical_work, sum_dopt)
/// differ only in their criterion and key table: each is this class with its criterion.
/// configure() reads the criterion keys the table declares plus the search keys;
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
  std::string map_png;         ///< optional background (row 0 = top)
  double map_resolution = 0.05;
  double map_origin_x = 0, map_origin_y = 0;  ///< map frame of its lower-left corner
};
/// Draws the graph (metres, y up) with `path` highlighted to a PNG; throws asf::Error
/// naming the file when it cannot be written.
void renderPlan(const std::string& png, const PoseGraph& g, const Marginals* marginals,
                const std::vector<NodeId>& path, const RenderOptions& o);

}  // namespace asf::planning
