// asf experiment: its INI and the scheduler of its runs (started by the host's ProcessRunner).
#include <asf/config.h>
#include <asf/errors.h>
#include <asf/studies/experiment.h>
#include <asf/text.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include "experiment_runs.h"

namespace asf::studies {

namespace fs = std::filesystem;
using detail::number;
using detail::plannedRuns;
using detail::readSummary;
using detail::runStatus;
using nlohmann::json;

namespace {

const KeySpec kExperimentKeys[] = {
    keyPath("pipeline", nullptr, "Pipeline INI every run uses (relative to this INI's folder)"),
    keyString("policies", nullptr, "Policy plugins to compare, comma-separated"),
    keyInt("replications", "10", "Runs per policy (seeds first_seed, first_seed + 1, ...)", 1,
           100000),
    keyInt("first_seed", "1", "Seed of the first replication ([pipeline] seed)", 0, 2e9),
    keyInt("jobs", "0", "Runs at the same time; 0 = the number of cores", 0, 1024),
    keyPath("out", "",
            "Output folder (relative to this INI's folder); default results/<INI name> "
            "relative to the working folder"),
    keyString("overrides", "",
              "';'-separated section.key=value applied to every run (as asf run --set)"),
};

/// How long runs get after SIGINT to write their outputs before they are killed.
constexpr std::chrono::seconds kStopGrace{120};

/// The last non-empty line of a file (the error a failed run printed last).
std::string lastLine(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (!trim(line).empty()) last = trim(line);
  return last;
}

using SteadyClock = std::chrono::steady_clock;

/// Starts the runs not finished yet, at most `jobs` at a time, and reports each end.
class Scheduler {
 public:
  Scheduler(const ExperimentConfig& cfg, ProcessRunner& runner,
            const std::function<void(const std::string&)>& progress, const std::atomic<bool>* stop)
      : cfg_(cfg), runner_(runner), progress_(progress), stop_(stop) {}

  std::vector<ExperimentRun> run();

 private:
  struct Running {
    std::size_t run;
    long handle;
    SteadyClock::time_point t0;
  };
  void plan();
  /// Forwards a stop request to the running runs once, and kills them after the grace.
  void handleStop(bool stopping);
  void startMore();
  /// Reaps the runs that ended; true if any did.
  bool reap();
  std::string endLine(const ExperimentRun& run, const ProcessRunner::Exit& e, double secs) const;
  void say(const std::string& line) const {
    if (progress_) progress_(line);
  }
  std::string prefix() const {
    return "[" + std::to_string(done_) + "/" + std::to_string(runs_.size()) + "] ";
  }
  static std::string name(const ExperimentRun& r) {
    return r.policy + " seed " + std::to_string(r.seed);
  }

