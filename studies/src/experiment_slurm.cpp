// asf experiment --backend slurm: the job array's script and the scheduler's outputs
// (asf/studies/experiment_slurm.h).
#include <asf/atomic_file.h>
#include <asf/errors.h>
#include <asf/studies/experiment_slurm.h>

#include <cctype>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "experiment_runs.h"

namespace asf::studies {

namespace fs = std::filesystem;

namespace {

void requireToken(const std::string& what, const std::string& value) {
  for (char c : value)
    if (std::isspace(static_cast<unsigned char>(c)) || c == '\'' || c == '"')
      throw ConfigError(what + " '" + value + "': no spaces or quotes allowed");
}

// A value as it can be shown in a message: control characters as \n, \t or \xNN.
std::string printable(const std::string& value) {
  std::string out;
  for (char c : value) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '\n') out += "\\n";
    else if (c == '\t') out += "\\t";
    else if (u < 0x20 || u == 0x7f) {
      const char* hex = "0123456789abcdef";
      out += std::string("\\x") + hex[u >> 4] + hex[u & 15];
    } else out += c;
  }
  return out;
}

// sbatch reads the #SBATCH lines itself, up to the first line that is not a comment: what goes
// into one must be a single word on a single line, or it would end the directives early or
// become a line of the script.
void requireDirectiveWord(const std::string& what, const std::string& value) {
  for (char c : value) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f || std::isspace(u) || c == '\'' || c == '"')
      throw ConfigError(what + " '" + printable(value) +
                        "': the Slurm backend writes it into #SBATCH lines, which allow no blanks, "
                        "quotes or control characters");
  }
}

// A Slurm job name from a folder name: letters, digits, '.', '_' and '-' kept, the rest '_'.
std::string jobName(const std::string& folder) {
  std::string n = "asf-";
  for (char c : folder) n += std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' ? c : '_';
  return n;
}

std::string exitCodeFile(const ExperimentRun& run) {
  return (fs::path(run.dir) / "exit_code").string();
}

std::string scriptText(const ExperimentConfig& cfg, const SlurmOptions& o, const SlurmBatch& b,
                       const std::string& asf_exe) {
  std::ostringstream s;
  // The directives first: sbatch stops reading them at the first line that is not a comment.
  s << "#!/bin/bash\n"
    << "#SBATCH --job-name=" << jobName(fs::path(cfg.out_dir).filename().string()) << "\n"
    << "#SBATCH --array=0-" << b.tasks.size() - 1;
  if (o.max_parallel > 0) s << "%" << o.max_parallel;
  s << "\n#SBATCH --output=" << b.dir << "/logs/task_%a.log\n"
    << "#SBATCH --cpus-per-task=1\n";
  if (!o.partition.empty()) s << "#SBATCH --partition=" << o.partition << "\n";
  if (!o.time_limit.empty()) s << "#SBATCH --time=" << o.time_limit << "\n";
  for (const auto& a : o.sbatch_args) s << "#SBATCH " << a << "\n";
  s << "# asf experiment --backend slurm: " << b.tasks.size() << " runs of "
    << printable(cfg.pipeline_ini) << "\n";  // escaped: never a line break
  s << "set -u\ncase \"${SLURM_ARRAY_TASK_ID:?not run as a Slurm array task}\" in\n";
  for (std::size_t i = 0; i < b.tasks.size(); ++i) {
    const ExperimentRun& run = b.runs[b.tasks[i]];
    s << "  " << i << ") dir=" << shellQuote(run.dir) << "; args=(" << shellQuote(asf_exe);
    for (const auto& a : runArguments(cfg, run)) s << " " << shellQuote(a);
    s << ") ;;\n";
  }
  s << "  *) echo \"asf: no task $SLURM_ARRAY_TASK_ID in this array\" >&2; exit 2 ;;\n"
    << "esac\n"
    << "mkdir -p \"$dir\" && rm -f \"$dir/summary.json\" \"$dir/exit_code\"\n"
    << "\"${args[@]}\" < /dev/null > \"$dir/run.log\" 2>&1\n"
    << "code=$?\n"
    << "echo \"$code\" > \"$dir/exit_code.tmp\" && mv \"$dir/exit_code.tmp\" \"$dir/exit_code\"\n"
    << "exit \"$code\"\n";
  return s.str();
}

