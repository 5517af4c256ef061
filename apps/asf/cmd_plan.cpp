// asf plan: one planner on one g2o pose graph (thesis chapter 3). The graph is taken as
// optimized; the back-end only recovers the marginals (and the cross-covariances the
// relocalization probability needs), then the chosen path is scored under every criterion.
#include <asf/backend.h>
#include <asf/config.h>
#include <asf/errors.h>
#include <asf/expected_uncertainty.h>
#include <asf/occupancy_io.h>
#include <asf/planner.h>
#include <asf/pose_graph.h>
#include <asf/registry.h>
#include <asf/segmentation_eval.h>
#include <asf/voronoi_graph.h>
#include <tclap/CmdLine.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>

#include "commands.h"
#include "plugin_cli.h"

namespace asf::app {

namespace {

std::string joinPath(const std::vector<NodeId>& p) {
  std::string s;
  for (std::size_t i = 0; i < p.size(); ++i) s += (i ? " " : "") + std::to_string(p[i]);
  return s;
}

/// Steps first+1 .. first+steps of a path model, as a path of its own from n_first.
eu::PathModel slice(const eu::PathModel& m, std::size_t first, std::size_t steps) {
  eu::PathModel p = m;
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
eu::RelocProbFn memoized(const eu::PathModel& path, const eu::RelocalizationOptions& o) {
  auto memo = std::make_shared<std::map<std::pair<std::size_t, std::size_t>, double>>();
  return [p = eu::relocalizationProbability(path, o), memo](const eu::RelocQuery& q) {
    const auto key = std::make_pair(q.k, q.t);
    const auto it = memo->find(key);
    return it != memo->end() ? it->second : (*memo)[key] = p(q);
  };
}

/// Prefixes of `w` (1..all its steps) whose merged hypotheses keep more than one with mass:
/// where E[C] is a mixture, not one covariance.
std::size_t mixedPrefixes(const eu::PathModel& w, const eu::RelocProbFn& p) {
  std::size_t n = 0;
  for (std::size_t len = 1; len <= w.steps(); ++len) {
    const auto r = eu::expectedCovariance(slice(w, 0, len), p);
    n += *std::max_element(r.prob.begin(), r.prob.end()) < 1 - 1e-9;
  }
  return n;
}

/// Thesis Figs. 3.1-3.2 on the chosen path: Algorithm 1 keeps one hypothesis per step of the
/// last relocalization (m + 1 of them, O(m^2) evaluations of the relocalization probability)
/// where the relocalization sequences are 2^m. Checked against the enumeration of every
/// sequence (the oracle) on the window of `window` steps of the path where E[C] is most
/// often a mixture, at the end of each of its prefixes.
nlohmann::json hypothesisCheck(const eu::PathModel& model, const eu::CriterionOptions& o,
                               std::size_t window = 16) {
  const std::size_t m = model.steps();
  const auto merged = eu::expectedCovariance(model, eu::relocalizationProbability(model, o.reloc));
  nlohmann::json j{{"steps", m},
                   {"sequences", std::pow(2.0, static_cast<double>(m))},
                   {"hypotheses", merged.prob.size()},
                   {"evaluations", merged.evaluations}};
  const std::size_t len = std::min(window, m);
  std::size_t first = 0, mixed = 0;
  for (std::size_t a = 0; a + len <= m && len > 0; ++a) {
    const eu::PathModel w = slice(model, a, len);
    const std::size_t k = mixedPrefixes(w, memoized(w, o.reloc));
    if (k > mixed) first = a, mixed = k;
  }
  const eu::PathModel w = slice(model, first, len);
  const eu::RelocProbFn p = memoized(w, o.reloc);
  double worst = 0;
  for (std::size_t l = 1; l <= len; ++l) {
    const eu::PathModel part = slice(w, 0, l);
    const Eigen::Matrix3d a = eu::expectedCovariance(part, p).mean;
    const Eigen::Matrix3d b = eu::expectedCovarianceBruteForce(part, p);
    worst = std::max(worst, (a - b).norm() / std::max(b.norm(), 1e-300));
  }
  j["checked_from_step"] = first;
  j["checked_steps"] = len;
  j["checked_sequences"] = std::pow(2.0, static_cast<double>(len));
  j["checked_mixed_prefixes"] = mixed;
  j["relative_difference"] = worst;
  return j;
}

}  // namespace

/// Thesis Table 3.2: the two alternatives of a partially explored map, each with its length,
/// det E[C] and their product (eq. 3.25): along the graph, the cheapest candidate without a
/// virtual step (the planner's choice without virtual edges); through unexplored space, the
/// shortest candidate with one (the shortcut the GVG offers; the cheapest of equally short
/// ones). Null for a kind without candidates.
nlohmann::json pathComparison(const PoseGraph& g, const Marginals& marginals,
                              const std::vector<std::vector<NodeId>>& paths,
                              const std::vector<gvg::VirtualEdge>& virtual_edges,
                              const eu::CriterionOptions& copt) {
  nlohmann::json best{{"graph", nullptr}, {"unexplored", nullptr}};
  for (const auto& p : paths) {
    const eu::PathModel model = eu::makePathModel(g, &marginals, p, &virtual_edges);
    std::size_t steps = 0;
    for (std::size_t i = 1; i < p.size(); ++i) steps += model.isVirtual(i);
    const double distance = eu::pathLength(model);
    const double det = eu::evaluatePath(eu::Criterion::ExpectedUncertainty, model, copt).cost;
    auto& slot = best[steps ? "unexplored" : "graph"];
    if (!slot.is_null()) {
      const double d0 = slot["distance"].get<double>(), c0 = slot["cost"].get<double>();
      const bool better =
          steps ? distance < d0 || (distance == d0 && distance * det < c0) : distance * det < c0;
      if (!better) continue;
    }
    slot = {{"path", p},
            {"distance", distance},
            {"expected_uncertainty", det},
            {"cost", distance * det},
            {"virtual_steps", steps}};
  }
  return best;
}

int cmdPlan(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Plans a path between two nodes of a 2D pose graph (g2o; taken as already optimized) "
      "with a planner plugin: expected_uncertainty (thesis ch. 3), mechanical_work, sum_dopt, "
      "shortest. The back-end recovers the node marginals and the cross-covariances between "
      "nodes of the candidate paths. Prints the path and its cost under every criterion "
      "(expected_uncertainty, mechanical_work, sum_dopt, distance); --image draws it.",
      ' ', ASF_VERSION_STRING);
  TCLAP::ValueArg<std::string> graph("g", "graph", "The pose graph (g2o)", true, "", "FILE.g2o",
                                     cmd);
  // Signed: an unsigned argument would read -1 as 4294967295.
  TCLAP::ValueArg<long long> start("", "start", "Start node id", true, 0, "ID", cmd);
  TCLAP::ValueArg<long long> goal("", "goal", "Goal node id", true, 0, "ID", cmd);
  TCLAP::ValueArg<std::string> planner("", "planner", "Planner plugin name", false,
                                       "expected_uncertainty", "NAME", cmd);
  TCLAP::MultiArg<std::string> set("s", "set",
                                   "Planner key: key=value or <planner>.key=value (repeatable)",
                                   false, "KEY=VALUE", cmd);
  TCLAP::ValueArg<std::string> backend("b", "backend", "Back-end recovering the marginals", false,
                                       "sparse_lm", "NAME", cmd);
  TCLAP::ValueArg<std::uint64_t> seed("", "seed", "Seed handed to the planner", false, 1, "N", cmd);
  TCLAP::ValueArg<std::size_t> max_cross(
      "", "max-cross",
      "Request cross-covariances only if the candidate paths need at most this many blocks", false,
      2000000, "N", cmd);
  TCLAP::SwitchArg json("j", "json",
                        "Print one JSON object: path, cost, criterion, costs (every "
                        "criterion), expected_covariance, candidates, capped, timings, note",
                        cmd);
  TCLAP::ValueArg<std::string> image("", "image", "Draw the graph and the path (PNG)", false, "",
                                     "OUT.png", cmd);
  TCLAP::SwitchArg ellipses("", "ellipses", "With --image: 3-sigma marginal ellipses", cmd);
  TCLAP::ValueArg<std::string> map(
      "", "map",
      "Occupancy map: a map_server YAML (e.g. a run's occupancy.yaml: resolution, origin and "
      "thresholds from it), or an image (row 0 = top, origin (0, 0), pixels >= 250 free, "
      "the rest occupied, --resolution); handed to the planner (voronoi_edges) and drawn "
      "under --image",
      false, "", "MAP.yaml|MAP.png", cmd);
  TCLAP::SwitchArg voronoi(
      "", "voronoi",
      "Partially explored map: set the planner's voronoi_edges=true (needs --map): virtual "
      "edges of the map's generalized Voronoi graph join nodes the pose graph does not",
      cmd);
  TCLAP::ValueArg<double> resolution("", "resolution", "Map resolution [m/pixel]", false, 0.05, "R",
                                     cmd);
  TCLAP::MultiArg<std::string> path("p", "plugin-path", "Extra plugin folder (repeatable)", false,
                                    "DIR", cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);

