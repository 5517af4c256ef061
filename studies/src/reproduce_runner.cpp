// The scheduler of `asf reproduce`: a stage's commands run one after the other, each a
// process the host's ProcessRunner starts, `jobs` cores at a time, ready stages started in
// list order. A stage that finished writes OUT/<id>/done.json with the settings it depends on,
// so a rerun under the same ones keeps it (resume after Ctrl-C or a failure).
#include <asf/errors.h>
#include <asf/studies/reproduce.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <thread>

namespace asf::studies::reproduce {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

std::string minutes(double seconds) {
  char b[32];
  const int s = static_cast<int>(seconds + 0.5);
  std::snprintf(b, sizeof b, "%d:%02d", s / 60, s % 60);
  return b;
}

double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
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
                               std::vector<StageResult>& res, const Progress& progress) {
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
      progress("reproduce: " + stages[i].id + " was begun with '" + before +
               "'; doing it again with '" + now + "'");
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

/// The stages being run: each one's current command as a process.
class StageRunner {
 public:
  StageRunner(const std::vector<Stage>& stages, const Settings& s, ProcessRunner& runner,
              const Progress& progress, std::vector<StageResult>& res)
      : stages_(stages), s_(s), runner_(runner), progress_(progress), res_(res) {
    for (const auto& r : res_) settled_ += r.status != StageResult::kNotRun;
  }

  /// Starts stage i's first command; false when the stage already ended (failed to start,
  /// or had no command).
  bool start(std::size_t i);
  /// Marks stage i skipped.
  void skip(std::size_t i, const std::string& why) {
    res_[i] = {StageResult::kSkipped, 0, why};
    ++settled_;
  }
  /// Moves the stages whose command ended on: their next command, done or failed. Returns
  /// the slots freed (0 when no stage ended).
  int reap(bool stopping);
  void interruptAll() {
    for (const auto& r : running_) runner_.interrupt(r.handle);
  }
  bool empty() const { return running_.empty(); }
  bool isRunning(std::size_t i) const {
    for (const auto& r : running_)
      if (r.stage == i) return true;
    return false;
  }
  int slots(std::size_t i) const { return std::min(stages_[i].slots, std::max(1, s_.jobs)); }
  void report(double elapsed) const;

 private:
  struct Running {
    std::size_t stage, command;
    long handle;
    Clock::time_point start;
  };
  std::string dir(std::size_t i) const { return s_.out + "/" + stages_[i].id; }
  void log(std::size_t i, const std::string& text) const {
    std::ofstream(dir(i) + "/stage.log", std::ios::app) << text;
  }
  std::string counter() {
    return "reproduce: [" + std::to_string(++settled_) + "/" + std::to_string(stages_.size()) +
           "] ";
  }
  /// Starts command k of stage i; false (the stage failed, said) when it could not.
  bool startCommand(std::size_t i, std::size_t k, Clock::time_point t0);
  /// Stage r.stage ended with its last command's `rc`; `complete`: that was its last command.
  void settle(const Running& r, int rc, bool complete, bool stopping);

  const std::vector<Stage>& stages_;
  const Settings& s_;
  ProcessRunner& runner_;
  const Progress& progress_;
  std::vector<StageResult>& res_;
  std::vector<Running> running_;
  std::size_t settled_ = 0;
};

bool StageRunner::start(std::size_t i) {
  std::ofstream(dir(i) + "/settings.txt") << stageSettings(s_, stages_[i]) << "\n";
  std::ofstream(dir(i) + "/stage.log", std::ios::trunc);
  progress_("reproduce: started " + stages_[i].id + " (" + stages_[i].title + ")");
  if (stages_[i].commands.empty()) {
    settle({i, 0, -1, Clock::now()}, 0, true, false);
    return false;
  }
  return startCommand(i, 0, Clock::now());
}

bool StageRunner::startCommand(std::size_t i, std::size_t k, Clock::time_point t0) {
  const Command& c = stages_[i].commands[k];
  std::vector<std::string> argv;
  std::string error;
  try {
    argv = c.argv();  // may read what an earlier command wrote
  } catch (const std::exception& e) {
    error = std::string("error: ") + e.what();
  }
  long handle = -1;
  if (error.empty()) {
    std::string line = "$";
    for (const auto& a : argv) line += " " + a;
    log(i, line + (c.stdout_file.empty() ? "" : " > " + c.stdout_file) + "\n");
    const std::string stage_log = dir(i) + "/stage.log";
    ProcessRunner::Redirect io{stage_log, true, ""};
    if (!c.stdout_file.empty()) io = {dir(i) + "/" + c.stdout_file, false, stage_log};
    handle = runner_.start(argv, io, error);
  }
  if (handle < 0) {
    log(i, error + "\n");
    res_[i] = {StageResult::kFailed, secondsSince(t0),
               error + "; see " + stages_[i].id + "/stage.log"};
    progress_(counter() + stages_[i].id + " FAILED: " + error);
    return false;
  }
  running_.push_back({i, k, handle, t0});
  return true;
}

int StageRunner::reap(bool stopping) {
  int freed = 0;
  for (std::size_t j = 0; j < running_.size();) {
    const std::optional<ProcessRunner::Exit> e = runner_.poll(running_[j].handle);
    if (!e) {
      ++j;
      continue;
    }
    const Running r = running_[j];
    running_.erase(running_.begin() + static_cast<std::ptrdiff_t>(j));
    const int rc = exitCode(*e);
    const bool complete = r.command + 1 == stages_[r.stage].commands.size();
    if (rc == 0 && !complete && !stopping) {
      if (startCommand(r.stage, r.command + 1, r.start)) continue;  // its slots stay taken
    } else {
      settle(r, rc, complete, stopping);
    }
    freed += slots(r.stage);
  }
  return freed;
}

void StageRunner::settle(const Running& r, int rc, bool complete, bool stopping) {
  const Stage& st = stages_[r.stage];
  StageResult& out = res_[r.stage];
  out.seconds = secondsSince(r.start);
  if (rc == 0 && complete) {
    std::ofstream done(dir(r.stage) + "/done.json");
    done << nlohmann::json{{"settings", stageSettings(s_, st)}, {"seconds", out.seconds}}.dump(1)
         << "\n";
    if (done) {
      out.status = StageResult::kDone;
      progress_(counter() + st.id + " done in " + minutes(out.seconds));
      return;
    }
    rc = 1;
    log(r.stage, "cannot write done.json\n");
  }
  if (stopping) {  // a command interrupted, or the stage stopped between two
    out.status = StageResult::kNotRun;
    out.why = "interrupted; see " + st.id + "/stage.log";
    progress_("reproduce: " + st.id + " interrupted after " + minutes(out.seconds));
    return;
  }
  log(r.stage, "exit code " + std::to_string(rc) + "\n");
  out.status = StageResult::kFailed;
  out.why = "exit code " + std::to_string(rc) + "; see " + st.id + "/stage.log";
  progress_(counter() + st.id + " FAILED after " + minutes(out.seconds) + ": " +
            lastLogLine(dir(r.stage) + "/stage.log"));
}

void StageRunner::report(double elapsed) const {
  std::string text = "reproduce: " + minutes(elapsed) + " elapsed, " + std::to_string(settled_) +
                     "/" + std::to_string(stages_.size()) + " stages settled; running:";
  for (const auto& r : running_)
    text += "\n  " + stages_[r.stage].id + " (" + minutes(secondsSince(r.start)) +
            "): " + lastLogLine(dir(r.stage) + "/stage.log");
  progress_(text);
}

}  // namespace

