#pragma once
/// \file experiment.h
/// `asf experiment`: replications x policies of one exploration pipeline, run as separate
/// `asf run` processes (in parallel up to the core count), resumable, summarized as
/// tables (Markdown, CSV, JSON), plots over all runs and an HTML report.
///
/// INI: an [experiment] section (experimentKeys()); the pipeline INI it names is run with
/// `--set pipeline.policy=P --set pipeline.seed=S` plus the experiment's own overrides.
#include <asf/key_spec.h>
#include <asf/studies/process_runner.h>

#include <atomic>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace asf::studies {

const KeySpec* experimentKeys(std::size_t& n);

struct ExperimentConfig {
  std::string pipeline_ini;           ///< absolute path
  std::vector<std::string> policies;  ///< plugin names
  int replications = 10;
  int first_seed = 1;
  int jobs = 0;  ///< concurrent runs; 0 = number of cores
  std::string out_dir;
  std::vector<std::string> overrides;  ///< section.key=value, applied to every run
};

/// Reads the [experiment] section of `ini_path` (relative paths against the INI's folder).
/// Throws ConfigError naming the file, line and key.
ExperimentConfig readExperimentConfig(const std::string& ini_path);

struct ExperimentRun {
  std::string policy;
  int seed = 0;
  std::string dir;       ///< out_dir/<policy>/seed_<seed>
  bool skipped = false;  ///< already finished in an earlier invocation
  int exit_code = 0;
};

/// True when RUN_DIR/summary.json exists, parses and its stop_reason is neither
/// "interrupted" nor an error ("error..."): such a run is not run again.
bool runFinished(const std::string& run_dir);

/// The `asf` arguments of one run: `run INI --out DIR --set pipeline.policy=P --set
/// pipeline.seed=S`, the experiment's overrides, `-v WARN`.
std::vector<std::string> runArguments(const ExperimentConfig& cfg, const ExperimentRun& run);

/// Runs every (policy, seed) not finished yet as `asf ARGS` processes through `runner`, at
/// most `cfg.jobs` at a time, each with stdout and stderr in <run dir>/run.log; `progress` (may be empty) gets
/// one line per started, skipped or ended run. A run counts as finished as runFinished()
/// says. When `*stop` becomes true (the host's Ctrl-C handler), the running runs are
/// interrupted (they write their outputs and exit; killed after a grace period), no new run
/// starts, and what exists is still summarized (summarizeExperiment).
std::vector<ExperimentRun> runExperiment(const ExperimentConfig& cfg, ProcessRunner& runner,
                                         const std::function<void(const std::string&)>& progress,
                                         const std::atomic<bool>* stop = nullptr);

/// Reads the run folders of every configured (policy, seed) under cfg.out_dir and writes
/// summary.md, summary.csv, summary.json, coverage_vs_distance.svg,
/// error_per_distance_vs_distance.svg and report.html there. Means and sample standard
/// deviations are over a policy's finished runs (runFinished), per metric over the runs
/// that know it (n). Returns the Markdown table.
std::string summarizeExperiment(const ExperimentConfig& cfg);

}  // namespace asf::studies
