// asf optimal: certified optimal edge weights of one graph for the criteria of chapter 5
// (D, A, E, T or any p <= 1), with the efficiency of traversing every edge once.
#include <asf/abi.h>
#include <asf/errors.h>
#include <asf/graph_information.h>
#include <asf/pose_graph.h>
#include <tclap/CmdLine.h>

#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.h"

namespace asf::app {

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The pose graph of a g2o file as a multigraph: one node per vertex, one edge per measurement.
graph::Multigraph fromG2o(const std::string& path) {
  const PoseGraph pg = readG2o(path);
  graph::Multigraph g;
  g.n = static_cast<int>(pg.size());
  for (const auto& e : pg.edges)
    g.edges.push_back({static_cast<int>(e.from), static_cast<int>(e.to), 1.0});
  return g;
}

// The topological graph of a run or of `asf segment --graph` (topology.json): one node per
// region, one edge per region border; frontier edges and the unexplored node are left out.
graph::Multigraph fromTopologyJson(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot be read");
  nlohmann::json j;
  try {
    in >> j;
  } catch (const std::exception& e) {
    throw InputError(path + ": not JSON: " + e.what());
  }
  if (!j.contains("nodes") || !j.contains("edges"))
    throw InputError(path + ": no \"nodes\" and \"edges\" (expected a topology.json)");
  graph::Multigraph g;
  std::map<long, int> index;
  for (const auto& n : j["nodes"]) {
    const long r = n.at("region").get<long>();
    if (r > 0) index.emplace(r, static_cast<int>(index.size()));
  }
  g.n = static_cast<int>(index.size());
  for (const auto& e : j["edges"]) {
    if (e.value("frontier", false)) continue;
    const auto a = index.find(e.at("a").get<long>()), b = index.find(e.at("b").get<long>());
    if (a == index.end() || b == index.end())
      throw InputError(path + ": edge " + e.dump() + " names a region that is not a node");
    g.edges.push_back({a->second, b->second, 1.0});
  }
  return g;
}

std::vector<double> parseCriteria(const std::string& list) {
  std::vector<double> out;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(graph::parseCriterion(item));
  if (out.empty()) throw InputError("--criteria '" + list + "': no criterion given");
  return out;
}

}  // namespace