std::vector<StageResult> run(const std::vector<Stage>& stages, const Settings& s,
                             ProcessRunner& runner, const std::atomic<bool>& stop,
                             const Progress& progress) {
  std::vector<StageResult> res(stages.size());
  std::map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < stages.size(); ++i) index[stages[i].id] = i;
  if (const std::size_t kept = markKeptAndMissing(stages, s, res, progress))
    progress("reproduce: " + std::to_string(kept) + " of " + std::to_string(stages.size()) +
             " stages done before with these settings (kept; delete a stage's folder to redo it)");
  StageRunner running(stages, s, runner, progress, res);
  int free_slots = std::max(1, s.jobs);
  const auto t0 = Clock::now();
  auto last_report = t0;
  bool forwarded = false;
  for (;;) {
    const bool stopping = stop;
    if (stopping && !forwarded) {  // each command is its own process group: stop them all
      running.interruptAll();
      forwarded = true;
    }
    // Skip the stages whose prerequisites failed or were skipped; start the ready ones.
    for (bool again = true; again && !stopping;) {
      again = false;
      for (std::size_t i = 0; i < stages.size(); ++i) {
        if (res[i].status != StageResult::kNotRun || running.isRunning(i)) continue;
        bool ready = false;
        const std::string why = blockedBy(stages[i], index, res, ready);
        if (!why.empty()) {
          running.skip(i, why);
          again = true;
        } else if (ready && running.slots(i) <= free_slots) {
          if (running.start(i)) free_slots -= running.slots(i);
          again = true;
        }
      }
    }
    if (running.empty()) break;
    if (const int freed = running.reap(stopping)) {
      free_slots += freed;
      continue;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    if (Clock::now() - last_report > std::chrono::seconds(60)) {
      last_report = Clock::now();
      running.report(secondsSince(t0));
    }
  }
  for (std::size_t i = 0; i < stages.size(); ++i)
    if (res[i].status == StageResult::kNotRun && res[i].why.empty())
      res[i].why = "interrupted before it started";
  return res;
}

}  // namespace asf::studies::reproduce
