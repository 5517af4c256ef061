#pragma once
/// \file plan_query.h
/// The protocol of `asf plan` (thesis chapter 3) as a library function: on a pose graph taken
/// as optimized, the back-end recovers the node marginals and the cross-covariances the
/// candidate paths need, the planner plans, and the chosen path is scored under every
/// criterion; with Voronoi virtual edges, the thesis' Table 3.2 comparison; the check of
/// Algorithm 1's merged hypotheses against the enumeration of every relocalization sequence.
#include <asf/backend.h>
#include <asf/planning/expected_uncertainty.h>
#include <asf/planner.h>
#include <asf/planning/voronoi_graph.h>

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace asf::studies {

struct PlanQuery {
  NodeId start = 0, goal = 0;
  const GridMap* map = nullptr;  ///< handed to the planner; needed for virtual edges
  /// Cross-covariances are requested only if the candidate paths need at most this many.
  std::size_t max_cross = 2000000;
};

/// One of the two alternatives of thesis Table 3.2.
struct PathAlternative {
  std::vector<NodeId> path;
  double distance = 0, expected_uncertainty = 0, cost = 0;  ///< cost = distance * det E[C]
  std::size_t virtual_steps = 0;
};

struct PlanQueryResult {
  PlanResult plan;  ///< the planner's answer; nothing below is filled when not found
  planning::PathSearchResult candidates;
  std::vector<planning::VirtualEdge> virtual_edges;  ///< the planner's voronoi_edges = true only
  Marginals marginals;
  std::size_t cross_blocks = 0;  ///< cross-covariance blocks requested
  bool cross_skipped = false;    ///< more than max_cross needed: node marginals only
  planning::PathModel model;               ///< of the chosen path
  planning::CriterionOptions criterion_options;
  std::vector<std::pair<NodeId, NodeId>> virtual_steps;  ///< of the chosen path
  std::map<std::string, planning::PathCost> costs;  ///< the chosen path under every criterion, by name
  /// Thesis Table 3.2 (voronoi_edges only): the cheapest candidate along the graph and the
  /// shortest through unexplored space; empty when there is no such candidate.
  std::optional<PathAlternative> along_graph, through_unexplored;
  double voronoi_s = 0, search_s = 0, marginals_s = 0, plan_s = 0;
  std::string note;  ///< capped search, fallback, missing cross-covariances
};

/// Runs the protocol with a configured planner and back-end; `planner_params` are the
/// planner's (its search keys and criterion options are used where it has them) and `seed`
/// the one it was configured with. Throws ConfigError when voronoi_edges is set without a map.
PlanQueryResult planOnGraph(const PoseGraph& g, Planner& planner, const Params& planner_params,
                            std::uint64_t seed, Backend& backend, const PlanQuery& q);

/// Thesis Table 3.2 over candidate paths (see PlanQueryResult::along_graph).
void comparePaths(const PoseGraph& g, const Marginals& marginals,
                  const std::vector<std::vector<NodeId>>& paths,
                  const std::vector<planning::VirtualEdge>& virtual_edges, const planning::CriterionOptions& copt,
                  std::optional<PathAlternative>& along_graph,
                  std::optional<PathAlternative>& through_unexplored);

/// Thesis Figs. 3.1-3.2 on a path: Algorithm 1 keeps one hypothesis per step of the last
/// relocalization (m + 1, O(m^2) evaluations of the relocalization probability) where the
/// relocalization sequences are 2^m; checked against the enumeration of every sequence on
/// the window of `window` steps where E[C] is most often a mixture, at the end of each of
/// its prefixes.
struct HypothesisCheck {
  std::size_t steps = 0, hypotheses = 0, evaluations = 0;
  double sequences = 0;  ///< 2^steps
  std::size_t checked_from_step = 0, checked_steps = 0, checked_mixed_prefixes = 0;
  double checked_sequences = 0;
  double relative_difference = 0;  ///< worst ||merged - enumerated|| / ||enumerated||
};
HypothesisCheck checkHypotheses(const planning::PathModel& model, const planning::CriterionOptions& o,
                                std::size_t window = 16);

}  // namespace asf::studies
