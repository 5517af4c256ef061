// asf optimal-eval: the optimal-exploration analysis of a set of graphs (thesis Table 5.1):
// certified D/A/E optima and the efficiency of the routes a robot could take on each graph;
// asf graph-gen: the seeded graph families to run it on.
#include <asf/atomic_file.h>
#include <asf/abi.h>
#include <asf/errors.h>
#include <asf/graph/families.h>
#include <asf/graph/information.h>
#include <asf/graph/routes.h>
#include <tclap/CmdLine.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.h"

namespace asf::app {

namespace {

using nlohmann::json;

const char* kRoutes[] = {"uniform", "cpp", "tsp", "tarry"};

struct Stats {
  double mean = 0, std = 0;
};

Stats stats(const std::vector<double>& v) {
  Stats s;
  if (v.empty()) return s;
  for (double x : v) s.mean += x;
  s.mean /= static_cast<double>(v.size());
  for (double x : v) s.std += (x - s.mean) * (x - s.mean);
  // Sample standard deviation, as tables of means +- std usually report.
  s.std = v.size() > 1 ? std::sqrt(s.std / static_cast<double>(v.size() - 1)) : 0.0;
  return s;
}

// Efficiency per graph (x: graphs in file order, y: 0..1), one panel per criterion, one
// colour per route. Hand-written SVG: no plotting dependency.
void writeEfficiencySvg(const std::string& path, const json& graphs,
                        const std::vector<std::string>& names) {
  const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e"};
  const int W = 300, H = 220, L = 45, B = 35, T = 25;
  const int panels = static_cast<int>(names.size());
  std::vector<const json*> ok;
  for (const auto& g : graphs)
    if (g["connected"].get<bool>()) ok.push_back(&g);
  std::ostringstream os;
  os << "<svg xmlns='http://www.w3.org/2000/svg' width='" << panels * (W + 10) + 10 << "' height='"
     << H + 40 << "' font-family='sans-serif' font-size='11'>\n"
     << "<rect width='100%' height='100%' fill='white'/>\n";
  for (int p = 0; p < panels; ++p) {
    const int x0 = 10 + p * (W + 10);
    const int pw = W - L - 10, ph = H - T - B;
    os << "<g transform='translate(" << x0 << ",0)'>\n"
       << "<text x='" << L + pw / 2 << "' y='15' text-anchor='middle'>efficiency, " << names[p]
       << "-criterion</text>\n"
       << "<rect x='" << L << "' y='" << T << "' width='" << pw << "' height='" << ph
       << "' fill='none' stroke='black'/>\n";
    for (int k = 0; k <= 4; ++k) {
      const double y = T + ph - ph * k / 4.0;
      os << "<line x1='" << L << "' x2='" << L + pw << "' y1='" << y << "' y2='" << y
         << "' stroke='#ddd'/><text x='" << L - 4 << "' y='" << y + 4 << "' text-anchor='end'>"
         << k * 25 << "%</text>\n";
    }
    os << "<text x='" << L + pw / 2 << "' y='" << H - 8
       << "' text-anchor='middle'>graph (file order)</text>\n";
    for (int r = 0; r < 4; ++r) {
      for (std::size_t i = 0; i < ok.size(); ++i) {
        const double e = (*ok[i])["efficiency"][kRoutes[r]][names[p]].get<double>();
        const double x = L + pw * (ok.size() > 1 ? static_cast<double>(i) / (ok.size() - 1) : 0.5);
        os << "<circle cx='" << x << "' cy='" << T + ph - ph * std::clamp(e, 0.0, 1.0)
           << "' r='1.8' fill='" << colours[r] << "'/>";
      }
      os << "\n";
      if (p == 0)
        os << "<rect x='" << L + 6 + 62 * r << "' y='" << T + 4 << "' width='8' height='8' fill='"
           << colours[r] << "'/><text x='" << L + 17 + 62 * r << "' y='" << T + 12 << "'>"
           << kRoutes[r] << "</text>\n";
    }
    os << "</g>\n";
  }
  os << "</svg>\n";
  writeFileAtomically(path, os.str(), "plot");
}

/// Each route's efficiencies per criterion over the connected graphs: [route][criterion].
using Efficiencies = std::map<std::string, std::map<std::string, std::vector<double>>>;

/// The routes of kRoutes from node 1 as traversals per edge: every edge once, the Chinese
/// postman, the TSP walk and TIGRE's modified Tarry walk (ties drawn with `seed`).
std::vector<Eigen::VectorXd> routeCounts(const graph::Multigraph& g, std::uint32_t seed) {
  std::vector<Eigen::VectorXd> counts;
  counts.push_back(Eigen::VectorXd::Ones(g.m()));
  auto asVector = [&](const graph::Walk& w) {
    const auto x = w.weights(g.m());
    return Eigen::Map<const Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size()))
        .eval();
  };
  counts.push_back(asVector(graph::chinesePostman(g, 0).walk));
  counts.push_back(asVector(graph::travelingSalesman(g, 0).walk));
  counts.push_back(asVector(graph::tarry(g, 0, graph::TarryOptions::modified(), seed).walk));
  return counts;
}