  Registry reg;
  scanPlugins(reg, path.getValue());
  const auto pinfo = reg.find(planner.getValue(), PluginKind::Planner);
  const auto binfo = reg.find(backend.getValue(), PluginKind::Backend);
  std::vector<std::string> overrides = set.getValue();
  if (voronoi.getValue()) {
    if (map.getValue().empty()) throw ConfigError("--voronoi needs --map MAP.png");
    bool declared = false;
    for (std::size_t i = 0; i < pinfo->descriptor->num_keys; ++i)
      if (std::string(pinfo->descriptor->keys[i].name) == "voronoi_edges") declared = true;
    if (!declared)
      throw ConfigError("--voronoi: planner " + pinfo->name() +
                        " has no voronoi_edges key (criterion planners: expected_uncertainty, "
                        "mechanical_work, sum_dopt)");
    overrides.push_back("voronoi_edges=true");
  }
  if (!(resolution.getValue() > 0)) throw ConfigError("--resolution must be > 0");
  const Params pparams =
      setOverrides(overrides, pinfo->name(), "planner")
          .resolve(pinfo->name(), pinfo->descriptor->keys, pinfo->descriptor->num_keys);
  const Params bparams =
      Params::fromSpecs(binfo->name(), binfo->descriptor->keys, binfo->descriptor->num_keys);
  PluginContext ctx;
  ctx.seed = seed.getValue();
  auto pl = Registry::create<Planner>(pinfo);
  logToStderr(*pl, pinfo->name());
  pl->configure(pparams, ctx);
  auto be = Registry::create<Backend>(binfo);
  logToStderr(*be, binfo->name());
  be->configure(bparams, PluginContext{});

