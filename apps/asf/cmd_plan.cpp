// asf plan: one planner on one g2o pose graph (thesis chapter 3). The graph is taken as
// optimized; the back-end only recovers the marginals (and the cross-covariances the
// relocalization probability needs), then the chosen path is scored under every criterion
// (asf/studies/plan_query.h holds the protocol; this file parses arguments and prints).
#include <asf/backend.h>
#include <asf/config.h>
#include <asf/errors.h>
#include <asf/planning/expected_uncertainty.h>
#include <asf/io/occupancy_io.h>
#include <asf/studies/plan_query.h>
#include <asf/planner.h>
#include <asf/pose_graph.h>
#include <asf/framework/registry.h>
#include <asf/evaluation/segmentation_eval.h>
#include <tclap/CmdLine.h>

#include <filesystem>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "plugin_cli.h"

namespace asf::app {

namespace {

std::string joinPath(const std::vector<NodeId>& p) {
  std::string s;
  for (std::size_t i = 0; i < p.size(); ++i) s += (i ? " " : "") + std::to_string(p[i]);
  return s;
}

/// The occupancy map of --map: a map_server YAML or an image at `resolution`; none if empty.
GridMap readMapArgument(const std::string& path, double resolution) {
  if (io::isOccupancyYaml(path)) return io::readOccupancyMap(path);
  if (!path.empty()) return io::gridFromImage(io::readGrayImage(path), resolution);
  return {};
}

/// The planner's keys with the command line's overrides; with --voronoi, voronoi_edges=true
/// (only for a planner that has the key).
Params plannerParams(const framework::PluginInfo& pinfo, std::vector<std::string> overrides,
                     bool voronoi, bool have_map) {
  if (voronoi) {
    if (!have_map) throw ConfigError("--voronoi needs --map MAP.png");
    bool declared = false;
    for (std::size_t i = 0; i < pinfo.descriptor->num_keys; ++i)
      if (std::string(pinfo.descriptor->keys[i].name) == "voronoi_edges") declared = true;
    if (!declared)
      throw ConfigError("--voronoi: planner " + pinfo.name() +
                        " has no voronoi_edges key (criterion planners: expected_uncertainty, "
                        "mechanical_work, sum_dopt)");
    overrides.push_back("voronoi_edges=true");
  }
  return setOverrides(overrides, pinfo.name(), "planner")
      .resolve(pinfo.name(), pinfo.descriptor->keys, pinfo.descriptor->num_keys);
}

void renderImage(const std::string& png, const std::string& map, double resolution, bool ellipses,
                 const PoseGraph& g, const studies::PlanQueryResult& r) {
  planning::RenderOptions ro;
  ro.ellipses = ellipses;
  ro.map_png = map;
  ro.map_resolution = resolution;
  if (io::isOccupancyYaml(map)) {  // the YAML's image, in the YAML's frame
    const io::OccupancyMapInfo info = io::readOccupancyYaml(map);
    ro.map_png = io::occupancyImagePath(map, info);
    ro.map_resolution = info.resolution;
    ro.map_origin_x = info.origin_x;
    ro.map_origin_y = info.origin_y;
  }
  planning::renderPlan(png, g, &r.marginals, r.plan.nodes, ro);
}

nlohmann::json alternativeJson(const std::optional<studies::PathAlternative>& a) {
  if (!a) return nullptr;
  return {{"path", a->path},
          {"distance", a->distance},
          {"expected_uncertainty", a->expected_uncertainty},
          {"cost", a->cost},
          {"virtual_steps", a->virtual_steps}};
}

nlohmann::json hypothesesJson(const studies::HypothesisCheck& h) {
  return {{"steps", h.steps},
          {"sequences", h.sequences},
          {"hypotheses", h.hypotheses},
          {"evaluations", h.evaluations},
          {"checked_from_step", h.checked_from_step},
          {"checked_steps", h.checked_steps},
          {"checked_sequences", h.checked_sequences},
          {"checked_mixed_prefixes", h.checked_mixed_prefixes},
          {"relative_difference", h.relative_difference}};
}

void printJson(const std::string& graph, const std::string& planner,
               const studies::PlanQuery& q, const studies::PlanQueryResult& r,
               bool voronoi_edges, const std::string& image) {
  const planning::PathCost& expected =
      r.costs.at(planning::criterionName(planning::Criterion::ExpectedUncertainty));
  nlohmann::json ec = nlohmann::json::array();
  for (int i = 0; i < 3; ++i)
    ec.push_back({expected.expected(i, 0), expected.expected(i, 1), expected.expected(i, 2)});
  nlohmann::json costs = nlohmann::json::object(), labels = nlohmann::json::object();
  for (const auto& [name, c] : r.costs) {
    costs[name] = c.cost;
    labels[name] = c.label;
  }
  const nlohmann::json comparison =
      voronoi_edges ? nlohmann::json{{"graph", alternativeJson(r.along_graph)},
                                     {"unexplored", alternativeJson(r.through_unexplored)}}
                    : nlohmann::json(nullptr);
  nlohmann::json j = {
      {"graph", graph},
      {"planner", planner},
      {"start", q.start},
      {"goal", q.goal},
      {"path", r.plan.nodes},
      {"cost", r.plan.cost},
      {"criterion", r.plan.criterion},
      {"costs", costs},
      {"labels", labels},
      {"expected_covariance", ec},
      {"candidates", r.candidates.paths.size()},
      {"capped", r.candidates.capped},
      {"search", planning::searchMethodName(r.candidates.method)},
      {"fell_back", r.candidates.fell_back},
      {"merged_vertices", r.candidates.merged_vertices},
      {"reduced_nodes", r.candidates.reduced_nodes},
      {"reduced_edges", r.candidates.reduced_edges},
      {"cross_blocks", r.cross_blocks},
      {"voronoi_edges", voronoi_edges},
      {"virtual_edges", r.virtual_edges.size()},
      {"virtual_steps", r.virtual_steps},
      {"comparison", comparison},
      {"voronoi_time_s", r.voronoi_s},
      {"search_time_s", r.search_s},
      {"marginals_time_s", r.marginals_s},
      {"plan_time_s", r.plan_s},
      {"hypotheses", hypothesesJson(studies::checkHypotheses(r.model, r.criterion_options))},
      {"note", r.note}};
  if (!image.empty()) j["image"] = image;
  std::cout << j.dump(2) << "\n";
}

void printComparison(const studies::PlanQueryResult& r) {
  std::cout << "  voronoi: " << r.virtual_edges.size() << " virtual edges (" << r.voronoi_s
            << " s); the path takes " << r.virtual_steps.size() << ":";
  for (const auto& [a, b] : r.virtual_steps) std::cout << " " << a << "-" << b;
  std::cout << "\n  thesis Table 3.2: distance [m], det(E[C]), product -- the best path along "
               "the graph, the shortest through unexplored space\n";
  for (const auto* c : {&r.along_graph, &r.through_unexplored}) {
    std::cout << "    " << std::left << std::setw(11)
              << (c == &r.along_graph ? "graph" : "unexplored");
    if (!*c)
      std::cout << "no candidate\n";
    else
      std::cout << (*c)->distance << "  " << (*c)->expected_uncertainty << "  " << (*c)->cost
                << "\n";
  }
}

void printText(const std::string& graph, const PoseGraph& g, const std::string& planner,
               const studies::PlanQueryResult& r, bool voronoi_edges) {
  const auto& c = r.candidates;
  std::cout << std::setprecision(6) << graph << ": " << g.size() << " nodes, " << g.edges.size()
            << " edges; " << c.paths.size() << " candidate paths ("
            << planning::searchMethodName(c.method) << "; search graph " << c.reduced_nodes
            << " vertices, " << c.reduced_edges << " edges, " << c.merged_vertices
            << " merged aliases" << (c.capped ? ", capped" : "") << ")\n"
            << planner << ": " << r.plan.nodes.size() << " nodes: " << joinPath(r.plan.nodes)
            << "\n  " << r.plan.criterion << " = " << r.plan.cost << " (plan " << r.plan_s
            << " s, marginals " << r.marginals_s << " s)\n";
  for (const auto& [k, v] : r.costs)
    std::cout << "  " << std::left << std::setw(22) << k << v.label << " = " << v.cost << "\n";
  if (voronoi_edges) printComparison(r);
  if (!r.note.empty()) std::cout << "note: " << r.note << "\n";
}

/// asf plan's options, added to `cmd` in declaration order (--help's order depends on it).
struct PlanArgs {
  explicit PlanArgs(TCLAP::CmdLine& parser) : cmd(parser) {}

