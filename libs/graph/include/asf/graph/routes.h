#pragma once
/// \file routes.h
/// Routes on a known graph (thesis ch. 5-6): Euler circuits/trails, the Chinese postman walk
/// (route inspection), the TSP walk (visit every node), and the on-line explorers Tarry,
/// modified Tarry (TIGRE's rule), Tremaux and DFS simulated on a known graph. Every route is a
/// Walk: nodes plus the edge index of each step (parallel edges are unambiguous), whose
/// per-edge traversal counts are the weights x_j of the information analysis.
///
/// Conventions: nodes are 0-based, edge lengths must be finite and >= 0 (InputError
/// otherwise); a route that does not exist (no Euler circuit, unreachable edges) throws
/// asf::Error with the reason. Seeds make the explorers deterministic: the same graph, start
/// and seed give the same walk on every platform (ties are drawn with std::mt19937, reduced
/// with a modulo, never through <random> distributions, whose output is implementation
/// defined).
#include <asf/graph/multigraph.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace asf::graph {

/// A walk: nodes[0] -> nodes[1] -> ... along edges[i] from nodes[i] to nodes[i+1].
/// A walk without steps is one node (nodes.size() == 1, edges empty).
struct Walk {
  std::vector<int> nodes;
  std::vector<int> edges;  ///< edges.size() == nodes.size() - 1 (indices into Multigraph::edges)
  double length = 0;       ///< sum of the lengths of the traversed edges

  int steps() const { return static_cast<int>(edges.size()); }
  bool closed() const { return !nodes.empty() && nodes.front() == nodes.back(); }
  /// How many times each of the graph's m edges is traversed (either direction): the weights
  /// x_j of L(x) = sum x_j E_j.
  std::vector<int> traversals(int m) const;
  std::vector<double> weights(int m) const;
};

/// Empty when `w` is a valid walk on `g` (node ids in range, nodes.size() == edges.size() + 1,
/// each edge joins its two consecutive nodes, length equal to the sum of edge lengths within
/// 1e-9 relative); otherwise a message saying what is wrong and at which step.
std::string walkError(const Multigraph& g, const Walk& w);
/// Every edge traversed at least once.
bool coversAllEdges(const Multigraph& g, const Walk& w);
/// Every node appears in the walk.
bool visitsAllNodes(const Multigraph& g, const Walk& w);

// ---------------------------------------------------------------------------------------------
// Euler (Hierholzer, O(m))

/// True when every edge lies in one connected component and every degree is even (self-loops
/// count twice). A graph without edges has a (trivial) circuit.
bool hasEulerCircuit(const Multigraph& g);
/// Closed walk from `start` traversing every edge exactly once. Throws Error naming the odd
/// vertices (1-based) or the edge not reachable from `start` when there is none.
Walk eulerCircuit(const Multigraph& g, int start = 0);
/// Walk traversing every edge exactly once, from `start` (-1: the lower odd vertex, or node
/// 0 / the first node with an edge when all degrees are even). With two odd vertices the walk
/// runs between them and `start` must be one of them; with none it is a circuit. Throws Error
/// otherwise.
Walk eulerTrail(const Multigraph& g, int start = -1);

// ---------------------------------------------------------------------------------------------
// Shortest paths

/// Dijkstra from `source`: dist (infinity when unreachable) and, for each node, the edge by
/// which the shortest path enters it (-1 for the source and unreachable nodes).
struct ShortestPaths {
  int source = 0;
  std::vector<double> dist;
  std::vector<int> pred_edge;
  /// The shortest walk source -> target (throws Error when unreachable).
  Walk walkTo(const Multigraph& g, int target) const;
};
ShortestPaths dijkstra(const Multigraph& g, int source);

// ---------------------------------------------------------------------------------------------
// Minimum-weight perfect matching on a complete graph (symmetric cost matrix, even size)

enum class MatchingMethod {
  Auto,        ///< bitmask DP up to 12 vertices (cheap, obviously exact), blossom above
  BitmaskDP,   ///< O(2^k k); refused above 24 vertices (memory)
  Blossom,     ///< Edmonds' weighted blossom, primal-dual, O(k^3)
};

