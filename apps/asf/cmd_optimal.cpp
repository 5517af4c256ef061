// asf optimal: certified optimal edge weights of one graph for the criteria of chapter 5
// (D, A, E, T or any p <= 1), with the efficiency of traversing every edge once.
#include <asf/abi.h>
#include <asf/errors.h>
#include <asf/graph/drawing.h>
#include <asf/graph/file.h>
#include <asf/graph/information.h>
#include <asf/pose_graph.h>
#include <asf/graph/pose_graph_information.h>
#include <tclap/CmdLine.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "commands.h"

namespace asf::app {

namespace {

std::vector<double> parseCriteria(const std::string& list) {
  std::vector<double> out;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(graph::parseCriterion(item));
  if (out.empty()) throw InputError("--criteria '" + list + "': no criterion given");
  return out;
}

/// Graphs from this size on get progress lines on stderr.
constexpr int kProgressNodes = 500;

// The optimum of each criterion, as text and into j; returns the weights per criterion.
// Graphs of kProgressNodes or more: a line on stderr per criterion, and while it is solved
// one per iteration at most every `interval_s` seconds (its bounds and gap so far).
std::vector<Eigen::VectorXd> designs(const graph::Multigraph& g, const std::vector<double>& ps,
                                     double tolerance, double interval_s, nlohmann::json& j,
                                     std::ostream& text) {
  graph::DesignOptions opt;
  opt.tolerance = tolerance;
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(g.m());
  std::vector<Eigen::VectorXd> out;
  // A large graph takes minutes per criterion (a dense eigendecomposition per iteration):
  // say which one is being solved, and how long it took.
  const bool large = g.n >= kProgressNodes;
  for (double p : ps) {
    const std::string name = graph::criterionName(p);
    if (large)
      std::cerr << "asf optimal: " << name << "-optimal weights of " << g.n << " nodes, " << g.m()
                << " edges (dense " << g.n << " x " << g.n
                << " eigendecompositions; minutes for thousands of nodes)..." << std::endl;
    const auto t0 = std::chrono::steady_clock::now();
    auto last = t0;
    if (large)
      opt.on_iteration = [&](int it, double lower, double upper) {
        const auto now = std::chrono::steady_clock::now();
        if (std::chrono::duration<double>(now - last).count() < interval_s) return;
        last = now;
        std::cerr << "asf optimal: " << name << ": iteration " << it << ", optimum in ["
                  << std::setprecision(6) << lower << ", " << upper << "], relative gap "
                  << std::setprecision(2) << (upper > 0 ? (upper - lower) / upper : 0) << ", "
                  << std::setprecision(3) << std::chrono::duration<double>(now - t0).count() << " s"
                  << std::endl;
      };
    const graph::OptimalDesign r = graph::optimalDesign(g, p, opt);
    if (large)
      std::cerr << "asf optimal: " << name << " done: " << r.iterations << " iterations, "
                << std::setprecision(3) << r.time_ms / 1000 << " s" << std::endl;
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
         << std::setprecision(2) << 100 * eff << "%" << std::defaultfloat << "  (" << r.iterations
         << " iterations, " << std::setprecision(3) << r.time_ms << " ms)\n"
         << "  weights:" << std::setprecision(6);
    for (int e = 0; e < r.weights.size(); ++e) text << " " << r.weights[e];
    text << "\n" << std::setprecision(8);
    out.push_back(r.weights);
  }
  return out;
}

// The bounded-noise model of a pose graph (eqs. 5.52-5.53): Sigma^-1 and the alpha_j.
void describeNoise(const graph::GraphFile& l, bool unit, graph::NoiseReference reference,
                   nlohmann::json& j, std::ostream& text) {
  const graph::BoundedNoise& b = *l.noise;
  std::vector<double> a = b.alpha, sh = b.sharpness;
  std::sort(a.begin(), a.end());
  std::sort(sh.begin(), sh.end());
  const Eigen::Vector3d ref = b.reference.diagonal();
  j["edge_information"] = {{"model", unit ? "unit" : "bounded"},
                           {"reference", graph::noiseReferenceName(reference)},
                           {"sigma_inverse", {ref[0], ref[1], ref[2]}},
                           {"alpha", b.alpha},
                           {"alpha_min", a.front()},
                           {"alpha_median", a[a.size() / 2]},
                           {"alpha_max", a.back()},
                           {"sharpness_median", sh[sh.size() / 2]}};
  text << "edge information: " << (unit ? "unit (every alpha_j = 1)" : "bounded noise (eq. 5.53)")
       << ", Sigma^-1 = diag(" << ref[0] << ", " << ref[1] << ", " << ref[2] << ") ("
       << graph::noiseReferenceName(reference) << "); alpha min " << a.front() << " median "
       << a[a.size() / 2] << " max " << a.back() << "; sharpness median " << sh[sh.size() / 2]
       << "\n";
}

// Theorem 5.2.1 and eq. 5.54 on the pose graph: exact information, edge sum, bound.
void theoremTable(const graph::GraphFile& l, const std::vector<double>& ps, nlohmann::json& j,
                  std::ostream& text) {
  text << "theorem 5.2.1 / eq. 5.54: ||J^T Omega J||_p (exact), ||sum E_j (x) Sigma_j^-1||_p "
          "(edge sum), ||L_alpha||_p ||Sigma^-1||_p (bound)\n";
  for (double p : ps) {
    const std::string name = graph::criterionName(p);
    try {
      const graph::TheoremCheck c = graph::checkTheorem(*l.pose_graph, *l.noise, p);
      j["theorem"][name] = {{"exact", c.exact}, {"edge_sum", c.edge_sum}, {"bound", c.bound}};
      text << "  " << name << ": exact " << c.exact << "  edge sum " << c.edge_sum << "  bound "
           << c.bound << "  (edge sum / bound " << c.edge_sum / c.bound << ", exact / edge sum "
           << c.exact / c.edge_sum << ")\n";
    } catch (const InputError& e) {
      j["theorem"][name] = nullptr;
      text << "  " << name << ": skipped (" << e.what() << ")\n";
    }
  }
}

void exhaustive(const graph::Multigraph& g, const std::vector<double>& ps, int max_d,
                const std::string& kind, std::optional<int> start, const std::string& plot,
                const std::string& title, nlohmann::json& j, std::ostream& text) {
  graph::ExhaustiveOptions eo;
  eo.max_d = max_d;
  eo.kind = kind == "multiset" ? graph::TraversalKind::Multiset
            : kind == "closed" ? graph::TraversalKind::ClosedWalk
                               : graph::TraversalKind::Walk;
  if (start) {
    if (*start < 1 || *start > g.n)
      throw InputError("--start " + std::to_string(*start) + ": nodes are 1.." +
                       std::to_string(g.n));
    eo.start = *start - 1;
  }
  eo.criteria = ps;
  const graph::ExhaustiveResult ex = graph::exhaustiveSearch(g, eo);
  nlohmann::json jx;
  jx["kind"] = kind;
  jx["d"] = ex.d;
  jx["candidates"] = ex.candidates;
  text << "exhaustive search (" << kind << "s), best information / rate per d:\n"
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
  if (!plot.empty()) {
    std::vector<double> optimum;
    for (double p : ex.criteria)
      optimum.push_back(j["optimum"][graph::criterionName(p)].get<double>());
    graph::writeExhaustiveSvg(ex, plot, title, optimum);
    text << "plot: " << plot << "\n";
  }
}

/// What `asf optimal` was asked, from its command line.
struct OptimalRequest {
  std::string path, criteria = "D,A,E";
  bool index_set = false;
  int index = 0;
  bool unit = false;
  std::string reference = "median";
  bool theorem = false;
  double tolerance = 0, progress_interval = 5;
  int walks = 0;
  std::string walk_kind = "walk";
  std::optional<int> start;
  std::string plot, draw;
  bool json = false;
};

int runOptimal(const OptimalRequest& rq) {
  if (!(rq.progress_interval >= 0)) throw InputError("--progress-interval must be >= 0 seconds");
  if (!rq.plot.empty() && rq.walks <= 0)
    throw InputError("--plot draws the exhaustive search: give --walks D too");
  const auto ps = parseCriteria(rq.criteria);
  const std::string& path = rq.path;
  const bool unit = rq.unit;
  const graph::NoiseReference ref = graph::parseNoiseReference(rq.reference, "--noise-reference");
  const std::optional<int> line_asked = rq.index_set ? std::optional<int>(rq.index) : std::nullopt;
  const graph::GraphFile l = graph::readGraphFile(path, line_asked, unit, ref);
  if (rq.theorem && !l.pose_graph)
    throw InputError(path + ": --theorem needs a pose graph (a .g2o file or a run directory)");
  const graph::Multigraph& g = l.g;
  const int line = l.line;
  nlohmann::json j = {{"file", path},
                      {"index", line ? nlohmann::json(line) : nullptr},
                      {"n", g.n},
                      {"m", g.m()},
                      {"connected", g.connected()}};
  std::ostringstream text;
  text << std::setprecision(8) << path << (line ? ":" + std::to_string(line) : "") << ": " << g.n
       << " nodes, " << g.m() << " edges, " << (g.connected() ? "connected" : "NOT connected")
       << "\n";
  if (l.noise) describeNoise(l, unit, ref, j, text);
  const auto weights = designs(g, ps, rq.tolerance, rq.progress_interval, j, text);
  if (rq.theorem) theoremTable(l, ps, j, text);
  if (rq.walks > 0) exhaustive(g, ps, rq.walks, rq.walk_kind, rq.start, rq.plot, path, j, text);
  if (!rq.draw.empty()) {
    std::vector<graph::WeightPanel> panels;
    for (std::size_t c = 0; c < ps.size(); ++c)
      panels.push_back({graph::criterionName(ps[c]) + "-optimal weights", weights[c]});
    const auto pos = l.positions.empty() ? graph::stressLayout(g) : l.positions;
    graph::writeWeightsSvg(g, pos, panels, path + (line ? ":" + std::to_string(line) : ""),
                           rq.draw);
    text << "drawing: " << rq.draw << "\n";
  }
  if (rq.json)
    std::cout << j.dump(2) << "\n";
  else
    std::cout << text.str();
  return kOk;
}

/// asf optimal's options, added to `cmd` in declaration order (--help's order depends on it).
struct OptimalArgs {
  explicit OptimalArgs(TCLAP::CmdLine& parser) : cmd(parser) {}

