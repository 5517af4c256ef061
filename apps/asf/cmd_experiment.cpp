// asf experiment: replications x policies of one pipeline as parallel `asf run` processes,
// resumable, summarized as tables, plots and an HTML report (asf/studies/experiment.h).
#include <asf/abi.h>
#include <asf/config.h>
#include <asf/errors.h>
#include <asf/studies/experiment.h>
#include <asf/studies/experiment_slurm.h>
#include <asf/framework/pipeline.h>
#include <tclap/CmdLine.h>

#include <atomic>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>

#include "commands.h"
#include "process_launcher.h"

namespace asf::app {

namespace {

namespace fs = std::filesystem;

std::atomic<bool> g_stop{false};
std::atomic<int> g_signal{0};

void printLine(const std::string& line) { std::cout << line << std::endl; }

/// Resolves the pipeline once per policy with the experiment's overrides, so a typo in a
/// policy name or an override fails here with its message, not in every run's log.
void checkPipeline(const studies::ExperimentConfig& cfg) {
  for (const auto& p : cfg.policies) {
    IniConfig ini = IniConfig::fromFile(cfg.pipeline_ini);
    ini.set("pipeline", "policy", p, "[experiment] policies");
    ini.set("pipeline", "seed", std::to_string(cfg.first_seed), "[experiment] first_seed");
    for (const auto& o : cfg.overrides) ini.applyOverride(o);
    framework::Registry reg;
    try {
      framework::resolveConfig(ini, reg);
    } catch (const ConfigError& e) {
      throw ConfigError(std::string(e.what()) + "\n(pipeline " + cfg.pipeline_ini +
                        " with policy " + p + ")");
    }
  }
}

/// The local backend: the runs as processes here; the exit code of the command.
int runLocally(const studies::ExperimentConfig& cfg) {
  checkPipeline(cfg);
  const std::string exe = asfExecutable();
  std::cout << "asf experiment: " << cfg.policies.size() << " policies x " << cfg.replications
            << " replications of " << cfg.pipeline_ini << " into " << cfg.out_dir << "/"
            << std::endl;
  const int failed = withStopSignals(g_stop, g_signal, [&] {
    ProcessLauncher launcher(exe);
    int n = 0;
    for (const auto& r : studies::runExperiment(cfg, launcher, printLine, &g_stop))
      if (!r.skipped && r.exit_code != 0 && r.exit_code != interruptedBy(SIGINT) &&
          r.exit_code != interruptedBy(SIGTERM))
        ++n;
    return n;
  });
  std::cout << "\n";
  // runExperiment ended with summarizeExperiment, which wrote the table to summary.md.
  std::ifstream md(fs::path(cfg.out_dir) / "summary.md");
  std::cout << md.rdbuf();
  return g_stop ? interruptedBy(g_signal) : failed ? kError : kOk;
}

/// The Slurm backend: the unfinished runs as one job array, followed until it ends; the exit
/// code of the command. A dry run only writes the array script (kOk, no summary).
int runOnSlurm(const studies::ExperimentConfig& cfg, const studies::SlurmOptions& o, bool dry_run,
               double poll_s) {
  checkPipeline(cfg);
  const std::string exe = asfExecutable();
  const int failed = withStopSignals(g_stop, g_signal, [&] {
    ProcessLauncher launcher(exe);
    return studies::runSlurmExperiment(cfg, o, dry_run, poll_s, exe, launcher, printLine,
                                       g_stop);
  });
  if (dry_run) return kOk;
  std::cout << "\n" << studies::summarizeExperiment(cfg);
  return g_stop ? interruptedBy(g_signal) : failed ? kError : kOk;
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
      "--backend slurm submits the unfinished runs as one Slurm job array instead, follows "
      "it with squeue and summarizes the same way. See docs/EXPERIMENTS.md.",
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
  std::vector<std::string> backends{"local", "slurm"};
  TCLAP::ValuesConstraint<std::string> backend_values(backends);
  TCLAP::ValueArg<std::string> backend(
      "", "backend",
      "local: runs as processes on this machine; slurm: one sbatch job array (the output "
      "folder and asf on a filesystem the compute nodes share)",
      false, "local", &backend_values, cmd);
  TCLAP::ValueArg<std::string> partition("", "partition", "slurm: the partition", false, "", "P",
                                         cmd);
  TCLAP::ValueArg<std::string> time_limit("", "time", "slurm: time limit per run (Slurm format)",
                                          false, "", "T", cmd);
  TCLAP::ValueArg<int> max_parallel(
      "", "max-parallel", "slurm: array tasks running at once (0: no limit)", false, 0, "N", cmd);
  TCLAP::MultiArg<std::string> sbatch_arg(
      "", "sbatch-arg", "slurm: one more #SBATCH option, e.g. --mem=2G", false, "OPT", cmd);
  TCLAP::SwitchArg dry_run("", "dry-run", "slurm: write the array script, do not submit", cmd);
  TCLAP::ValueArg<double> poll("", "poll", "slurm: seconds between squeue calls", false, 5, "S",
                               cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);

  studies::ExperimentConfig cfg = studies::readExperimentConfig(config.getValue());
  if (!out.getValue().empty()) cfg.out_dir = out.getValue();
  if (jobs.isSet()) {
    if (jobs.getValue() < 0) throw ConfigError("--jobs must be >= 0");
    cfg.jobs = jobs.getValue();
  }

  const bool slurm = backend.getValue() == "slurm";
  if (!slurm && (partition.isSet() || time_limit.isSet() || max_parallel.isSet() ||
                 sbatch_arg.isSet() || dry_run.isSet() || poll.isSet()))
    throw ConfigError(
        "--partition, --time, --max-parallel, --sbatch-arg, --dry-run and --poll need "
        "--backend slurm");
  if (!(poll.getValue() > 0)) throw ConfigError("--poll must be > 0");
  int code = kOk;
  if (summarize_only.getValue()) {
    std::cout << studies::summarizeExperiment(cfg);
  } else if (slurm) {
    studies::SlurmOptions o;
    o.partition = partition.getValue();
    o.time_limit = time_limit.getValue();
    o.max_parallel = max_parallel.getValue();
    o.sbatch_args = sbatch_arg.getValue();
    code = runOnSlurm(cfg, o, dry_run.getValue(), poll.getValue());
    if (dry_run.getValue()) return code;  // nothing submitted: no report to point at
  } else {
    code = runLocally(cfg);
  }
  std::cout << "\nasf experiment: report in "
            << (fs::absolute(cfg.out_dir) / "report.html").lexically_normal().string()
            << " (summary.md, summary.csv, summary.json, *.svg beside it)\n";
  return code;
}

}  // namespace asf::app