  TCLAP::CmdLine& cmd;
  TCLAP::ValueArg<std::string> graph{"g", "graph", "The pose graph (g2o)", true, "", "FILE.g2o",
                                     cmd};
  // Signed: an unsigned argument would read -1 as 4294967295.
  TCLAP::ValueArg<long long> start{"", "start", "Start node id", true, 0, "ID", cmd};
  TCLAP::ValueArg<long long> goal{"", "goal", "Goal node id", true, 0, "ID", cmd};
  TCLAP::ValueArg<std::string> planner{"", "planner", "Planner plugin name", false,
                                       "expected_uncertainty", "NAME", cmd};
  TCLAP::MultiArg<std::string> set{"s", "set",
                                   "Planner key: key=value or <planner>.key=value (repeatable)",
                                   false, "KEY=VALUE", cmd};
  TCLAP::ValueArg<std::string> backend{"b", "backend", "Back-end recovering the marginals", false,
                                       "sparse_lm", "NAME", cmd};
  TCLAP::ValueArg<std::uint64_t> seed{"", "seed", "Seed handed to the planner", false, 1, "N", cmd};
  TCLAP::ValueArg<std::size_t> max_cross{
      "", "max-cross",
      "Request cross-covariances only if the candidate paths need at most this many blocks", false,
      2000000, "N", cmd};
  TCLAP::SwitchArg json{"j", "json",
                        "Print one JSON object: path, cost, criterion, costs (every "
                        "criterion), expected_covariance, candidates, capped, timings, note",
                        cmd};
  TCLAP::ValueArg<std::string> image{"", "image", "Draw the graph and the path (PNG)", false, "",
                                     "OUT.png", cmd};
  TCLAP::SwitchArg ellipses{"", "ellipses", "With --image: 3-sigma marginal ellipses", cmd};
  TCLAP::ValueArg<std::string> map{
      "", "map",
      "Occupancy map: a map_server YAML (e.g. a run's map.yaml: resolution, origin, thresholds and "
      "mode from it; unknown cells are not free), or an image (row 0 = top, origin (0, 0), pixels "
      ">= 250 free, "
      "the rest occupied, --resolution); handed to the planner (voronoi_edges) and drawn "
      "under --image",
      false, "", "MAP.yaml|MAP.png", cmd};
  TCLAP::SwitchArg voronoi{
      "", "voronoi",
      "Partially explored map: set the planner's voronoi_edges=true (needs --map): virtual "
      "edges of the map's generalized Voronoi graph join nodes the pose graph does not",
      cmd};
  TCLAP::ValueArg<double> resolution{"", "resolution", "Map resolution [m/pixel]", false, 0.05, "R",
                                     cmd};
  TCLAP::MultiArg<std::string> path{"p", "plugin-path", "Extra plugin folder (repeatable)", false,
                                    "DIR", cmd};
};

}  // namespace

int cmdPlan(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Plans a path between two nodes of a 2D pose graph (g2o; taken as already optimized) "
      "with a planner plugin: expected_uncertainty (thesis ch. 3), mechanical_work, sum_dopt, "
      "shortest. The back-end recovers the node marginals and the cross-covariances between "
      "nodes of the candidate paths. Prints the path and its cost under every criterion "
      "(expected_uncertainty, mechanical_work, sum_dopt, distance); --image draws it.",
      ' ', ASF_VERSION_STRING);
  PlanArgs args(cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);