/// mate[i] = partner of i; minimizes sum over pairs of cost[i][mate[i]]. `cost` must be square,
/// symmetric, of even size, finite and >= 0 (InputError otherwise). The blossom runs on integer
/// costs (scaled by a power of two so that the largest is about 2^40): exact for integer or
/// dyadic costs, and within 1e-11 of the optimum relative to the largest cost otherwise.
std::vector<int> minWeightPerfectMatching(const std::vector<std::vector<double>>& cost,
                                          MatchingMethod method = MatchingMethod::Auto);

// ---------------------------------------------------------------------------------------------
// Chinese postman (route inspection)

struct PostmanResult {
  Walk walk;
  std::vector<int> odd_vertices;  ///< vertices that had to be paired (0-based)
  std::vector<int> duplicates;    ///< per edge: extra traversals added (walk uses 1 + this)
  double edges_length = 0;        ///< sum of all edge lengths
  double added_length = 0;        ///< walk.length - edges_length
};

/// Shortest walk from `start` traversing every edge at least once; closed when end < 0 or
/// end == start, otherwise ending at `end` (open variant). Exact: shortest paths between the
/// vertices of wrong parity, a minimum-weight perfect matching of them, the matched paths'
/// edges duplicated, then an Euler circuit/trail. Nodes without edges are ignored, but `start`
/// and `end` must lie in the component of the edges (Error otherwise).
PostmanResult chinesePostman(const Multigraph& g, int start = 0, int end = -1,
                             MatchingMethod method = MatchingMethod::Auto);

// ---------------------------------------------------------------------------------------------
// TSP on a graph: shortest closed walk from `start` visiting every node

struct TspOptions {
  int exact_max_nodes = 16;  ///< Held-Karp up to this many nodes (O(2^n n^2), at most 20)
  int bound_iterations = 300;  ///< subgradient steps of the Held-Karp (1-tree) lower bound
  int kicks = 100;             ///< iterated local search: double-bridge kicks (n >= 8)
  bool certify = true;         ///< a heuristic tour meeting the lower bound counts as exact
  std::uint32_t seed = 0;      ///< for the kicks
};

struct TspResult {
  Walk walk;               ///< the tour expanded to edges of the graph (closed at start)
  std::vector<int> order;  ///< tour on the metric closure: order[0] == start, each node once
  double lower_bound = 0;  ///< == walk.length when exact
  bool exact = false;      ///< optimal: Held-Karp, or a tour that meets the lower bound
  std::string method;
};

/// The graph must be connected (Error otherwise). Distances are shortest paths (the metric
/// closure), so the walk may pass through nodes more than once. For n >= 3: the better of a
/// nearest-neighbour and a Christofides tour, each improved by 2-opt and Or-opt, then
/// iterated (double-bridge kicks) until it meets the Held-Karp bound or the kicks run out;
/// if it meets the bound it is optimal (with `certify`), otherwise Held-Karp runs when
/// n <= exact_max_nodes, and above that the heuristic tour is returned with the bound.
TspResult travelingSalesman(const Multigraph& g, int start = 0, const TspOptions& options = {});

/// Held-Karp (1-tree, subgradient ascent) lower bound on the shortest Hamiltonian cycle of the
/// complete graph with symmetric distances `dist` (n >= 3; n = 2: the cycle there and back).
/// `upper` (any tour's length) only sets the step sizes; the value is a valid bound whatever it
/// is, and is not capped by it.
double heldKarpLowerBound(const std::vector<std::vector<double>>& dist, double upper,
                          int iterations = 300);

// ---------------------------------------------------------------------------------------------
// On-line explorers simulated on a known graph. The explorer knows the edges incident to the
// nodes it has been at; the far end of an edge is known once that node has been visited (an
// edge to an unvisited node is a frontier edge in TIGRE's terms).