/// The optimum of each criterion of connected graph g and the efficiency of each route
/// (`counts`) against it, into jg and eff; the solves' time is added to optimum_ms.
void scoreGraph(const graph::Multigraph& g, const std::vector<Eigen::VectorXd>& counts,
                const std::vector<std::string>& names, const std::vector<double>& ps, json& jg,
                Efficiencies& eff, double& optimum_ms) {
  for (std::size_t c = 0; c < ps.size(); ++c) {
    const graph::OptimalDesign d = graph::optimalDesign(g, ps[c]);
    optimum_ms += d.time_ms;
    jg["optimum"][names[c]] = d.value;
    jg["gap"][names[c]] = d.relative_gap;
    jg["weights"][names[c]] =
        std::vector<double>(d.weights.data(), d.weights.data() + d.weights.size());
    for (int r = 0; r < 4; ++r) {
      const double e = graph::efficiency(g, counts[r], ps[c], d.value);
      jg["efficiency"][kRoutes[r]][names[c]] = e;
      eff[kRoutes[r]][names[c]].push_back(e);
    }
  }
}

/// One row of the text table: optima and the routes' efficiencies [%].
void printGraphRow(const json& jg, int line, const graph::Multigraph& g,
                   const std::vector<std::string>& names) {
  std::cout << std::setw(6) << line << std::setw(5) << g.n << std::setw(5) << g.m() << "  "
            << std::fixed << std::setprecision(4);
  for (const auto& n : names) std::cout << jg["optimum"][n].get<double>() << ' ';
  std::cout << std::setprecision(1) << "  ";
  for (int r = 0; r < 4; ++r) {
    for (const auto& n : names)
      std::cout << 100 * jg["efficiency"][kRoutes[r]][n].get<double>() << (n == "E" ? "" : "/");
    std::cout << (r < 3 ? " | " : "\n");
  }
  std::cout << std::defaultfloat;
}

/// The text summary: each route's efficiency per criterion (mean +- std) and the times.
void printSummaryTable(const json& summary, const std::vector<std::string>& names,
                       std::size_t connected, std::size_t graphs, double optimum_ms) {
  std::cout << "\n"
            << connected << " connected graphs of " << graphs << "; efficiency, mean +- std [%]:\n"
            << std::fixed << std::setprecision(1);
  for (const char* r : kRoutes) {
    std::cout << "  " << std::left << std::setw(8) << r;
    for (const auto& n : names)
      std::cout << "  " << n << " " << 100 * summary["efficiency"][r][n]["mean"].get<double>()
                << " +- " << 100 * summary["efficiency"][r][n]["std"].get<double>();
    std::cout << "\n";
  }
  std::cout << std::setprecision(3) << "time " << summary["time_ms"].get<double>() / 1000
            << " s (D/A/E optima " << optimum_ms / 1000 << " s, the rest routes and I/O)\n";
}

}  // namespace