  TCLAP::CmdLine& cmd;
  TCLAP::UnlabeledValueArg<std::string> file{
      "graph", "Graph list, g2o file, run directory or topology.json", true, "", "GRAPH", cmd};
  TCLAP::ValueArg<std::string> criteria{"c", "criteria",
                                        "Comma-separated criteria: T, D, A, E or numbers p <= 1",
                                        false, "D,A,E", "LIST", cmd};
  TCLAP::ValueArg<int> index{"i", "index", "Line number (1-based) of the graph in a graph list",
                             false, 0, "K", cmd};
  TCLAP::ValueArg<double> tolerance{
      "t", "tolerance", "Target relative gap (default 5e-7 smooth criteria, 5e-6 for E)", false,
      0.0, "TOL", cmd};
  TCLAP::SwitchArg json{"j", "json",
                        "Print one JSON object: file, index, n, m, connected, optimum, "
                        "upper_bound, gap, relative_gap, converged, weights, efficiency.uniform, "
                        "iterations, time_ms (each keyed by criterion name); pose graphs add "
                        "edge_information and, with --theorem, theorem",
                        cmd};
  std::vector<std::string> models{"bounded", "unit"};
  TCLAP::ValuesConstraint<std::string> model_c{models};
  TCLAP::ValueArg<std::string> model{
      "", "edge-information",
      "Pose graphs: bounded (alpha_j from each edge's information, eq. 5.53) or unit (every "
      "alpha_j = 1, as if all edges had the same noise: Corollary 5.2.2)",
      false, "bounded", &model_c, cmd};
  std::vector<std::string> refs{"median", "identity"};
  TCLAP::ValuesConstraint<std::string> ref_c{refs};
  TCLAP::ValueArg<std::string> reference{
      "", "noise-reference",
      "The common Sigma^-1 of eq. 5.52, diag(a, a, c): median (a, c the medians of the edges' "
      "translation and rotation information) or identity (a = c, eq. 5.55)",
      false, "median", &ref_c, cmd};
  TCLAP::SwitchArg theorem{"", "theorem",
                           "Pose graphs: ||.||_p of the exact information, of Theorem 5.2.1's "
                           "edge sum and of the bound of eq. 5.54 (D at any size, other "
                           "criteria up to 1000 poses)",
                           cmd};
  TCLAP::ValueArg<int> walks{"w", "walks", "Exhaustive search of every traversal of d = 1..D edges",
                             false, 0, "D", cmd};
  std::vector<std::string> kinds{"walk", "closed", "multiset"};
  TCLAP::ValuesConstraint<std::string> kind_c{kinds};
  TCLAP::ValueArg<std::string> kind{
      "", "walk-kind",
      "walk: edge sequences of walks (figs 5.8-5.10); closed: walks back to their start; "
      "multiset: any d edges (figs 5.6, 5.7)",
      false, "walk", &kind_c, cmd};
  TCLAP::ValueArg<int> start{"", "start", "Walks start at this node (1-based; default any)", false,
                             0, "NODE", cmd};
  TCLAP::ValueArg<std::string> plot{"p", "plot",
                                    "SVG of the exhaustive search: information and rate vs d, "
                                    "with the relaxed optima dashed",
                                    false, "", "FILE.svg", cmd};
  TCLAP::ValueArg<std::string> draw{
      "", "draw",
      "SVG of the optimal weights on the graph, one panel per criterion, edge width "
      "proportional to the weight (figs. 5.11-5.13); nodes at their poses or region centroids, "
      "else laid out by stress majorization",
      false, "", "FILE.svg", cmd};
  TCLAP::ValueArg<double> progress_interval{
      "", "progress-interval",
      "Graphs of 500 nodes or more: seconds between progress lines on stderr while a "
      "criterion is solved (0: every iteration)",
      false, 5.0, "S", cmd};
};

/// What the parsed command line asks.
OptimalRequest optimalRequest(const OptimalArgs& a) {
  OptimalRequest rq;
  rq.path = a.file.getValue();
  rq.criteria = a.criteria.getValue();
  rq.index_set = a.index.isSet();
  rq.index = a.index.getValue();
  rq.unit = a.model.getValue() == "unit";
  rq.reference = a.reference.getValue();
  rq.theorem = a.theorem.isSet();
  rq.tolerance = a.tolerance.getValue();
  rq.progress_interval = a.progress_interval.getValue();
  rq.walks = a.walks.getValue();
  rq.walk_kind = a.kind.getValue();
  if (a.start.isSet()) rq.start = a.start.getValue();
  rq.plot = a.plot.getValue();
  rq.draw = a.draw.getValue();
  rq.json = a.json.getValue();
  return rq;
}

}  // namespace

int cmdOptimal(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Certified optimal edge weights of a graph (thesis ch. 5): maximizes the normalised "
      "information ||L(x)||_p (power mean of the n-1 non-zero eigenvalues of L(x) = sum_j "
      "x_j alpha_j E_j) over the simplex sum x = 1, x >= 0, and proves it with a dual upper "
      "bound. Prints the optimum (= the best information rate), the gap, the weights and the "
      "efficiency of traversing every edge once (uniform weights). GRAPH is a graph-list file "
      "(one graph per line, 'n m u1-v1 u2-v2 ...', 1-based ids; the first graph, or the one "
      "on line --index; alpha_j = 1), a g2o file (.g2o) or an asf run directory (its "
      "graph.g2o): one node per pose, one edge per measurement, alpha_j from the edge's "
      "information by the bounded-noise model (eqs. 5.52-5.54); or a topological graph (.json, "
      "as asf run and asf segment --graph write it: regions and their borders; alpha_j = 1). "
      "--theorem compares, on a pose graph, the exact information J^T Omega J with Theorem "
      "5.2.1's edge sum and the bound of eq. 5.54. --walks D also searches every traversal of "
      "1..D edges exhaustively (thesis figs. 5.6-5.10) and --plot draws best information and "
      "information rate vs d. --draw draws the optimal weights on the graph (figs. 5.11-5.13).",
      ' ', ASF_VERSION_STRING);
  OptimalArgs args(cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);

  return runOptimal(optimalRequest(args));
}

}  // namespace asf::app
