// asf recognition: place recognition by Monte Carlo ICP (thesis ch. 3.4.2) on every node of a
// SLAM run, from the nodes' own scans in the log the run read; Fig. 3.3 (the scatter of
// one node's samples) as SVG for the nodes asked.
#include <asf/atomic_file.h>
#include <asf/errors.h>
#include <asf/planning/place_recognition.h>
#include <asf/planning/unreliable_zone.h>
#include <asf/studies/recognition_figure.h>
#include <tclap/CmdLine.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "plugin_cli.h"

namespace asf::app {

namespace {

/// Mean, quartiles and the share of nodes at 0 and at 1 of the nodes with a scan.
nlohmann::json summary(const PoseGraph& g, const std::vector<double>& p) {
  std::vector<double> v;
  for (NodeId n = 0; n < g.size(); ++n)
    if (g.nodes[n].scan) v.push_back(p[n]);
  if (v.empty()) return {{"nodes", 0}};
  std::sort(v.begin(), v.end());
  double sum = 0;
  std::size_t zero = 0, one = 0;
  for (double x : v) {
    sum += x;
    zero += x == 0;
    one += x == 1;
  }
  auto q = [&](double f) { return v[static_cast<std::size_t>(f * (v.size() - 1))]; };
  return {{"nodes", v.size()}, {"mean", sum / v.size()}, {"q25", q(0.25)}, {"median", q(0.5)},
          {"q75", q(0.75)},    {"at_0", zero},           {"at_1", one}};
}

/// Thesis Fig. 3.3 for node n: scatter_<n>.svg in `dir`; its entry of recognition.json.
nlohmann::json writeScatter(const PoseGraph& g, unsigned n, const planning::RecognitionMcOptions& o,
                            const std::filesystem::path& dir) {
  const planning::RecognitionTrial t = planning::recognitionTrial(g, n, o);
  const std::string file = (dir / ("scatter_" + std::to_string(n) + ".svg")).string();
  std::ostringstream title;
  title << "Monte Carlo place recognition at node " << n << " (" << std::fixed
        << std::setprecision(2) << g.nodes[n].pose.x() << ", " << g.nodes[n].pose.y() << ")";
  writeFileAtomically(file, studies::recognitionScatterSvg(t, g.nodes[n], o, title.str()),
                      "scatter");
  std::size_t ok = 0;
  for (const auto& s : t.samples) ok += s.success;
  return {{"node", n}, {"p", t.p}, {"successes", ok}, {"file", file}};
}

void printSummary(const nlohmann::json& j, int samples, double seconds) {
  const auto& s = j["summary"];
  std::cout << std::fixed << std::setprecision(3) << "recognition: " << s["nodes"]
            << " nodes with a scan, " << samples << " samples each, " << seconds << " s\n";
  if (s["nodes"].get<std::size_t>() > 0)
    std::cout << "p_recognition: mean " << s["mean"].get<double>() << ", quartiles "
              << s["q25"].get<double>() << " / " << s["median"].get<double>() << " / "
              << s["q75"].get<double>() << "; " << s["at_0"] << " nodes at 0, " << s["at_1"]
              << " at 1\n";
  for (const auto& sc : j["scatter"])
    std::cout << "node " << sc["node"] << ": p " << sc["p"].get<double>() << " -> "
              << sc["file"].get<std::string>() << "\n";
}

/// asf recognition's options, added to `cmd` in declaration order (--help's order depends on it).
struct RecognitionArgs {
  explicit RecognitionArgs(TCLAP::CmdLine& parser) : cmd(parser) {}

