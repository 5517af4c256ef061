// asf experiment --backend slurm on the host's side: submits the array the library wrote,
// follows it with squeue, cancels it on Ctrl-C, and lists failed tasks with their logs.
#include "experiment_slurm_host.h"

#include <asf/errors.h>
#include <asf/experiment_slurm.h>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <map>
#include <thread>

#include "process_launcher.h"

namespace asf::app {

namespace {

namespace fs = std::filesystem;

std::string runOrThrow(const std::vector<std::string>& argv) {
  std::string out;
  const int code = runCommand(argv, out);
  if (code != 0) {
    std::string cmd;
    for (const auto& a : argv) cmd += (cmd.empty() ? "" : " ") + a;
    throw Error(cmd + ": " + (code < 0 ? out : "exit status " + std::to_string(code) + ": " + out));
  }
  return out;
}

/// Polls squeue until the job has no task left in the queue (or `stop`), printing a line
/// whenever the counts change. A failing squeue is retried: a busy controller answers later.
void follow(const SlurmBatch& b, const std::string& job, double poll_s,
            const std::atomic<bool>& stop) {
  std::string last;
  int failures = 0;
  for (;;) {
    std::string out;
    const int code = runCommand({"squeue", "-h", "-r", "-j", job, "-o", "%T"}, out);
    SlurmQueue q;
    if (code == 0) {
      failures = 0;
      q = parseSqueue(out);
    } else if (++failures > 10) {
      throw Error("squeue -j " + job + " failed 10 times in a row: " + out);
    }
    const std::size_t ended = slurmTasksEnded(b);
    const std::string line = "slurm job " + job + ": " + std::to_string(ended) + "/" +
                             std::to_string(b.tasks.size()) + " ended, " +
                             std::to_string(q.running) + " running, " + std::to_string(q.pending) +
                             " pending";
    if (line != last) std::cout << line << std::endl;
    last = line;
    if (code == 0 && q.total() == 0) return;
    if (stop) return;
    std::this_thread::sleep_for(std::chrono::duration<double>(poll_s));
  }
}

}  // namespace

int runSlurmExperiment(const ExperimentConfig& cfg, const SlurmOptions& o, bool dry_run,
                       double poll_s, const std::string& asf_exe, const std::atomic<bool>& stop) {
  const SlurmBatch b = writeSlurmBatch(cfg, o, asf_exe);
  const std::size_t done = b.runs.size() - b.tasks.size();
  std::cout << "asf experiment: " << b.runs.size() << " runs, " << done << " finished earlier, "
            << b.tasks.size() << " to submit" << std::endl;
  if (b.tasks.empty()) return 0;
  std::cout << "asf experiment: array script " << b.script << std::endl;
  if (dry_run) {
    std::cout << "asf experiment: --dry-run: not submitted (sbatch --parsable " << b.script << ")"
              << std::endl;
    return 0;
  }
  const std::string job = parseSbatchJobId(runOrThrow(sbatchCommand(b)));
  std::cout << "asf experiment: submitted as Slurm job " << job << " (" << b.tasks.size()
            << " array tasks; logs in " << b.dir << "/logs)" << std::endl;
  follow(b, job, poll_s, stop);
  if (stop) {
    std::string out;
    runCommand({"scancel", job}, out);
    std::cout << "asf experiment: interrupted: scancel " << job
              << " (cancelled tasks keep what they wrote; run again to resubmit them)" << std::endl;
  }
  int failed = 0;
  const std::vector<ExperimentRun> runs = collectSlurmBatch(b);
  std::map<std::size_t, std::string> states;  // Slurm's word on the tasks, if it keeps accounts
  bool asked = false;
  for (std::size_t task = 0; task < b.tasks.size(); ++task) {
    const ExperimentRun& r = runs[b.tasks[task]];
    if (runFinished(r.dir)) continue;
    ++failed;
    if (!asked) {
      asked = true;
      std::string out;
      if (runCommand({"sacct", "-n", "-P", "-X", "-j", job, "-o", "JobID,State"}, out) == 0)
        states = parseSacctStates(out, job);
    }
    const auto st = states.find(task);
    std::cout << "asf experiment: " << r.policy << " seed " << r.seed << " (task " << task
              << ") did not finish"
              << (st != states.end() ? " (Slurm: " + st->second + ")" : std::string())
              << (r.exit_code >= 0 ? " (exit status " + std::to_string(r.exit_code) + ")"
                                   : " (no exit status: never ran, or killed by Slurm)")
              << "; logs: " << (fs::path(r.dir) / "run.log").string() << ", " << b.dir
              << "/logs/task_" << task << ".log" << std::endl;
  }
  return failed;
}

}  // namespace asf::app