std::string runOrThrow(ProcessRunner& runner, const std::vector<std::string>& argv) {
  std::string out;
  const int code = runner.run(argv, out);
  if (code != 0) {
    std::string cmd;
    for (const auto& a : argv) cmd += (cmd.empty() ? "" : " ") + a;
    throw Error(cmd + ": " + (code < 0 ? out : "exit status " + std::to_string(code) + ": " + out));
  }
  return out;
}

/// Polls squeue until the job has no task left in the queue (or `stop`), printing a line
/// whenever the counts change. A failing squeue is retried: a busy controller answers later.
void follow(const SlurmBatch& b, const std::string& job, double poll_s, ProcessRunner& runner,
            const std::function<void(const std::string&)>& progress, const std::atomic<bool>& stop) {
  std::string last;
  int failures = 0;
  for (;;) {
    std::string out;
    const int code = runner.run({"squeue", "-h", "-r", "-j", job, "-o", "%T"}, out);
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
    if (line != last && progress) progress(line);
    last = line;
    if (code == 0 && q.total() == 0) return;
    if (stop) return;
    std::this_thread::sleep_for(std::chrono::duration<double>(poll_s));
  }
}

}  // namespace

std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

SlurmBatch writeSlurmBatch(const ExperimentConfig& cfg_in, const SlurmOptions& o,
                           const std::string& asf_exe) {
  requireToken("--partition", o.partition);
  requireToken("--time", o.time_limit);
  if (o.max_parallel < 0) throw ConfigError("--max-parallel must be >= 0");
  for (const auto& a : o.sbatch_args) {
    if (a.rfind("--", 0) != 0)
      throw ConfigError("sbatch argument '" + a + "': expected an option starting with --");
    requireToken("sbatch argument", a);
  }
  // The compute nodes see absolute paths only.
  ExperimentConfig cfg = cfg_in;
  cfg.out_dir = fs::absolute(cfg.out_dir).lexically_normal().string();
  SlurmBatch b;
  b.dir = (fs::path(cfg.out_dir) / "slurm").string();
  requireDirectiveWord("--out", cfg.out_dir);  // in #SBATCH --output
  b.runs = detail::plannedRuns(cfg);
  for (std::size_t i = 0; i < b.runs.size(); ++i) {
    if (runFinished(b.runs[i].dir)) {
      b.runs[i].skipped = true;
      continue;
    }
    b.tasks.push_back(i);
    std::error_code ec;
    fs::remove(exitCodeFile(b.runs[i]), ec);
  }
  if (b.tasks.empty()) return b;
  std::error_code ec;
  fs::create_directories(fs::path(b.dir) / "logs", ec);
  if (ec) throw Error(b.dir + ": cannot create: " + ec.message());
  b.script = (fs::path(b.dir) / "array.sh").string();
  writeFileAtomically(b.script, scriptText(cfg, o, b, asf_exe), "Slurm array script");
  fs::permissions(b.script, fs::perms::owner_exec, fs::perm_options::add, ec);
  return b;
}

std::vector<std::string> sbatchCommand(const SlurmBatch& b) {
  return {"sbatch", "--parsable", b.script};
}

std::string parseSbatchJobId(const std::string& output) {
  std::istringstream in(output);
  std::string line;
  while (std::getline(in, line)) {
    const std::string id = line.substr(0, line.find(';'));
    if (!id.empty() && id.find_first_not_of("0123456789") == std::string::npos) return id;
  }
  throw Error("sbatch printed no job id: '" + output + "'");
}

