#include <asf/errors.h>
#include <asf/studies/plan_query.h>
#include <asf/text.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <set>

namespace asf::studies {

namespace {

using Clock = std::chrono::steady_clock;

/// Steps first+1 .. first+steps of a path model, as a path of its own from n_first.
planning::PathModel slice(const planning::PathModel& m, std::size_t first, std::size_t steps) {
  planning::PathModel p = m;
  const std::size_t end = std::min(m.nodes.size(), first + steps + 1);
  auto cut = [&](auto& v) {
    if (v.size() >= end) v = std::vector(v.begin() + first, v.begin() + end);
  };
  cut(p.nodes);
  cut(p.pose);
  cut(p.sigma);
  cut(p.motion);
  cut(p.motion_cov);
  cut(p.virtual_step);
  cut(p.virtual_length);
  return p;
}

/// The relocalization probability of `path`, each (k, t) query asked once: the oracle asks
/// the same ones many times, and a query's covariances depend on k and t only.
planning::RelocProbFn memoized(const planning::PathModel& path, const planning::RelocalizationOptions& o) {
  auto memo = std::make_shared<std::map<std::pair<std::size_t, std::size_t>, double>>();
  return [p = planning::relocalizationProbability(path, o), memo](const planning::RelocQuery& q) {
    const auto key = std::make_pair(q.k, q.t);
    const auto it = memo->find(key);
    return it != memo->end() ? it->second : (*memo)[key] = p(q);
  };
}

/// Prefixes of `w` (1..all its steps) whose merged hypotheses keep more than one with mass:
/// where E[C] is a mixture, not one covariance.
std::size_t mixedPrefixes(const planning::PathModel& w, const planning::RelocProbFn& p) {
  std::size_t n = 0;
  for (std::size_t len = 1; len <= w.steps(); ++len) {
    const auto r = planning::expectedCovariance(slice(w, 0, len), p);
    n += *std::max_element(r.prob.begin(), r.prob.end()) < 1 - 1e-9;
  }
  return n;
}

/// The node pairs of the candidate paths, for their cross-covariances; empty with `skipped`
/// set when there are more than `max`.
std::vector<std::pair<NodeId, NodeId>> crossPairs(const std::vector<std::vector<NodeId>>& paths,
                                                  std::size_t max, bool& skipped) {
  std::set<std::pair<NodeId, NodeId>> pairs;
  skipped = false;
  for (const auto& p : paths) {
    for (std::size_t a = 0; a < p.size() && !skipped; ++a)
      for (std::size_t b = a + 1; b < p.size(); ++b) {
        pairs.emplace(std::min(p[a], p[b]), std::max(p[a], p[b]));
        if (pairs.size() > max) {
          skipped = true;
          break;
        }
      }
    if (skipped) break;
  }
  if (skipped) return {};
  return {pairs.begin(), pairs.end()};
}

/// The chosen path under every criterion, and what limited the answer.
void scoreChosenPath(const PoseGraph& g, const planning::PathSearchOptions& search, PlanQueryResult& r) {
  r.model = planning::makePathModel(g, &r.marginals, r.plan.nodes, &r.virtual_edges);
  for (std::size_t i = 1; i < r.plan.nodes.size(); ++i)
    if (r.model.isVirtual(i)) r.virtual_steps.emplace_back(r.plan.nodes[i - 1], r.plan.nodes[i]);
  for (auto c : {planning::Criterion::ExpectedUncertainty, planning::Criterion::MechanicalWork, planning::Criterion::SumDopt,
                 planning::Criterion::Distance})
    r.costs[planning::criterionName(c)] = planning::evaluatePath(c, r.model, r.criterion_options);
  if (search.voronoi_edges)
    comparePaths(g, r.marginals, r.candidates.paths, r.virtual_edges, r.criterion_options,
                 r.along_graph, r.through_unexplored);
  if (r.candidates.capped)
    r.note += "path search capped at " + std::to_string(search.max_paths) + " paths. ";
  if (r.candidates.fell_back)
    r.note += "enumeration given up past " + std::to_string(search.max_paths) +
              " simple routes: Yen's " + std::to_string(search.k_paths) +
              " shortest and the penalty method's routes evaluated. ";
  const std::size_t missing = r.costs[planning::criterionName(planning::Criterion::ExpectedUncertainty)].missing_cross;
  if (missing)
    r.note += std::to_string(missing) +
              " relocalization queries on the chosen path lacked a cross-covariance block.";
}

}  // namespace

PlanQueryResult planOnGraph(const PoseGraph& g, Planner& planner, const Params& planner_params,
                            std::uint64_t seed, Backend& backend, const PlanQuery& q) {
  PlanQueryResult r;
  // The candidate paths as the planner sees them (its own search keys when it has them),
  // to request the cross-covariance blocks its relocalization probability reads.
  const planning::PathSearchOptions search = planning::pathSearchOptionsFrom(planner_params);
  if (search.voronoi_edges) {
    if (!q.map || !q.map->grid)
      throw ConfigError("planner key voronoi_edges=true needs --map MAP.png (the occupancy map)");
    // Partially explored map: the planner's virtual edges (the same computation it makes).
    const auto tv = Clock::now();
    r.virtual_edges = planning::computeVirtualEdges(g, *q.map, search.voronoi).edges;
    r.voronoi_s = secondsSince(tv);
  }
  auto t0 = Clock::now();
  r.candidates = planning::searchPaths(g, q.start, q.goal, search, &r.virtual_edges);
  r.search_s = secondsSince(t0);
  const auto pairs = crossPairs(r.candidates.paths, q.max_cross, r.cross_skipped);
  r.cross_blocks = pairs.size();
  t0 = Clock::now();
  r.marginals = backend.marginals(g, pairs);
  r.marginals_s = secondsSince(t0);

  PlanRequest req;
  req.graph = &g;
  req.marginals = &r.marginals;
  req.map = q.map && q.map->grid ? q.map : nullptr;
  req.start = q.start;
  req.goal = q.goal;
  t0 = Clock::now();
  r.plan = planner.plan(req);
  r.plan_s = secondsSince(t0);
  if (!r.plan.found) return r;
  // With the planner's options where it has them.
  r.criterion_options = planning::criterionOptionsFrom(planner_params, seed);
  scoreChosenPath(g, search, r);
  return r;
}

void comparePaths(const PoseGraph& g, const Marginals& marginals,
                  const std::vector<std::vector<NodeId>>& paths,
                  const std::vector<planning::VirtualEdge>& virtual_edges, const planning::CriterionOptions& copt,
                  std::optional<PathAlternative>& along_graph,
                  std::optional<PathAlternative>& through_unexplored) {
  // Along the graph, the cheapest candidate without a virtual step (the planner's choice
  // without virtual edges); through unexplored space, the shortest candidate with one (the
  // shortcut the GVG offers; the cheapest of equally short ones).
  for (const auto& p : paths) {
    const planning::PathModel model = planning::makePathModel(g, &marginals, p, &virtual_edges);
    PathAlternative a;
    for (std::size_t i = 1; i < p.size(); ++i) a.virtual_steps += model.isVirtual(i);
    a.distance = planning::pathLength(model);
    a.expected_uncertainty = planning::evaluatePath(planning::Criterion::ExpectedUncertainty, model, copt).cost;
    a.cost = a.distance * a.expected_uncertainty;
    auto& slot = a.virtual_steps ? through_unexplored : along_graph;
    if (slot) {
      const bool better =
          a.virtual_steps
              ? a.distance < slot->distance || (a.distance == slot->distance && a.cost < slot->cost)
              : a.cost < slot->cost;
      if (!better) continue;
    }
    a.path = p;
    slot = a;
  }
}

HypothesisCheck checkHypotheses(const planning::PathModel& model, const planning::CriterionOptions& o,
                                std::size_t window) {
  HypothesisCheck h;
  const std::size_t m = model.steps();
  const auto merged = planning::expectedCovariance(model, planning::relocalizationProbability(model, o.reloc));
  h.steps = m;
  h.sequences = std::pow(2.0, static_cast<double>(m));
  h.hypotheses = merged.prob.size();
  h.evaluations = merged.evaluations;
  const std::size_t len = std::min(window, m);
  std::size_t first = 0, mixed = 0;
  for (std::size_t a = 0; a + len <= m && len > 0; ++a) {
    const planning::PathModel w = slice(model, a, len);
    const std::size_t k = mixedPrefixes(w, memoized(w, o.reloc));
    if (k > mixed) first = a, mixed = k;
  }
  const planning::PathModel w = slice(model, first, len);
  const planning::RelocProbFn p = memoized(w, o.reloc);
  double worst = 0;
  for (std::size_t l = 1; l <= len; ++l) {
    const planning::PathModel part = slice(w, 0, l);
    const Eigen::Matrix3d a = planning::expectedCovariance(part, p).mean;
    const Eigen::Matrix3d b = planning::expectedCovarianceBruteForce(part, p);
    worst = std::max(worst, (a - b).norm() / std::max(b.norm(), 1e-300));
  }
  h.checked_from_step = first;
  h.checked_steps = len;
  h.checked_sequences = std::pow(2.0, static_cast<double>(len));
  h.checked_mixed_prefixes = mixed;
  h.relative_difference = worst;
  return h;
}

}  // namespace asf::studies
