// The scheduler of `asf reproduce`: stages run as child processes (a stage's commands one
// after the other, each an exec of asf), `jobs` cores at a time, ready stages started in
// list order. A stage that finished writes OUT/<id>/done.json with the settings it depends on,
// so a rerun under the same ones keeps it (resume after Ctrl-C or a failure).
#include "reproduce_runner.h"

#include <asf/errors.h>
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

namespace asf::reproduce {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

volatile std::sig_atomic_t g_interrupted = 0;  ///< the signal that stopped the run (0: none)
void onInterrupt(int signo) { g_interrupted = signo; }

std::string minutes(double seconds) {
  char b[32];
  const int s = static_cast<int>(seconds + 0.5);
  std::snprintf(b, sizeof b, "%d:%02d", s / 60, s % 60);
  return b;
}

/// Runs one command with stdout to `out_path` and stderr to `log_fd`; its exit code, or -1
/// when it could not start.
int runCommand(const std::vector<std::string>& argv, const std::string& out_path, int log_fd) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const pid_t pid = fork();
  if (pid < 0) return -1;
  if (pid == 0) {
    const int out =
        out_path.empty() ? log_fd : open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (out < 0) _exit(126);
    dup2(out, STDOUT_FILENO);
    dup2(log_fd, STDERR_FILENO);
    execvp(args[0], args.data());
    std::fprintf(stderr, "cannot run %s: %s\n", args[0], std::strerror(errno));
    _exit(127);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + WTERMSIG(status);
}

/// The body of a stage's child process: its commands in order; 0 when all succeeded.
int runStageProcess(const Stage& st, const Settings& s) {
  const std::string dir = s.out + "/" + st.id;
  const int log_fd = open((dir + "/stage.log").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (log_fd < 0) return 1;
  auto log = [&](const std::string& text) { (void)!::write(log_fd, text.data(), text.size()); };
  std::ofstream(dir + "/settings.txt") << stageSettings(s, st) << "\n";
  const auto t0 = Clock::now();
  for (const Command& c : st.commands) {
    if (g_interrupted) return 128 + g_interrupted;
    std::vector<std::string> argv;
    try {
      argv = c.argv();
    } catch (const std::exception& e) {
      log(std::string("error: ") + e.what() + "\n");
      return 1;
    }
    if (!argv.empty() && argv[0] == "asf") argv[0] = s.asf;
    std::string line = "$";
    for (const auto& a : argv) line += " " + a;
    log(line + (c.stdout_file.empty() ? "" : " > " + c.stdout_file) + "\n");
    const int rc = runCommand(argv, c.stdout_file.empty() ? "" : dir + "/" + c.stdout_file, log_fd);
    if (rc != 0) {
      log("exit code " + std::to_string(rc) + "\n");
      if (g_interrupted) return 128 + g_interrupted;
      return rc == 130 || rc == 143 ? rc : (rc > 0 ? rc : 1);
    }
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  std::ofstream done(dir + "/done.json");
  done << nlohmann::json{{"settings", stageSettings(s, st)}, {"seconds", seconds}}.dump(1) << "\n";
  return done ? 0 : 1;
}

/// The last non-empty line of a stage's log (its command's progress), shortened.
std::string lastLogLine(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line)) {
    const auto cr = line.find_last_of('\r');  // progress lines rewritten in place
    if (cr != std::string::npos) line = line.substr(cr + 1);
    if (line.find_first_not_of(" \t") != std::string::npos) last = line;
  }
  return last.size() > 90 ? last.substr(0, 87) + "..." : last;
}

/// Marks the stages done before under the same settings (kept) and those missing an input
/// (skipped); returns how many were kept.
std::size_t markKeptAndMissing(const std::vector<Stage>& stages, const Settings& s,
                               std::vector<StageResult>& res) {
  std::size_t kept = 0;
  for (std::size_t i = 0; i < stages.size(); ++i) {
    const std::string dir = s.out + "/" + stages[i].id;
    fs::create_directories(dir);
    const std::string now = stageSettings(s, stages[i]);
    if (recordedSettings(s, stages[i]) == now) {
      res[i].status = StageResult::kReused;
      ++kept;
      continue;
    }
    // Begun under other settings: start afresh (an unfinished one under these resumes, e.g.
    // an experiment keeps its finished runs).
    std::ifstream begun(dir + "/settings.txt");
    std::string before;
    if (begun && std::getline(begun, before) && before != now) {
      std::cerr << "reproduce: " << stages[i].id << " was begun with '" << before
                << "'; doing it again with '" << now << "'\n";
      fs::remove_all(dir);
      fs::create_directories(dir);
    }
    for (const auto& f : stages[i].inputs)
      if (!fs::exists(f)) {
        res[i].status = StageResult::kSkipped;
        res[i].why = "needs " + f + ", which does not exist";
        break;
      }
    if (res[i].status == StageResult::kNotRun) fs::remove(dir + "/done.json");
  }
  return kept;
}

/// The stage's first prerequisite that failed or was skipped ("" when none); `ready` tells
/// whether all are done.
std::string blockedBy(const Stage& st, const std::map<std::string, std::size_t>& index,
                      const std::vector<StageResult>& res, bool& ready) {
  ready = true;
  for (const auto& a : st.after) {
    const auto it = index.find(a);
    if (it == index.end()) throw Error("reproduce: stage " + st.id + " waits for unknown " + a);
    const auto& r = res[it->second];
    if (r.status == StageResult::kFailed || r.status == StageResult::kSkipped)
      return "needs stage " + a + ", which " +
             (r.status == StageResult::kFailed ? "failed" : "was skipped");
    ready = ready && (r.status == StageResult::kDone || r.status == StageResult::kReused);
  }
  return "";
}

/// Forks the process that runs a stage, in its own process group.
pid_t startStage(const Stage& st, const Settings& s) {
  std::cout.flush();
  std::cerr.flush();
  const pid_t pid = fork();
  if (pid < 0) throw Error("reproduce: cannot start a process for stage " + st.id);
  if (pid == 0) {
    setpgid(0, 0);  // Ctrl-C reaches the stage through the parent only
    int rc = 1;
    try {
      rc = runStageProcess(st, s);
    } catch (const std::exception& e) {
      std::cerr << "reproduce: stage " << st.id << ": " << e.what() << "\n";
    }
    _exit(rc);
  }
  setpgid(pid, pid);
  std::cerr << "reproduce: started " << st.id << " (" << st.title << ")\n";
  return pid;
}

struct Running {
  std::size_t stage;
  Clock::time_point start;
};

void printRunning(const std::vector<Stage>& stages, const Settings& s,
                  const std::map<pid_t, Running>& running, double elapsed, std::size_t settled) {
  std::cerr << "reproduce: " << minutes(elapsed) << " elapsed, " << settled << "/" << stages.size()
            << " stages settled; running:";
  for (const auto& [p, r] : running)
    std::cerr << "\n  " << stages[r.stage].id << " ("
              << minutes(std::chrono::duration<double>(Clock::now() - r.start).count())
              << "): " << lastLogLine(s.out + "/" + stages[r.stage].id + "/stage.log");
  std::cerr << "\n";
}

}  // namespace