  const PoseGraph g = readG2o(graph.getValue());
  for (long long v : {start.getValue(), goal.getValue()})
    if (v < 0 || static_cast<unsigned long long>(v) >= g.size())
      throw InputError(graph.getValue() + ": node " + std::to_string(v) +
                       " does not exist (the graph has " + std::to_string(g.size()) +
                       " nodes, numbered from 0)");
  const NodeId s = static_cast<NodeId>(start.getValue()), t = static_cast<NodeId>(goal.getValue());

  // The candidate paths as the planner sees them (its own search keys when it has them),
  // to request the cross-covariance blocks its relocalization probability reads.
  const eu::PathSearchOptions search = eu::pathSearchOptionsFrom(pparams);
  GridMap grid;
  const bool yaml =
      map.getValue().size() > 5 && (map.getValue().substr(map.getValue().size() - 5) == ".yaml" ||
                                    map.getValue().substr(map.getValue().size() - 4) == ".yml");
  if (yaml)
    grid = readOccupancyMap(map.getValue());
  else if (!map.getValue().empty())
    grid = gridFromImage(readGrayImage(map.getValue()), resolution.getValue());
  // Partially explored map: the planner's virtual edges (the same computation it makes).
  std::vector<gvg::VirtualEdge> virtual_edges;
  double voronoi_s = 0;
  if (search.voronoi_edges) {
    if (!grid.grid)
      throw ConfigError("planner key voronoi_edges=true needs --map MAP.png (the occupancy map)");
    const auto tv = std::chrono::steady_clock::now();
    virtual_edges = gvg::computeVirtualEdges(g, grid, search.voronoi).edges;
    voronoi_s = secondsSince(tv);
  }
  const auto t_search = std::chrono::steady_clock::now();
  const eu::PathSearchResult candidates = eu::searchPaths(g, s, t, search, &virtual_edges);
  const double search_s = secondsSince(t_search);
  std::set<std::pair<NodeId, NodeId>> pairs;
  bool cross_skipped = false;
  for (const auto& p : candidates.paths) {
    for (std::size_t a = 0; a < p.size() && !cross_skipped; ++a)
      for (std::size_t b = a + 1; b < p.size(); ++b) {
        pairs.emplace(std::min(p[a], p[b]), std::max(p[a], p[b]));
        if (pairs.size() > max_cross.getValue()) {
          cross_skipped = true;
          break;
        }
      }
    if (cross_skipped) break;
  }
  if (cross_skipped) {
    std::cerr << "asf plan: the candidate paths need more than " << max_cross.getValue()
              << " cross-covariance blocks (--max-cross); node marginals only\n";
    pairs.clear();
  }
  auto t0 = std::chrono::steady_clock::now();
  const Marginals marginals =
      be->marginals(g, std::vector<std::pair<NodeId, NodeId>>(pairs.begin(), pairs.end()));
  const double marginals_s = secondsSince(t0);

