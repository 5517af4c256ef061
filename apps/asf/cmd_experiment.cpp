// asf experiment: replications x policies of one pipeline as parallel `asf run` processes,
// resumable, summarized as tables, plots and an HTML report (asf/experiment.h).
#include <asf/abi.h>
#include <asf/config.h>
#include <asf/errors.h>
#include <asf/experiment.h>
#include <asf/pipeline.h>
#include <tclap/CmdLine.h>

#include "process_launcher.h"

#include <atomic>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "commands.h"

namespace asf::app {

namespace {

namespace fs = std::filesystem;

std::atomic<bool> g_stop{false};
std::atomic<int> g_signal{0};
extern "C" void onExperimentSignal(int signo) {
  g_signal = signo;
  g_stop = true;
}

/// Resolves the pipeline once per policy with the experiment's overrides, so a typo in a
/// policy name or an override fails here with its message, not in every run's log.
void checkPipeline(const ExperimentConfig& cfg) {
  for (const auto& p : cfg.policies) {
    IniConfig ini = IniConfig::fromFile(cfg.pipeline_ini);
    ini.set("pipeline", "policy", p, "[experiment] policies");
    ini.set("pipeline", "seed", std::to_string(cfg.first_seed), "[experiment] first_seed");
    for (const auto& o : cfg.overrides) ini.applyOverride(o);
    Registry reg;
    try {
      resolveConfig(ini, reg);
    } catch (const ConfigError& e) {
      throw ConfigError(std::string(e.what()) + "\n(pipeline " + cfg.pipeline_ini +
                        " with policy " + p + ")");
    }
  }
}

}  // namespace

int cmdExperiment(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Runs every policy of an experiment INI's [experiment] section `replications` times "
      "(seeds first_seed, first_seed + 1, ...) on its pipeline, each run a separate "
      "`asf run` process with its log in <out>/<policy>/seed_<s>/run.log, `jobs` at a time. "
      "Runs finished earlier are skipped, so an interrupted experiment resumes. Then writes "
      "summary.md, summary.csv, summary.json, coverage_vs_distance.svg, "
      "error_per_distance_vs_distance.svg and report.html into the output folder and prints "
      "the table. Ctrl-C stops the running runs (they keep their outputs) and still "
      "summarizes. Keys of [experiment]: pipeline, policies, replications (10), first_seed "
      "(1), jobs (0 = cores), out (results/<INI name>), overrides (section.key=value;...). "
      "See docs/EXPERIMENTS.md.",
      ' ', ASF_VERSION_STRING);
  TCLAP::UnlabeledValueArg<std::string> config("config", "Experiment INI file", true, "",
                                               "CONFIG.ini", cmd);
  TCLAP::ValueArg<std::string> out("o", "out", "Output folder (overrides [experiment] out)", false,
                                   "", "DIR", cmd);
  TCLAP::ValueArg<int> jobs("j", "jobs",
                            "Runs at the same time (overrides [experiment] jobs; 0 = cores)", false,
                            -1, "N", cmd);
  TCLAP::SwitchArg summarize_only("", "summarize-only",
                                  "Do not run anything: summarize the runs that exist", cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);

  ExperimentConfig cfg = readExperimentConfig(config.getValue());
  if (!out.getValue().empty()) cfg.out_dir = out.getValue();
  if (jobs.isSet()) {
    if (jobs.getValue() < 0) throw ConfigError("--jobs must be >= 0");
    cfg.jobs = jobs.getValue();
  }

  int code = kOk;
  if (summarize_only.getValue()) {
    std::cout << summarizeExperiment(cfg);
  } else {
    checkPipeline(cfg);
    std::error_code ec;
    const std::string exe = fs::read_symlink("/proc/self/exe", ec).string();
    if (ec) throw Error("/proc/self/exe: cannot find the asf binary: " + ec.message());

    std::cout << "asf experiment: " << cfg.policies.size() << " policies x " << cfg.replications
              << " replications of " << cfg.pipeline_ini << " into " << cfg.out_dir << "/"
              << std::endl;
    g_stop = false;
    std::signal(SIGINT, onExperimentSignal);
    std::signal(SIGTERM, onExperimentSignal);
    std::vector<ExperimentRun> runs;
    try {
      ProcessLauncher launcher(exe);
      runs = runExperiment(
          cfg, launcher, [](const std::string& line) { std::cout << line << std::endl; },
          &g_stop);
    } catch (...) {
      std::signal(SIGINT, SIG_DFL);
      std::signal(SIGTERM, SIG_DFL);
      throw;
    }
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
    std::size_t failed = 0;
    for (const auto& r : runs)
      if (!r.skipped && r.exit_code != 0 && r.exit_code != interruptedBy(SIGINT) &&
          r.exit_code != interruptedBy(SIGTERM))
        ++failed;
    std::cout << "\n";
    // runExperiment ended with summarizeExperiment, which wrote the table to summary.md.
    std::ifstream md(fs::path(cfg.out_dir) / "summary.md");
    std::cout << md.rdbuf();
    if (g_stop)
      code = interruptedBy(g_signal);
    else if (failed)
      code = kError;
  }
  std::cout << "\nasf experiment: report in "
            << (fs::absolute(cfg.out_dir) / "report.html").lexically_normal().string()
            << " (summary.md, summary.csv, summary.json, *.svg beside it)\n";
  return code;
}

}  // namespace asf::app