int interruptingSignal() { return g_interrupted; }

std::vector<StageResult> run(const std::vector<Stage>& stages, const Settings& s) {
  std::vector<StageResult> res(stages.size());
  std::map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < stages.size(); ++i) index[stages[i].id] = i;
  if (const std::size_t kept = markKeptAndMissing(stages, s, res))
    std::cerr
        << "reproduce: " << kept << " of " << stages.size()
        << " stages done before with these settings (kept; delete a stage's folder to redo it)\n";

  std::map<pid_t, Running> running;
  const int jobs = std::max(1, s.jobs);
  int free_slots = jobs;
  const auto t0 = Clock::now();
  auto last_report = t0;
  struct sigaction sa {
  }, old_sa{};
  sa.sa_handler = onInterrupt;
  sigemptyset(&sa.sa_mask);
  struct sigaction old_term {};
  sigaction(SIGINT, &sa, &old_sa);
  sigaction(SIGTERM, &sa, &old_term);  // a SIGTERM must not leave the stages running
  auto settled = [&](std::size_t i) { return res[i].status != StageResult::kNotRun; };
  std::size_t finished = 0;
  for (std::size_t i = 0; i < stages.size(); ++i) finished += settled(i);
  bool forwarded = false;
  for (;;) {
    if (g_interrupted && !forwarded) {  // each stage is its own process group: stop them all
      for (const auto& [pid, r] : running) kill(-pid, g_interrupted);
      forwarded = true;
    }
    // Skip the stages whose prerequisites failed or were skipped; start the ready ones.
    for (bool progress = true; progress;) {
      progress = false;
      for (std::size_t i = 0; i < stages.size() && !g_interrupted; ++i) {
        if (settled(i)) continue;
        bool ready = false;
        const std::string why = blockedBy(stages[i], index, res, ready);
        if (!why.empty()) {
          res[i] = {StageResult::kSkipped, 0, why};
          ++finished;
          progress = true;
          continue;
        }
        bool is_running = false;
        for (const auto& [pid, r] : running) is_running = is_running || r.stage == i;
        const int slots = std::min(stages[i].slots, jobs);
        if (!ready || is_running || slots > free_slots) continue;
        running[startStage(stages[i], s)] = {i, Clock::now()};
        free_slots -= slots;
        progress = true;
      }
    }
    if (running.empty()) break;
    int status = 0;
    const pid_t pid = waitpid(-1, &status, WNOHANG);
    if (pid > 0 && running.count(pid)) {
      const Running r = running[pid];
      running.erase(pid);
      const Stage& st = stages[r.stage];
      free_slots += std::min(st.slots, jobs);
      StageResult& out = res[r.stage];
      out.seconds = std::chrono::duration<double>(Clock::now() - r.start).count();
      const int rc = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      if (rc == 0) {
        out.status = StageResult::kDone;
        std::cerr << "reproduce: [" << ++finished << "/" << stages.size() << "] " << st.id
                  << " done in " << minutes(out.seconds) << "\n";
        continue;
      }
      out.status = g_interrupted ? StageResult::kNotRun : StageResult::kFailed;
      out.why = (g_interrupted ? "interrupted" : "exit code " + std::to_string(rc)) + "; see " +
                st.id + "/stage.log";
      finished += !g_interrupted;
      std::cerr << "reproduce: [" << finished << "/" << stages.size() << "] " << st.id
                << (g_interrupted ? " interrupted" : " FAILED") << " after " << minutes(out.seconds)
                << ": " << lastLogLine(s.out + "/" + st.id + "/stage.log") << "\n";
      continue;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    if (Clock::now() - last_report > std::chrono::seconds(60)) {
      last_report = Clock::now();
      printRunning(stages, s, running, std::chrono::duration<double>(last_report - t0).count(),
                   finished);
    }
  }
  sigaction(SIGINT, &old_sa, nullptr);
  sigaction(SIGTERM, &old_term, nullptr);
  for (std::size_t i = 0; i < stages.size(); ++i)
    if (res[i].status == StageResult::kNotRun && res[i].why.empty())
      res[i].why = "interrupted before it started";
  return res;
}

}  // namespace asf::reproduce