int cmdOptimal(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Certified optimal edge weights of a graph (thesis ch. 5): maximizes the normalised "
      "information ||L(x)||_p (power mean of the n-1 non-zero Laplacian eigenvalues) over the "
      "simplex sum x = 1, x >= 0, and proves it with a dual upper bound. Prints the optimum "
      "(= the best information rate), the gap, the weights and the efficiency of traversing "
      "every edge once (uniform weights). GRAPH is a graph-list file (one graph per line, "
      "'n m u1-v1 u2-v2 ...', 1-based ids; the first graph, or the one on line --index), a "
      "g2o file (.g2o: one node per vertex, one edge per measurement) or a topological graph "
      "(.json, as asf run and asf segment --graph write it: regions and their borders). "
      "--walks D also searches every traversal of 1..D edges exhaustively (thesis figs. "
      "5.6-5.10) and --plot draws best information and information rate vs d.",
      ' ', ASF_VERSION_STRING);
  TCLAP::UnlabeledValueArg<std::string> file("graph", "Graph-list or g2o file", true, "",
                                             "GRAPH", cmd);
  TCLAP::ValueArg<std::string> criteria(
      "c", "criteria", "Comma-separated criteria: T, D, A, E or numbers p <= 1", false, "D,A,E",
      "LIST", cmd);
  TCLAP::ValueArg<int> index("i", "index", "Line number (1-based) of the graph in a graph list",
                             false, 0, "K", cmd);
  TCLAP::ValueArg<double> tolerance(
      "t", "tolerance", "Target relative gap (default 5e-7 smooth criteria, 5e-6 for E)", false,
      0.0, "TOL", cmd);
  TCLAP::SwitchArg json("j", "json",
                        "Print one JSON object: file, index, n, m, connected, optimum, "
                        "upper_bound, gap, relative_gap, converged, weights, efficiency.uniform, "
                        "iterations, time_ms (each keyed by criterion name)",
                        cmd);
  TCLAP::ValueArg<int> walks("w", "walks",
                             "Exhaustive search of every traversal of d = 1..D edges", false, 0,
                             "D", cmd);
  std::vector<std::string> kinds{"walk", "closed", "multiset"};
  TCLAP::ValuesConstraint<std::string> kind_c(kinds);
  TCLAP::ValueArg<std::string> kind(
      "", "walk-kind",
      "walk: edge sequences of walks (figs 5.8-5.10); closed: walks back to their start; "
      "multiset: any d edges (figs 5.6, 5.7)",
      false, "walk", &kind_c, cmd);
  TCLAP::ValueArg<int> start("", "start", "Walks start at this node (1-based; default any)",
                             false, 0, "NODE", cmd);
  TCLAP::ValueArg<std::string> plot("p", "plot",
                                    "SVG of the exhaustive search: information and rate vs d, "
                                    "with the relaxed optima dashed",
                                    false, "", "FILE.svg", cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);
  if (plot.isSet() && walks.getValue() <= 0)
    throw InputError("--plot draws the exhaustive search: give --walks D too");

  const auto ps = parseCriteria(criteria.getValue());
  const std::string path = file.getValue();
  graph::Multigraph g;
  int line = 0;
  if (endsWith(path, ".g2o")) {
    if (index.isSet()) throw InputError(path + ": --index applies to graph lists only");
    g = fromG2o(path);
  } else if (endsWith(path, ".json")) {
    if (index.isSet()) throw InputError(path + ": --index applies to graph lists only");
    g = fromTopologyJson(path);
  } else {
    const auto list = graph::readGraphList(path);
    if (list.empty()) throw InputError(path + ": no graph in the file");
    const graph::ListedGraph* pick = &list.front();
    if (index.isSet()) {
      pick = nullptr;
      for (const auto& lg : list)
        if (lg.line == index.getValue()) pick = &lg;
      if (!pick)
        throw InputError(path + ":" + std::to_string(index.getValue()) +
                         ": no graph on that line");
    }
    g = pick->graph;
    line = pick->line;
  }

  graph::DesignOptions opt;
  opt.tolerance = tolerance.getValue();
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(g.m());
  nlohmann::json j = {{"file", path},       {"index", line ? nlohmann::json(line) : nullptr},
                      {"n", g.n},           {"m", g.m()},
                      {"connected", g.connected()}};
  std::ostringstream text;
  text << std::setprecision(8) << path << (line ? ":" + std::to_string(line) : "") << ": " << g.n
       << " nodes, " << g.m() << " edges, " << (g.connected() ? "connected" : "NOT connected")
       << "\n";
  for (double p : ps) {
    const std::string name = graph::criterionName(p);
    const graph::OptimalDesign r = graph::optimalDesign(g, p, opt);
    const double eff = graph::efficiency(g, ones, p, r.value);
    j["optimum"][name] = r.value;
    j["upper_bound"][name] = r.upper_bound;
    j["gap"][name] = r.gap;
    j["relative_gap"][name] = r.relative_gap;
    j["converged"][name] = r.converged;
    j["weights"][name] = std::vector<double>(r.weights.data(), r.weights.data() + r.weights.size());
    j["efficiency"]["uniform"][name] = eff;
    j["iterations"][name] = r.iterations;
    j["time_ms"][name] = r.time_ms;
    text << name << ": optimum " << r.value << "  upper bound " << r.upper_bound
         << "  relative gap " << std::setprecision(3) << r.relative_gap
         << (r.converged ? "" : " (NOT converged)") << "  uniform efficiency " << std::fixed
         << std::setprecision(2) << 100 * eff << "%" << std::defaultfloat << "  ("
         << r.iterations << " iterations, " << std::setprecision(3) << r.time_ms << " ms)\n"
         << "  weights:" << std::setprecision(6);
    for (int e = 0; e < r.weights.size(); ++e) text << " " << r.weights[e];
    text << "\n" << std::setprecision(8);
  }
  if (walks.getValue() > 0) {
    graph::ExhaustiveOptions eo;
    eo.max_d = walks.getValue();
    eo.kind = kind.getValue() == "multiset" ? graph::TraversalKind::Multiset
              : kind.getValue() == "closed" ? graph::TraversalKind::ClosedWalk
                                            : graph::TraversalKind::Walk;
    if (start.isSet()) {
      if (start.getValue() < 1 || start.getValue() > g.n)
        throw InputError("--start " + std::to_string(start.getValue()) + ": nodes are 1.." +
                         std::to_string(g.n));
      eo.start = start.getValue() - 1;
    }
    eo.criteria = ps;
    const graph::ExhaustiveResult ex = graph::exhaustiveSearch(g, eo);
    nlohmann::json jx;
    jx["kind"] = kind.getValue();
    jx["d"] = ex.d;
    jx["candidates"] = ex.candidates;
    text << "exhaustive search (" << kind.getValue() << "s), best information / rate per d:\n"
         << std::setprecision(5);
    for (std::size_t c = 0; c < ex.criteria.size(); ++c) {
      const std::string name = graph::criterionName(ex.criteria[c]);
      std::vector<double> info, rate;
      for (std::size_t i = 0; i < ex.d.size(); ++i) {
        info.push_back(ex.information(static_cast<int>(i), static_cast<int>(c)));
        rate.push_back(ex.rate(static_cast<int>(i), static_cast<int>(c)));
      }
      jx["information"][name] = info;
      jx["rate"][name] = rate;
      text << "  " << name << ":";
      for (std::size_t i = 0; i < ex.d.size(); ++i)
        text << "  d=" << ex.d[i] << " " << info[i] << "/" << rate[i];
      text << "\n";
    }
    j["exhaustive"] = jx;
    if (plot.isSet()) {
      std::vector<double> optimum;
      for (double p : ex.criteria) optimum.push_back(j["optimum"][graph::criterionName(p)].get<double>());
      graph::writeExhaustiveSvg(ex, plot.getValue(), path, optimum);
      text << "plot: " << plot.getValue() << "\n";
    }
  }
  if (json.getValue())
    std::cout << j.dump(2) << "\n";
  else
    std::cout << text.str();
  return kOk;
}

}  // namespace asf::app