  PlanRequest req;
  req.graph = &g;
  req.marginals = &marginals;
  if (grid.grid) req.map = &grid;
  req.start = s;
  req.goal = t;
  t0 = std::chrono::steady_clock::now();
  const PlanResult r = pl->plan(req);
  const double plan_s = secondsSince(t0);
  if (!r.found)
    throw Error(pinfo->name() + ": no path from " + std::to_string(s) + " to " + std::to_string(t) +
                ": " + r.reason);

  // The chosen path under every criterion, with the planner's options where it has them.
  const eu::CriterionOptions copt = eu::criterionOptionsFrom(pparams, ctx.seed);
  const eu::PathModel model = eu::makePathModel(g, &marginals, r.nodes, &virtual_edges);
  std::vector<std::pair<NodeId, NodeId>> virtual_steps;
  for (std::size_t i = 1; i < r.nodes.size(); ++i)
    if (model.isVirtual(i)) virtual_steps.emplace_back(r.nodes[i - 1], r.nodes[i]);
  nlohmann::json costs = nlohmann::json::object();
  nlohmann::json labels = nlohmann::json::object();
  eu::PathCost expected;
  for (auto c : {eu::Criterion::ExpectedUncertainty, eu::Criterion::MechanicalWork,
                 eu::Criterion::SumDopt, eu::Criterion::Distance}) {
    const eu::PathCost pc = eu::evaluatePath(c, model, copt);
    costs[eu::criterionName(c)] = pc.cost;
    labels[eu::criterionName(c)] = pc.label;
    if (c == eu::Criterion::ExpectedUncertainty) expected = pc;
  }
  const nlohmann::json comparison =
      search.voronoi_edges ? pathComparison(g, marginals, candidates.paths, virtual_edges, copt)
                           : nlohmann::json(nullptr);
  std::string note;
  if (candidates.capped)
    note += "path search capped at " + std::to_string(search.max_paths) + " paths. ";
  if (candidates.fell_back)
    note += "enumeration given up past " + std::to_string(search.max_paths) +
            " simple routes: Yen's " + std::to_string(search.k_paths) +
            " shortest and the penalty method's routes evaluated. ";
  if (expected.missing_cross)
    note += std::to_string(expected.missing_cross) +
            " relocalization queries on the chosen path lacked a cross-covariance block.";