int cmdOptimalEval(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Optimal-exploration analysis of a set of graphs (thesis ch. 5, Table 5.1). For every "
      "connected graph of LIST (one per line, 'n m u1-v1 ...', 1-based; '#' comments): the "
      "certified optimum of ||L(x)||_p over the simplex for D, A, E, and the efficiency "
      "(information rate / optimum) of four routes from node 1: every edge once (uniform), "
      "the Chinese postman walk, the TSP walk and TIGRE's modified Tarry walk. Prints a table "
      "and the mean +- std over the connected graphs.",
      ' ', ASF_VERSION_STRING);
  TCLAP::UnlabeledValueArg<std::string> file("list", "Graph-list file", true, "", "LIST", cmd);
  TCLAP::ValueArg<std::uint32_t> seed("s", "seed", "Seed of the Tarry walk's ties", false, 1,
                                      "SEED", cmd);
  TCLAP::ValueArg<std::string> plot("p", "plot", "Write the efficiencies as an SVG plot", false, "",
                                    "OUT.svg", cmd);
  TCLAP::SwitchArg json_out(
      "j", "json",
      "Print one JSON object: graphs [{index (line), n, m, connected, optimum {D,A,E}, gap "
      "{D,A,E} (relative), weights {D,A,E}, efficiency {uniform,cpp,tsp,tarry}{D,A,E}, "
      "time_ms}], summary {graphs, connected, efficiency {route {criterion {mean, std}}}, "
      "time_ms, optimum_time_ms (the optimal-design solves alone)}",
      cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);

  const std::vector<std::string> names{"D", "A", "E"};
  const std::vector<double> ps{graph::kCriterionD, graph::kCriterionA, graph::kCriterionE};
  const auto list = graph::readGraphList(file.getValue());
  const auto t_all = std::chrono::steady_clock::now();
  json graphs = json::array();
  Efficiencies eff;
  std::size_t connected = 0;
  double optimum_ms = 0;  // the D/A/E solves alone (the speed goal), routes aside
  const bool text = !json_out.getValue();
  if (text)
    std::cout << std::left << std::setw(6) << "line" << std::setw(5) << "n" << std::setw(5) << "m"
              << "  optimum D/A/E           efficiency D/A/E [%]: uniform | cpp | tsp | tarry\n";
  for (const auto& lg : list) {
    const graph::Multigraph& g = lg.graph;
    const auto t0 = std::chrono::steady_clock::now();
    json jg{{"index", lg.line}, {"n", g.n}, {"m", g.m()}, {"connected", g.connected()}};
    if (!g.connected()) {
      graphs.push_back(jg);
      if (text)
        std::cout << std::setw(6) << lg.line << std::setw(5) << g.n << std::setw(5) << g.m()
                  << "  not connected: skipped\n";
      continue;
    }
    ++connected;
    scoreGraph(g, routeCounts(g, seed.getValue()), names, ps, jg, eff, optimum_ms);
    jg["time_ms"] =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (text) printGraphRow(jg, lg.line, g, names);
    graphs.push_back(jg);
  }
  json summary{{"graphs", list.size()}, {"connected", connected}};
  for (const char* r : kRoutes)
    for (const auto& n : names) {
      const Stats s = stats(eff[r][n]);
      summary["efficiency"][r][n] = {{"mean", s.mean}, {"std", s.std}};
    }
  summary["time_ms"] =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_all).count();
  summary["optimum_time_ms"] = optimum_ms;
  if (!plot.getValue().empty()) writeEfficiencySvg(plot.getValue(), graphs, names);
  if (json_out.getValue())
    std::cout << json{{"file", file.getValue()}, {"graphs", graphs}, {"summary", summary}}.dump(1)
              << "\n";
  else
    printSummaryTable(summary, names, connected, list.size(), optimum_ms);
  return kOk;
}

int cmdGraphGen(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Writes a graph list (the input of asf optimal-eval, asf optimal and asf route) of seeded "
      "random graphs: 4-connected grids, random trees, Watts-Strogatz small worlds (k = 4, "
      "beta = 0.2), indoor-like rooms along a corridor, or a mix of the four. Graph i is drawn "
      "from seed + i, so a longer list starts with the shorter one.",
      ' ', ASF_VERSION_STRING);
  std::vector<std::string> fams{"grid", "tree", "smallworld", "rooms", "mixed"};
  TCLAP::ValuesConstraint<std::string> fc(fams);
  TCLAP::ValueArg<std::string> family("f", "family", "Graph family", false, "mixed", &fc, cmd);
  TCLAP::ValueArg<int> count("c", "count", "Number of graphs", false, 137, "N", cmd);
  TCLAP::ValueArg<int> max_nodes("n", "max-nodes", "Largest graph (>= 4 nodes)", false, 120, "N",
                                 cmd);
  TCLAP::ValueArg<std::uint64_t> seed("s", "seed", "Seed of the first graph", false, 1, "SEED",
                                      cmd);
  TCLAP::ValueArg<std::string> out("o", "out", "Output graph-list file", true, "", "FILE", cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);
  if (count.getValue() < 0) throw TCLAP::CmdLineParseException("must be >= 0", "--count");
  if (max_nodes.getValue() < 4) throw TCLAP::CmdLineParseException("must be >= 4", "--max-nodes");
  const auto gs = graph::generateFamily(family.getValue(), count.getValue(), max_nodes.getValue(),
                                        seed.getValue());
  std::ostringstream c;
  c << "asf graph-gen --family " << family.getValue() << " --count " << count.getValue()
    << " --max-nodes " << max_nodes.getValue() << " --seed " << seed.getValue();
  graph::writeGraphList(out.getValue(), gs, c.str());
  std::size_t nmax = 0, mmax = 0;
  for (const auto& g : gs)
    nmax = std::max<std::size_t>(nmax, g.n), mmax = std::max<std::size_t>(mmax, g.m());
  std::cout << "graph-gen: " << gs.size() << " " << family.getValue() << " graphs (up to " << nmax
            << " nodes, " << mmax << " edges) written to " << out.getValue() << "\n";
  return kOk;
}

}  // namespace asf::app