SlurmQueue parseSqueue(const std::string& output) {
  SlurmQueue q;
  std::istringstream in(output);
  std::string state;
  while (in >> state) {
    if (state == "PENDING" || state == "CONFIGURING" || state == "REQUEUED")
      ++q.pending;
    else if (state == "RUNNING" || state == "COMPLETING")
      ++q.running;
    else
      ++q.other;
  }
  return q;
}

std::map<std::size_t, std::string> parseSacctStates(const std::string& output,
                                                    const std::string& job) {
  std::map<std::size_t, std::string> states;
  std::istringstream in(output);
  std::string line;
  const std::string prefix = job + "_";
  while (std::getline(in, line)) {
    const auto bar = line.find('|');
    if (bar == std::string::npos || line.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string task = line.substr(prefix.size(), bar - prefix.size());
    if (task.empty() || task.find_first_not_of("0123456789") != std::string::npos) continue;
    std::string state = line.substr(bar + 1);
    state = state.substr(0, state.find_first_of(" |"));
    states[std::stoul(task)] = state;
  }
  return states;
}

std::size_t slurmTasksEnded(const SlurmBatch& b) {
  std::size_t n = 0;
  for (std::size_t i : b.tasks) n += fs::exists(exitCodeFile(b.runs[i])) ? 1 : 0;
  return n;
}

std::vector<ExperimentRun> collectSlurmBatch(const SlurmBatch& b) {
  std::vector<ExperimentRun> runs = b.runs;
  for (std::size_t i : b.tasks) {
    std::ifstream in(exitCodeFile(runs[i]));
    int code = -1;
    if (!(in >> code)) code = -1;
    runs[i].exit_code = code;
  }
  return runs;
}

int runSlurmExperiment(const ExperimentConfig& cfg, const SlurmOptions& o, bool dry_run,
                       double poll_s, const std::string& asf_exe, ProcessRunner& runner,
                       const std::function<void(const std::string&)>& progress,
                       const std::atomic<bool>& stop) {
  auto say = [&](const std::string& line) {
    if (progress) progress(line);
  };
  const SlurmBatch b = writeSlurmBatch(cfg, o, asf_exe);
  const std::size_t done = b.runs.size() - b.tasks.size();
  say("asf experiment: " + std::to_string(b.runs.size()) + " runs, " + std::to_string(done) +
      " finished earlier, " + std::to_string(b.tasks.size()) + " to submit");
  if (b.tasks.empty()) return 0;
  say("asf experiment: array script " + b.script);
  if (dry_run) {
    say("asf experiment: --dry-run: not submitted (sbatch --parsable " + b.script + ")");
    return 0;
  }
  const std::string job = parseSbatchJobId(runOrThrow(runner, sbatchCommand(b)));
  say("asf experiment: submitted as Slurm job " + job + " (" + std::to_string(b.tasks.size()) +
      " array tasks; logs in " + b.dir + "/logs)");
  follow(b, job, poll_s, runner, progress, stop);
  if (stop) {
    std::string out;
    runner.run({"scancel", job}, out);
    say("asf experiment: interrupted: scancel " + job +
        " (cancelled tasks keep what they wrote; run again to resubmit them)");
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
      if (runner.run({"sacct", "-n", "-P", "-X", "-j", job, "-o", "JobID,State"}, out) == 0)
        states = parseSacctStates(out, job);
    }
    const auto st = states.find(task);
    say("asf experiment: " + r.policy + " seed " + std::to_string(r.seed) + " (task " +
        std::to_string(task) + ") did not finish" +
        (st != states.end() ? " (Slurm: " + st->second + ")" : std::string()) +
        (r.exit_code >= 0 ? " (exit status " + std::to_string(r.exit_code) + ")"
                          : " (no exit status: never ran, or killed by Slurm)") +
        "; logs: " + (fs::path(r.dir) / "run.log").string() + ", " + b.dir + "/logs/task_" +
        std::to_string(task) + ".log");
  }
  return failed;
}

}  // namespace asf::studies
