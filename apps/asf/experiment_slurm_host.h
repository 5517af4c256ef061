#pragma once
// asf experiment --backend slurm, the host's part (experiment_slurm_host.cpp).
#include <asf/experiment_slurm.h>

#include <atomic>
#include <string>

namespace asf::app {

/// Writes the array for cfg's unfinished runs, submits it (unless `dry_run`), follows it
/// every `poll_s` seconds until no task is queued or `stop`, then cancels it if stopped.
/// Returns the number of submitted runs that did not finish (each listed with its logs).
int runSlurmExperiment(const ExperimentConfig& cfg, const SlurmOptions& o, bool dry_run,
                       double poll_s, const std::string& asf_exe, const std::atomic<bool>& stop);

}  // namespace asf::app
