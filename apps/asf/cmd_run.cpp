#include <asf/pipeline.h>
#include <tclap/CmdLine.h>

#include <csignal>
#include <filesystem>
#include <iostream>

#include "commands.h"

namespace asf::app {

namespace {
std::atomic<bool> g_stop{false}, g_pause{false};
std::atomic<int> g_signal{0};
extern "C" void onSignal(int signo) {
  g_signal = signo;
  g_stop = true;
}
extern "C" void onPauseSignal(int) { g_pause = !g_pause.load(); }
}  // namespace

int cmdRun(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Runs the pipeline of CONFIG: source -> front-end -> back-end -> map -> segmenter -> "
      "topological graph -> policy, until the source ends, the policy is done or a budget is "
      "spent. Ctrl-C stops the run and still writes its outputs; SIGUSR1 (kill -USR1 PID) pauses "
      "it and a second SIGUSR1 resumes it.",
      ' ', ASF_VERSION_STRING);
  TCLAP::UnlabeledValueArg<std::string> config("config", "Pipeline INI file", true, "",
                                               "CONFIG.ini", cmd);
  TCLAP::ValueArg<std::string> out("o", "out", "Output folder (default: results/<config name>)",
                                   false, "", "DIR", cmd);
  TCLAP::MultiArg<std::string> set("s", "set", "Override a key: section.key=value (repeatable)",
                                   false, "section.key=value", cmd);
  std::vector<std::string> levels{"DEBUG", "INFO", "WARN", "ERROR"};
  TCLAP::ValuesConstraint<std::string> lv(levels);
  TCLAP::ValueArg<std::string> verb(
      "v", "verbosity",
      "Log level (overrides [pipeline] verbosity), on the console too. Without it (and without "
      "verbosity in the INI) the console shows warnings, errors and one progress line; every "
      "line goes to the output folder's run.log",
      false, "", &lv, cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);

  IniConfig ini = IniConfig::fromFile(config.getValue());
  for (const auto& s : set.getValue()) ini.applyOverride(s);
  if (!verb.getValue().empty()) ini.set("pipeline", "verbosity", verb.getValue(), "--verbosity");
  Registry reg;
  const ResolvedConfig rc = resolveConfig(ini, reg);

  std::string dir = out.getValue();
  if (dir.empty()) dir = "results/" + std::filesystem::path(config.getValue()).stem().string();
  Pipeline pipeline(rc, dir);

  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  std::signal(SIGUSR1, onPauseSignal);
  const RunSummary s = pipeline.run(&g_stop, &g_pause);
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  std::signal(SIGUSR1, SIG_DFL);

  std::cout << "asf run: " << s.stop_reason << " after " << s.steps << " steps, " << s.distance_m
            << " m, " << s.nodes << " nodes, " << s.edges << " edges, " << s.regions << " regions";
  if (s.final_pose_error_m >= 0)
    std::cout << ", final pose error " << s.final_pose_error_m << " m (mean " << s.mean_pose_error_m
              << " m)";
  if (s.ate_rmse_m >= 0)
    std::cout << ", ATE RMSE " << s.ate_rmse_m << " m (max " << s.ate_max_m << " m, " << s.ate_poses
              << " keyframes)";
  if (s.coverage >= 0) std::cout << ", coverage " << 100 * s.coverage << "%";
  std::cout << " in " << s.wall_time_s << " s\n";
  std::cout << "asf run: results in " << std::filesystem::absolute(dir).lexically_normal().string()
            << "/ (";
  const auto files = Pipeline::outputFiles();
  for (std::size_t i = 0; i < files.size(); ++i) std::cout << (i ? ", " : "") << files[i];
  std::cout << ")\n";
  const auto report = (std::filesystem::absolute(dir) / "report.html").lexically_normal();
  if (std::filesystem::exists(report)) std::cout << "asf run: report: " << report.string() << "\n";
  if (!s.output_errors.empty()) {
    std::cerr << "asf run: error: outputs not written: " << s.output_errors << "\n";
    return g_stop ? interruptedBy(g_signal) : kError;
  }
  return g_stop ? interruptedBy(g_signal) : kOk;
}

}  // namespace asf::app