  TCLAP::CmdLine& cmd;
  TCLAP::UnlabeledValueArg<std::string> graph{"graph", "The run's graph.g2o", true, "", "GRAPH.g2o",
                                              cmd};
  TCLAP::ValueArg<std::string> rawlog{"r", "rawlog", "The log the run read (the nodes' scans)",
                                      true, "", "FILE", cmd};
  TCLAP::ValueArg<std::string> keyframes{"k", "keyframes",
                                         "The run's keyframes.txt (default: beside the graph)",
                                         false, "", "FILE", cmd};
  TCLAP::ValueArg<std::string> label{"", "laser-label", "The run's [rawlog] laser_label", false, "",
                                     "LABEL", cmd};
  TCLAP::ValueArg<int> samples{"n", "samples", "ICP samples per node", false, 40, "N", cmd};
  TCLAP::ValueArg<double> radius{"", "map-radius", "Local map: other nodes' scans within [m]",
                                 false, 6.0, "M", cmd};
  TCLAP::ValueArg<double> window_xy{"", "window-xy", "Half size of the window in x, y [m]", false,
                                    0.3, "M", cmd};
  TCLAP::ValueArg<double> window_phi{"", "window-phi-deg", "Half size of the window [deg]", false,
                                     30, "DEG", cmd};
  TCLAP::ValueArg<double> success_xy{"", "success-xy",
                                     "A sample succeeds within this distance of the node [m]",
                                     false, 0.1, "M", cmd};
  TCLAP::ValueArg<double> success_phi{
      "", "success-phi-deg", "... and within this heading of the node [deg]", false, 5, "DEG", cmd};
  TCLAP::ValueArg<unsigned long> seed{"", "seed", "Seed of the draws", false, 1, "N", cmd};
  TCLAP::ValueArg<unsigned> threads{"j", "threads", "Threads (0: one per core)", false, 0, "N",
                                    cmd};
  TCLAP::MultiArg<unsigned> scatter{"s", "scatter", "Draw this node's samples (repeatable)", false,
                                    "NODE", cmd};
  TCLAP::ValueArg<std::string> out{"o", "out", "Output folder", false, "recognition", "DIR", cmd};
};

/// The Monte Carlo trials the options ask for; ConfigError for values out of range.
planning::RecognitionMcOptions recognitionOptions(const RecognitionArgs& a) {
  if (a.samples.getValue() < 1) throw ConfigError("--samples: at least 1");
  if (!(a.radius.getValue() > 0) || !(a.window_xy.getValue() >= 0) ||
      !(a.window_phi.getValue() >= 0))
    throw ConfigError("--map-radius must be > 0, --window-xy and --window-phi-deg >= 0");
  if (!(a.success_xy.getValue() > 0) || !(a.success_phi.getValue() > 0))
    throw ConfigError("--success-xy and --success-phi-deg must be > 0");
  planning::RecognitionMcOptions o;
  o.samples = a.samples.getValue();
  o.map_radius = a.radius.getValue();
  o.half_x = o.half_y = a.window_xy.getValue();
  o.half_phi = a.window_phi.getValue() * M_PI / 180;
  o.seed = a.seed.getValue();
  o.success_xy = a.success_xy.getValue();
  o.success_phi = a.success_phi.getValue() * M_PI / 180;
  return o;
}

}  // namespace

int cmdRecognition(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Place recognition by Monte Carlo ICP (thesis ch. 3.4.2) on the nodes of a SLAM run: "
      "each sample puts the robot anywhere in the localization window around the node, "
      "occludes a sector of the node's own scan and clutters a few rays, aligns it with ICP "
      "against the other nodes' scans within the map radius, and succeeds when ICP returns "
      "close to the node. Writes recognition.txt (node p, the planners' p_recognition_file), "
      "recognition.json and, for each --scatter node, Fig. 3.3 as scatter_<node>.svg.",
      ' ', ASF_VERSION_STRING);
  RecognitionArgs args(cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);

  const planning::RecognitionMcOptions o = recognitionOptions(args);

  const PoseGraph g = planning::readRunWithScans(args.graph.getValue(), args.keyframes.getValue(),
                                                 args.rawlog.getValue(), args.label.getValue());
  for (unsigned n : args.scatter.getValue())
    if (n >= g.size())
      throw ConfigError("--scatter " + std::to_string(n) + ": the graph has nodes 0.." +
                        std::to_string(g.size() - 1));
  std::filesystem::create_directories(args.out.getValue());
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<double> p = planning::recognitionProbabilities(
      g, o, args.threads.getValue(), [&](std::size_t k, std::size_t n) {
        std::cerr << "recognition: " << k << "/" << n << " nodes, " << std::setprecision(3)
                  << secondsSince(t0) << " s\n";
      });
  const double seconds = secondsSince(t0);
  std::map<NodeId, double> table;
  for (NodeId n = 0; n < g.size(); ++n) table[n] = p[n];
  const std::filesystem::path dir(args.out.getValue());
  planning::writeRecognitionProbabilities((dir / "recognition.txt").string(), table);

  nlohmann::json j{{"graph", args.graph.getValue()},
                   {"rawlog", args.rawlog.getValue()},
                   {"samples", o.samples},
                   {"map_radius", o.map_radius},
                   {"window_xy", o.half_x},
                   {"window_phi_deg", args.window_phi.getValue()},
                   {"success_xy", o.success_xy},
                   {"success_phi_deg", args.success_phi.getValue()},
                   {"seed", o.seed},
                   {"time_s", seconds},
                   {"summary", summary(g, p)},
                   {"scatter", nlohmann::json::array()}};
  for (unsigned n : args.scatter.getValue()) j["scatter"].push_back(writeScatter(g, n, o, dir));
  {
    const std::string file = (dir / "recognition.json").string();
    writeFileAtomically(file, j.dump(1) + "\n", "recognition summary");
  }
  printSummary(j, o.samples, seconds);
  std::cout << "wrote " << (dir / "recognition.txt").string() << "\n";
  return kOk;
}

}  // namespace asf::app
