#pragma once
/// \file experiment_slurm.h
/// `asf experiment --backend slurm`: an experiment's unfinished runs as one Slurm job array.
///
/// The library writes the array's script, runs `sbatch`, `squeue`, `scancel` and `sacct`
/// through the host's ProcessRunner and reads what they print. Task i of the
/// array runs the i-th unfinished (policy, seed) with the local backend's command line
/// (runArguments), its stdout and stderr in the run folder's run.log and its exit status in
/// the run folder's exit_code; the scheduler's own log of the task goes to
/// <out>/slurm/logs/task_<i>.log. Nothing assumes that the submitting machine runs the tasks:
/// every path in the script is absolute, so the output folder and the asf installation must
/// be on a filesystem the compute nodes share (docs/EXPERIMENTS.md).
#include <asf/studies/experiment.h>

#include <atomic>
#include <cstddef>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace asf::studies {

struct SlurmOptions {
  std::string partition;   ///< --partition (empty: the cluster's default)
  std::string time_limit;  ///< --time per task, Slurm's format (empty: the partition's)
  int max_parallel = 0;    ///< tasks running at once (the array's %N; 0: no limit)
  std::vector<std::string> sbatch_args;  ///< more #SBATCH options, e.g. --mem=2G
};

struct SlurmBatch {
  std::string dir;     ///< <out>/slurm
  std::string script;  ///< <out>/slurm/array.sh (empty when nothing is left to run)
  /// Every configured run; `skipped` = finished earlier (runFinished), not in the array.
  std::vector<ExperimentRun> runs;
  std::vector<std::size_t> tasks;  ///< task i of the array runs runs[tasks[i]]
};

/// The unfinished runs of `cfg` and, if there are any, the array script for them, written
/// atomically; `asf_exe` is the absolute path of the asf binary the tasks run. A run's
/// old exit_code is removed (it is resubmitted). Throws ConfigError for options Slurm would
/// refuse (a partition or time with whitespace, a negative max_parallel, an sbatch argument
/// not starting with "--").
SlurmBatch writeSlurmBatch(const ExperimentConfig& cfg, const SlurmOptions& o,
                           const std::string& asf_exe);

/// `sbatch --parsable SCRIPT`.
std::vector<std::string> sbatchCommand(const SlurmBatch& b);

/// The job id `sbatch --parsable` printed ("123" or "123;cluster"); asf::Error quoting the
/// output when there is none.
std::string parseSbatchJobId(const std::string& output);

/// Tasks of a job by state, from `squeue -h -r -j ID -o %T` (one state per line).
struct SlurmQueue {
  int pending = 0, running = 0, other = 0;
  int total() const { return pending + running + other; }
};
SlurmQueue parseSqueue(const std::string& output);

/// Final states of the array's tasks from `sacct -n -P -X -j ID -o JobID,State` ("123_4|
/// TIMEOUT" lines; task 4 -> "TIMEOUT"; "CANCELLED by 0" -> "CANCELLED"); lines of other
/// jobs or without a task number are ignored. Empty when accounting is off.
std::map<std::size_t, std::string> parseSacctStates(const std::string& output,
                                                    const std::string& job);

/// After the array has left the queue: each task's run gets the exit status its script
/// wrote (-1 when it wrote none: the task never ran, or was killed by the scheduler).
/// Returns the batch's runs with exit codes; a task counts as done as runFinished() says.
std::vector<ExperimentRun> collectSlurmBatch(const SlurmBatch& b);

/// How many of the batch's tasks have written their exit status so far.
std::size_t slurmTasksEnded(const SlurmBatch& b);

/// Single-quotes `s` for bash ('\'' for each quote inside).
std::string shellQuote(const std::string& s);

/// `asf experiment --backend slurm`: writes the array for cfg's unfinished runs, submits it
/// through `runner` (sbatch) unless `dry_run`, follows it with squeue every `poll_s` seconds
/// until no task is queued or `stop`, then cancels it (scancel) if stopped; `progress` gets
/// the lines to show. Returns the number of submitted runs that did not finish (each named
/// with its logs). Throws asf::Error when sbatch fails or squeue fails 10 times in a row.
int runSlurmExperiment(const ExperimentConfig& cfg, const SlurmOptions& o, bool dry_run,
                       double poll_s, const std::string& asf_exe, ProcessRunner& runner,
                       const std::function<void(const std::string&)>& progress,
                       const std::atomic<bool>& stop);

}  // namespace asf::studies