  if (!image.getValue().empty()) {
    eu::RenderOptions ro;
    ro.ellipses = ellipses.getValue();
    ro.map_png = map.getValue();
    ro.map_resolution = resolution.getValue();
    if (yaml) {  // the YAML's image, in the YAML's frame
      const OccupancyMapInfo info = readOccupancyYaml(map.getValue());
      ro.map_png = (std::filesystem::path(map.getValue()).parent_path() / info.image).string();
      ro.map_resolution = info.resolution;
      ro.map_origin_x = info.origin_x;
      ro.map_origin_y = info.origin_y;
    }
    eu::renderPlan(image.getValue(), g, &marginals, r.nodes, ro);
  }

  if (json.getValue()) {
    nlohmann::json ec = nlohmann::json::array();
    for (int i = 0; i < 3; ++i)
      ec.push_back({expected.expected(i, 0), expected.expected(i, 1), expected.expected(i, 2)});
    nlohmann::json j = {{"graph", graph.getValue()},
                        {"planner", pinfo->name()},
                        {"start", s},
                        {"goal", t},
                        {"path", r.nodes},
                        {"cost", r.cost},
                        {"criterion", r.criterion},
                        {"costs", costs},
                        {"labels", labels},
                        {"expected_covariance", ec},
                        {"candidates", candidates.paths.size()},
                        {"capped", candidates.capped},
                        {"search", eu::searchMethodName(candidates.method)},
                        {"fell_back", candidates.fell_back},
                        {"merged_vertices", candidates.merged_vertices},
                        {"reduced_nodes", candidates.reduced_nodes},
                        {"reduced_edges", candidates.reduced_edges},
                        {"cross_blocks", pairs.size()},
                        {"voronoi_edges", search.voronoi_edges},
                        {"virtual_edges", virtual_edges.size()},
                        {"virtual_steps", virtual_steps},
                        {"comparison", comparison},
                        {"voronoi_time_s", voronoi_s},
                        {"search_time_s", search_s},
                        {"marginals_time_s", marginals_s},
                        {"plan_time_s", plan_s},
                        {"hypotheses", hypothesisCheck(model, copt)},
                        {"note", note}};
    if (!image.getValue().empty()) j["image"] = image.getValue();
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << std::setprecision(6) << graph.getValue() << ": " << g.size() << " nodes, "
              << g.edges.size() << " edges; " << candidates.paths.size() << " candidate paths ("
              << eu::searchMethodName(candidates.method) << "; search graph "
              << candidates.reduced_nodes << " vertices, " << candidates.reduced_edges << " edges, "
              << candidates.merged_vertices << " merged aliases"
              << (candidates.capped ? ", capped" : "") << ")\n"
              << pinfo->name() << ": " << r.nodes.size() << " nodes: " << joinPath(r.nodes)
              << "\n  " << r.criterion << " = " << r.cost << " (plan " << plan_s << " s, marginals "
              << marginals_s << " s)\n";
    for (const auto& [k, v] : costs.items())
      std::cout << "  " << std::left << std::setw(22) << k << labels[k].get<std::string>() << " = "
                << v.get<double>() << "\n";
    if (search.voronoi_edges) {
      std::cout << "  voronoi: " << virtual_edges.size() << " virtual edges (" << voronoi_s
                << " s); the path takes " << virtual_steps.size() << ":";
      for (const auto& [a, b] : virtual_steps) std::cout << " " << a << "-" << b;
      std::cout << "\n  thesis Table 3.2: distance [m], det(E[C]), product -- the best path along "
                   "the graph, the shortest through unexplored space\n";
      for (const char* kind : {"graph", "unexplored"}) {
        const auto& c = comparison[kind];
        std::cout << "    " << std::left << std::setw(11) << kind;
        if (c.is_null())
          std::cout << "no candidate\n";
        else
          std::cout << c["distance"].get<double>() << "  "
                    << c["expected_uncertainty"].get<double>() << "  " << c["cost"].get<double>()
                    << "\n";
      }
    }
    if (!note.empty()) std::cout << "note: " << note << "\n";
    if (!image.getValue().empty()) std::cout << "wrote " << image.getValue() << "\n";
  }
  return kOk;
}

}  // namespace asf::app
