// asf optimize: one back-end on one g2o file, timed; the command behind the back-end
// figures of docs/benchmarks/backends.md.
#include <asf/backend.h>
#include <asf/config.h>
#include <asf/errors.h>
#include <asf/pose_graph.h>
#include <asf/framework/registry.h>
#include <tclap/CmdLine.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "plugin_cli.h"

namespace asf::app {

namespace {

/// One timed optimization: chi2 before and after, the back-end's report, the seconds of
/// optimize() and of the marginals (< 0: not asked).
struct TimedOptimization {
  double chi2_before = 0, chi2_after = 0;
  OptimizeReport report;
  double time_s = 0, marginals_time_s = -1;
};

/// Optimizes g with the back-end `name`, timed; with `marginals` also times the recovery of
/// every node's marginal covariance.
TimedOptimization optimizeTimed(Backend& be, const std::string& name, PoseGraph& g,
                                const std::string& file, bool marginals) {
  TimedOptimization t;
  t.chi2_before = g.chi2();
  auto t0 = std::chrono::steady_clock::now();
  // A back-end's error is about this graph: it names the file (the mutation sweep found a
  // non-finite chi2 reported as "sparse_lm: ..." alone).
  const auto naming_file = [&](const Error& e) -> Error {
    return Error(file + ": " + e.what());
  };
  try {
    t.report = be.optimize(g);
  } catch (const Error& e) {
    throw naming_file(e);
  }
  t.time_s = secondsSince(t0);
  t.chi2_after = g.chi2();
  if (marginals) {
    t0 = std::chrono::steady_clock::now();
    Marginals m;
    try {
      m = be.marginals(g);
    } catch (const Error& e) {
      throw naming_file(e);
    }
    t.marginals_time_s = secondsSince(t0);
    if (m.node.size() != g.size())
      throw Error(name + ": marginals() returned " + std::to_string(m.node.size()) +
                  " blocks for " + std::to_string(g.size()) + " nodes");
  }
  return t;
}

void printOptimizeJson(const std::string& file, const std::string& name, const PoseGraph& g,
                       const TimedOptimization& t) {
  const OptimizeReport& r = t.report;
  nlohmann::json j = {{"file", file},
                      {"backend", name},
                      {"nodes", g.size()},
                      {"edges", g.edges.size()},
                      {"fixed", g.fixed.size()},
                      {"initial_chi2", t.chi2_before},
                      {"final_chi2", t.chi2_after},
                      {"iterations", r.iterations},
                      {"converged", r.converged},
                      {"time_s", t.time_s},
                      {"marginals_time_s", nullptr},
                      {"message", r.message}};
  if (t.marginals_time_s >= 0) j["marginals_time_s"] = t.marginals_time_s;
  std::cout << j.dump(2) << "\n";
}

void printOptimizeText(const std::string& file, const std::string& name, const PoseGraph& g,
                       const TimedOptimization& t, const std::string& output) {
  const OptimizeReport& r = t.report;
  std::cout << std::setprecision(10) << file << ": " << g.size() << " nodes, " << g.edges.size()
            << " edges";
  if (!g.fixed.empty()) std::cout << ", " << g.fixed.size() << " fixed";
  std::cout << "\n" << name << ": chi2 " << t.chi2_before << " -> " << t.chi2_after << " in "
            << r.iterations << " iterations, " << std::setprecision(4) << t.time_s << " s ("
            << (r.converged ? "converged" : "not converged") << ": " << r.message << ")\n";
  if (t.marginals_time_s >= 0)
    std::cout << "marginals: all " << g.size() << " node covariances in " << t.marginals_time_s
              << " s\n";
  if (!output.empty()) std::cout << "wrote " << output << "\n";
}

}  // namespace

int cmdOptimize(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Optimizes a 2D pose graph in g2o format (VERTEX_SE2, EDGE_SE2, FIX; without VERTEX "
      "lines the initial guess composes the odometry chain i -> i+1) with a back-end plugin. "
      "Prints chi2 (sum over edges of e^T Omega e, the g2o convention) before and after, "
      "iterations and the time of optimize(); --marginals also times the recovery of every "
      "node's marginal covariance.",
      ' ', ASF_VERSION_STRING);
  TCLAP::UnlabeledValueArg<std::string> file("file", "The g2o file", true, "", "FILE.g2o", cmd);
  TCLAP::ValueArg<std::string> backend("b", "backend", "Back-end plugin name", false,
                                       "sparse_lm", "NAME", cmd);
  TCLAP::SwitchArg marginals("m", "marginals", "Also compute (and time) all node marginals",
                             cmd);
  TCLAP::SwitchArg json("j", "json",
                        "Print one JSON object: nodes, edges, initial_chi2, final_chi2, "
                        "iterations, time_s, marginals_time_s (null without --marginals), ...",
                        cmd);
  TCLAP::ValueArg<std::string> output("o", "output", "Write the optimized graph (g2o)", false,
                                      "", "OUT.g2o", cmd);
  TCLAP::MultiArg<std::string> set(
      "s", "set", "Back-end key: key=value or <backend>.key=value (repeatable)", false,
      "KEY=VALUE", cmd);
  TCLAP::MultiArg<std::string> path("p", "plugin-path", "Extra plugin folder (repeatable)", false,
                                    "DIR", cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);

  framework::Registry reg;
  scanPlugins(reg, path.getValue());
  const auto info = reg.find(backend.getValue(), PluginKind::Backend);
  const std::string name = info->name();
  // The back-end's keys, validated like an INI section ([name] key = value).
  const Params params = setOverrides(set.getValue(), name, "back-end")
                            .resolve(name, info->descriptor->keys, info->descriptor->num_keys);
  auto be = framework::Registry::create<Backend>(info);
  framework::logPluginToStderr(*be, name);
  be->configure(params, PluginContext{});

  PoseGraph g = readG2o(file.getValue());
  const TimedOptimization t = optimizeTimed(*be, name, g, file.getValue(), marginals.getValue());
  if (!output.getValue().empty()) writeG2o(g, output.getValue());

  if (json.getValue())
    printOptimizeJson(file.getValue(), name, g, t);
  else
    printOptimizeText(file.getValue(), name, g, t, output.getValue());
  return kOk;
}

}  // namespace asf::app
