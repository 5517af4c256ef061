// asf route: one route on one graph of a graph-list file (Euler, Chinese postman, TSP, or an
// on-line explorer simulated on the known graph). The offline baselines of thesis ch. 6.
#include <asf/abi.h>
#include <asf/errors.h>
#include <asf/graph/file.h>
#include <asf/graph/routes.h>
#include <asf/graph/multigraph.h>
#include <tclap/CmdLine.h>

#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"

namespace asf::app {

namespace {

void printRouteJson(const std::string& file, const graph::ListedGraph& chosen,
                    graph::RouteAlgorithm algo, int start, unsigned seed,
                    const graph::RouteResult& r) {
  const graph::Multigraph& g = chosen.graph;
  const auto counts = r.walk.traversals(g.m());
  double total = 0;
  for (const auto& e : g.edges) total += e.length;
  nlohmann::json nodes = nlohmann::json::array(), edges = nlohmann::json::array();
  for (int v : r.walk.nodes) nodes.push_back(v + 1);
  for (int e : r.walk.edges) edges.push_back(e + 1);
  nlohmann::json j = {{"file", file},
                      {"index", chosen.line},
                      {"n", g.n},
                      {"m", g.m()},
                      {"algorithm", graph::routeAlgorithmName(algo)},
                      {"start", start},
                      {"end", r.walk.nodes.back() + 1},
                      {"seed", seed},
                      {"length", r.walk.length},
                      {"edges_length", total},
                      {"traversals", r.walk.steps()},
                      {"closed", r.walk.closed()},
                      {"nodes", nodes},
                      {"edges", edges},
                      {"edge_traversals", counts},
                      {"covered_all_edges", r.covered_all_edges},
                      {"visited_all_nodes", r.visited_all_nodes},
                      {"steps_to_cover_edges", r.steps_to_cover_edges},
                      {"steps_to_visit_nodes", r.steps_to_visit_nodes},
                      {"exact", r.exact},
                      {"lower_bound", nullptr}};
  if (r.lower_bound >= 0) j["lower_bound"] = r.lower_bound;
  std::cout << j.dump(2) << "\n";
}

void printRouteText(const std::string& where, const graph::Multigraph& g,
                    graph::RouteAlgorithm algo, int start, const graph::RouteResult& r) {
  double total = 0;
  for (const auto& e : g.edges) total += e.length;
  std::cout << std::setprecision(10) << where << ": " << g.n << " nodes, " << g.m()
            << " edges (total length " << total << ")\n"
            << graph::routeAlgorithmName(algo) << " from node " << start << ": length "
            << r.walk.length << ", " << r.walk.steps() << " traversals, "
            << (r.walk.closed() ? "closed"
                                : "ends at node " + std::to_string(r.walk.nodes.back() + 1))
            << "\n";
  if (r.exact)
    std::cout << "optimal\n";
  else if (r.lower_bound >= 0)
    std::cout << "lower bound " << r.lower_bound << " (gap " << std::setprecision(3)
              << (r.walk.length > 0 ? 100 * (r.walk.length - r.lower_bound) / r.walk.length : 0)
              << "%)\n"
              << std::setprecision(10);
  std::cout << "covers every edge: " << (r.covered_all_edges ? "yes" : "no");
  if (r.steps_to_cover_edges >= 0) std::cout << " (after " << r.steps_to_cover_edges << " steps)";
  std::cout << "; visits every node: " << (r.visited_all_nodes ? "yes" : "no");
  if (r.steps_to_visit_nodes >= 0) std::cout << " (after " << r.steps_to_visit_nodes << " steps)";
  std::cout << "\nwalk:";
  for (int v : r.walk.nodes) std::cout << " " << v + 1;
  std::cout << "\n";
}

}  // namespace

int cmdRoute(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Computes a route on one graph of a graph-list file (one graph per line: 'n m u1-v1 "
      "u2-v2 ...', 1-based nodes, unit lengths). euler: every edge once; cpp: Chinese postman "
      "(shortest closed walk covering every edge, exact); tsp: shortest closed walk visiting "
      "every node (exact up to 16 nodes, otherwise a heuristic with a lower bound); tarry, "
      "tarry_modified (entrance edge last, loop closing first, stop when every edge is "
      "traversed: TIGRE's rule), tremaux, dfs: on-line explorers that learn edges on arrival. "
      "Prints the length, the number of traversals, the nodes of the walk (1-based) and its "
      "coverage.",
      ' ', ASF_VERSION_STRING);
  TCLAP::UnlabeledValueArg<std::string> file("graph", "Graph-list file", true, "", "GRAPH", cmd);
  std::vector<std::string> names;
  for (auto a : {graph::RouteAlgorithm::Euler, graph::RouteAlgorithm::ChinesePostman,
                 graph::RouteAlgorithm::Tsp, graph::RouteAlgorithm::Tarry,
                 graph::RouteAlgorithm::TarryModified, graph::RouteAlgorithm::Tremaux,
                 graph::RouteAlgorithm::Dfs})
    names.push_back(graph::routeAlgorithmName(a));
  TCLAP::ValuesConstraint<std::string> allowed(names);
  TCLAP::ValueArg<std::string> algorithm("a", "algorithm", "Route to compute", true, "", &allowed,
                                         cmd);
  TCLAP::ValueArg<int> start("s", "start", "Start node (1-based)", false, 1, "K", cmd);
  TCLAP::ValueArg<int> end("e", "end", "End node (1-based; euler and cpp only: an open walk)",
                           false, 0, "K", cmd);
  TCLAP::ValueArg<unsigned> seed("", "seed", "Seed for the explorers' ties", false, 0, "S", cmd);
  TCLAP::ValueArg<int> index("i", "index",
                             "The graph on this line of the file (1-based; default: the first "
                             "graph)",
                             false, 0, "L", cmd);
  TCLAP::SwitchArg json("j", "json",
                        "Print one JSON object: file, index, n, m, algorithm, start, seed, "
                        "length, traversals, nodes, edges, edge_traversals, closed, "
                        "covered_all_edges, visited_all_nodes, exact, lower_bound, ...",
                        cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);

  const auto list = graph::readGraphList(file.getValue());
  const graph::ListedGraph* chosen = &graph::graphOnLine(
      list, file.getValue(),
      index.getValue() == 0 ? std::nullopt : std::optional<int>(index.getValue()));
  const graph::Multigraph& g = chosen->graph;
  const auto algo = graph::parseRouteAlgorithm(algorithm.getValue());
  const std::string where = file.getValue() + ":" + std::to_string(chosen->line);
  graph::RouteResult r;
  try {
    r = graph::computeRoute(g, algo, start.getValue() - 1, seed.getValue(), end.getValue() - 1);
  } catch (const InputError& e) {
    throw InputError(where + ": " + e.what());
  } catch (const Error& e) {
    throw Error(where + ": " + e.what());
  }
  if (json.getValue())
    printRouteJson(file.getValue(), *chosen, algo, start.getValue(), seed.getValue(), r);
  else
    printRouteText(where, g, algo, start.getValue(), r);
  return kOk;
}

}  // namespace asf::app