  framework::Registry reg;
  scanPlugins(reg, args.path.getValue());
  const auto pinfo = reg.find(args.planner.getValue(), PluginKind::Planner);
  const auto binfo = reg.find(args.backend.getValue(), PluginKind::Backend);
  const Params pparams = plannerParams(*pinfo, args.set.getValue(), args.voronoi.getValue(),
                                       !args.map.getValue().empty());
  if (!(args.resolution.getValue() > 0)) throw ConfigError("--resolution must be > 0");
  PluginContext ctx;
  ctx.seed = args.seed.getValue();
  auto pl = framework::Registry::create<Planner>(pinfo);
  framework::logPluginToStderr(*pl, pinfo->name());
  pl->configure(pparams, ctx);
  auto be = framework::Registry::create<Backend>(binfo);
  framework::logPluginToStderr(*be, binfo->name());
  be->configure(
      Params::fromSpecs(binfo->name(), binfo->descriptor->keys, binfo->descriptor->num_keys),
      PluginContext{});

  const PoseGraph g = readG2o(args.graph.getValue());
  for (long long v : {args.start.getValue(), args.goal.getValue()})
    if (v < 0 || static_cast<unsigned long long>(v) >= g.size())
      throw InputError(args.graph.getValue() + ": node " + std::to_string(v) +
                       " does not exist (the graph has " + std::to_string(g.size()) +
                       " nodes, numbered from 0)");
  const GridMap grid = readMapArgument(args.map.getValue(), args.resolution.getValue());
  studies::PlanQuery q;
  q.start = static_cast<NodeId>(args.start.getValue());
  q.goal = static_cast<NodeId>(args.goal.getValue());
  q.map = grid.grid ? &grid : nullptr;
  q.max_cross = args.max_cross.getValue();
  const studies::PlanQueryResult r = studies::planOnGraph(g, *pl, pparams, ctx.seed, *be, q);
  if (r.cross_skipped)
    std::cerr << "asf plan: the candidate paths need more than " << args.max_cross.getValue()
              << " cross-covariance blocks (--max-cross); node marginals only\n";
  if (!r.plan.found)
    throw Error(pinfo->name() + ": no path from " + std::to_string(q.start) + " to " +
                std::to_string(q.goal) + ": " + r.plan.reason);
  if (!args.image.getValue().empty())
    renderImage(args.image.getValue(), args.map.getValue(), args.resolution.getValue(),
                args.ellipses.getValue(), g, r);
  const bool voronoi_edges = planning::pathSearchOptionsFrom(pparams).voronoi_edges;
  if (args.json.getValue()) {
    printJson(args.graph.getValue(), pinfo->name(), q, r, voronoi_edges, args.image.getValue());
  } else {
    printText(args.graph.getValue(), g, pinfo->name(), r, voronoi_edges);
    if (!args.image.getValue().empty()) std::cout << "wrote " << args.image.getValue() << "\n";
  }
  return kOk;
}

}  // namespace asf::app