  const ExperimentConfig& cfg_;
  ProcessRunner& runner_;
  const std::function<void(const std::string&)>& progress_;
  const std::atomic<bool>* stop_;
  std::vector<ExperimentRun> runs_;
  std::vector<std::size_t> todo_;
  std::vector<Running> running_;
  std::size_t jobs_ = 1, next_ = 0, done_ = 0;
  bool forwarded_ = false, killed_ = false;
  SteadyClock::time_point stop_time_;
};

std::vector<ExperimentRun> Scheduler::run() {
  plan();
  while (true) {
    const bool stopping = stop_ && stop_->load();
    handleStop(stopping);
    if (!stopping) startMore();
    if (running_.empty() && (stopping || next_ >= todo_.size())) break;
    if (!reap()) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return runs_;
}

void Scheduler::plan() {
  runs_ = plannedRuns(cfg_);
  for (std::size_t i = 0; i < runs_.size(); ++i) {
    if (runFinished(runs_[i].dir)) {
      runs_[i].skipped = true;
      ++done_;
      say(prefix() + name(runs_[i]) + ": already finished, skipped");
    } else {
      todo_.push_back(i);
    }
  }
  jobs_ = cfg_.jobs > 0 ? static_cast<std::size_t>(cfg_.jobs)
                        : std::max<std::size_t>(1, std::thread::hardware_concurrency());
}

void Scheduler::handleStop(bool stopping) {
  if (stopping && !forwarded_) {
    forwarded_ = true;
    if (!running_.empty())
      say("interrupted: stopping " + std::to_string(running_.size()) +
          " running run(s); they write their outputs first");
    for (const auto& r : running_) runner_.interrupt(r.handle);
    stop_time_ = SteadyClock::now();
  }
  // A run that ignores SIGINT (hung in a plugin) must not keep the experiment forever.
  if (forwarded_ && !killed_ && SteadyClock::now() - stop_time_ > kStopGrace) {
    killed_ = true;
    for (const auto& r : running_) runner_.kill(r.handle);
  }
}

void Scheduler::startMore() {
  while (running_.size() < jobs_ && next_ < todo_.size()) {
    ExperimentRun& run = runs_[todo_[next_++]];
    std::error_code ec;
    fs::create_directories(run.dir, ec);
    if (ec) throw Error(run.dir + ": cannot create: " + ec.message());
    // A stale summary.json (interrupted, error) must not pass for this run's result.
    fs::remove(fs::path(run.dir) / "summary.json", ec);
    std::string error;
    const std::string log = (fs::path(run.dir) / "run.log").string();
    std::vector<std::string> argv{"asf"};
    for (auto& a : runArguments(cfg_, run)) argv.push_back(std::move(a));
    const long handle = runner_.start(argv, {log, false, ""}, error);
    if (handle < 0) {
      run.exit_code = 127;
      ++done_;
      say(prefix() + name(run) + ": " + error);
      continue;
    }
    running_.push_back({static_cast<std::size_t>(&run - runs_.data()), handle, SteadyClock::now()});
    say("started " + name(run) + " -> " + run.dir);
  }
}

bool Scheduler::reap() {
  bool reaped = false;
  for (auto it = running_.begin(); it != running_.end();) {
    const std::optional<ProcessRunner::Exit> e = runner_.poll(it->handle);
    if (!e) {
      ++it;
      continue;
    }
    reaped = true;
    ExperimentRun& run = runs_[it->run];
    const double secs = std::chrono::duration<double>(SteadyClock::now() - it->t0).count();
    ++done_;
    run.exit_code = exitCode(*e);
    say(prefix() + name(run) + ": " + endLine(run, *e, secs));
    it = running_.erase(it);
  }
  return reaped;
}

std::string Scheduler::endLine(const ExperimentRun& run, const ProcessRunner::Exit& e,
                               double secs) const {
  const std::string log = (fs::path(run.dir) / "run.log").string();
  using How = ProcessRunner::Exit::How;
  if (e.how == How::Lost) return "lost (" + e.error + ")";
  if (e.how == How::Signaled)
    return "killed by signal " + std::to_string(e.code) + " after " + formatFixed(secs, 1) + " s" +
           (killed_
                ? " (did not stop within " + std::to_string(kStopGrace.count()) + " s of SIGINT)"
                : "") +
           "; see " + log;
  std::string why;
  const json s = readSummary(run.dir, why);
  const std::string status = runStatus(s, why);
  if (status == "interrupted") return "interrupted after " + formatFixed(secs, 1) + " s";
  if (status != "finished")
    return "failed (exit " + std::to_string(run.exit_code) + ", " + status + ") after " +
           formatFixed(secs, 1) + " s: " + lastLine(log) + " (see " + log + ")";
  std::string line = "finished in " + formatFixed(secs, 1) + " s (";
  const double c = number(s, "coverage"), d = number(s, "distance_m");
  if (std::isfinite(c)) line += "coverage " + formatFixed(100 * c, 1) + "%, ";
  return line + "distance " + (std::isfinite(d) ? formatFixed(d, 1) : std::string("?")) + " m)";
}

}  // namespace

const KeySpec* experimentKeys(std::size_t& n) {
  n = sizeof kExperimentKeys / sizeof *kExperimentKeys;
  return kExperimentKeys;
}

ExperimentConfig readExperimentConfig(const std::string& ini_path) {
  const IniConfig ini = IniConfig::fromFile(ini_path);
  for (const auto& s : ini.sections())
    if (s != "experiment")
      throw ConfigError(
          ini.unknownSection(s, {"experiment"}, "an experiment INI has only [experiment]"));
  std::size_t n = 0;
  const KeySpec* keys = experimentKeys(n);
  const Params p = ini.resolve("experiment", keys, n);

  ExperimentConfig cfg;
  cfg.pipeline_ini = fs::absolute(p.getString("pipeline")).lexically_normal().string();
  std::error_code ec;
  if (!fs::is_regular_file(cfg.pipeline_ini, ec)) p.fail("pipeline", "no such file");

  cfg.policies = splitTrimmed(p.getString("policies"), ',');
  if (cfg.policies.empty()) p.fail("policies", "names no policy");
  std::set<std::string> seen;
  for (const auto& pol : cfg.policies) {
    if (pol.find_first_of("/\\ \t") != std::string::npos || pol == "." || pol == "..")
      p.fail("policies", "'" + pol + "' is not a plugin name");
    if (!seen.insert(pol).second) p.fail("policies", "'" + pol + "' appears twice");
  }
  cfg.replications = static_cast<int>(p.getInt("replications"));
  cfg.first_seed = static_cast<int>(p.getInt("first_seed"));
  cfg.jobs = static_cast<int>(p.getInt("jobs"));
  cfg.out_dir = p.getString("out");
  if (cfg.out_dir.empty()) cfg.out_dir = "results/" + fs::path(ini_path).stem().string();
  for (const auto& o : splitTrimmed(p.getString("overrides"), ';')) {
    const auto eq = o.find('='), dot = o.find('.');
    if (eq == std::string::npos || dot == std::string::npos || dot == 0 || dot + 1 >= eq)
      p.fail("overrides", "'" + o + "' is not section.key=value");
    cfg.overrides.push_back(o);
  }
  return cfg;
}

bool runFinished(const std::string& run_dir) {
  std::string why;
  return runStatus(readSummary(run_dir, why), why) == "finished";
}

std::vector<std::string> runArguments(const ExperimentConfig& cfg, const ExperimentRun& run) {
  std::vector<std::string> args{"run",   cfg.pipeline_ini,
                                "--out", run.dir,
                                "--set", "pipeline.policy=" + run.policy,
                                "--set", "pipeline.seed=" + std::to_string(run.seed)};
  for (const auto& o : cfg.overrides) {
    args.push_back("--set");
    args.push_back(o);
  }
  args.insert(args.end(), {"-v", "WARN"});
  return args;
}

std::vector<ExperimentRun> runExperiment(const ExperimentConfig& cfg, ProcessRunner& runner,
                                         const std::function<void(const std::string&)>& progress,
                                         const std::atomic<bool>* stop) {
  std::vector<ExperimentRun> runs = Scheduler(cfg, runner, progress, stop).run();
  summarizeExperiment(cfg);
  return runs;
}

}  // namespace asf::studies