/// One edge the explorer may leave by, as Tarry's rule sees it (also what a TIGRE policy
/// builds from its topological graph).
struct TarryCandidate {
  int edge = -1;                  ///< caller's edge id (returned by tarryChoose)
  bool traversed_outward = false; ///< already left the current node by this edge
  bool entrance = false;          ///< the edge of first arrival at the current node
  bool leads_to_visited = false;  ///< the far end is a visited node (a loop-closing link)
  double cost = 0;                ///< e.g. edge length or distance to its goal
};

struct TarryOptions {
  bool loop_closing_first = false;  ///< prefer edges to visited nodes over frontier edges
  bool nearest_first = false;       ///< then prefer the least cost
  bool stop_when_covered = false;   ///< Fraenkel-style: stop once no edge is untraversed
  /// TIGRE's rule (thesis sec. 6.2): all three on.
  static TarryOptions modified() { return {true, true, true}; }
};

/// Tarry's rule: among the candidates not traversed outward and not the entrance edge (after
/// the preferences of `options`, ties drawn with `rng`), return one's `edge`; the entrance edge
/// only when nothing else is left (and not yet traversed outward); -1 when nothing is allowed
/// (the walk is over: at the start node every edge has been traversed both ways).
int tarryChoose(const std::vector<TarryCandidate>& candidates, const TarryOptions& options,
                std::mt19937& rng);

struct ExploreResult {
  Walk walk;
  bool covered_all_edges = false;
  bool visited_all_nodes = false;
  /// Step at which every edge had been traversed (-1: never) and at which every node had been
  /// visited: an explorer that knew it was done could have stopped there.
  int steps_to_cover_edges = -1;
  int steps_to_visit_nodes = -1;
};

/// Tarry's walk from `start`: never leaves a node twice by the same edge, the entrance edge
/// last. Without stop_when_covered it ends at `start` with every edge traversed exactly once
/// in each direction (graph connected); with it, it stops as soon as every edge has been
/// traversed (between the open Chinese postman length and twice the total length).
ExploreResult tarry(const Multigraph& g, int start, const TarryOptions& options,
                    std::uint32_t seed);
/// Tremaux: like Tarry, but arriving at an already visited node through a new edge it turns
/// back at once; ends at `start`, every edge traversed exactly twice (once each way).
/// Ties among unmarked edges are drawn with the seed.
ExploreResult tremaux(const Multigraph& g, int start, std::uint32_t seed);
/// Depth-first search as an explorer sees it (node exploration: it sees where incident edges
/// lead): go to an unvisited neighbour (ties drawn with the seed), otherwise back along the
/// edge of first arrival; ends at `start` having walked the DFS tree twice. Covers every
/// node, not every edge.
ExploreResult dfsExplore(const Multigraph& g, int start, std::uint32_t seed);

// ---------------------------------------------------------------------------------------------
// One entry point for commands and experiments

enum class RouteAlgorithm { Euler, ChinesePostman, Tsp, Tarry, TarryModified, Tremaux, Dfs };

/// "euler", "cpp", "tsp", "tarry", "tarry_modified", "tremaux", "dfs" (InputError otherwise,
/// listing them).
RouteAlgorithm parseRouteAlgorithm(const std::string& name);
std::string routeAlgorithmName(RouteAlgorithm a);

struct RouteResult {
  RouteAlgorithm algorithm = RouteAlgorithm::Euler;
  Walk walk;
  bool covered_all_edges = false;
  bool visited_all_nodes = false;
  double lower_bound = -1;  ///< TSP: the lower bound; CPP: the walk length (exact); else -1
  bool exact = false;       ///< the walk is optimal for its problem (Euler, CPP, exact TSP)
  /// Steps after which every edge / every node had been reached (-1: never).
  int steps_to_cover_edges = -1;
  int steps_to_visit_nodes = -1;
};

/// Runs `algorithm` from `start` (`end` only for euler and cpp: -1 closed). Errors as the
/// individual functions.
RouteResult computeRoute(const Multigraph& g, RouteAlgorithm algorithm, int start,
                         std::uint32_t seed = 0, int end = -1);

}  // namespace asf::graph
