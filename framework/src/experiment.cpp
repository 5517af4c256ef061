#include <asf/abi.h>
#include <asf/atomic_file.h>
#include <asf/config.h>
#include <asf/errors.h>
#include <asf/experiment.h>
#include <asf/run_report.h>
#include <asf/svg_plot.h>
#include <asf/text.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>

extern char** environ;

namespace asf {

namespace fs = std::filesystem;
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

std::vector<std::string> splitTrim(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, sep))
    if (!trim(item).empty()) out.push_back(trim(item));
  return out;
}

/// How long runs get after SIGINT to write their outputs before they are killed.
constexpr std::chrono::seconds kStopGrace{120};

std::string runDir(const ExperimentConfig& cfg, const std::string& policy, int seed) {
  return (fs::path(cfg.out_dir) / policy / ("seed_" + std::to_string(seed))).string();
}

/// summary.json of a run, or null with `why` set.
json readSummary(const std::string& dir, std::string& why) {
  const fs::path p = fs::path(dir) / "summary.json";
  std::ifstream in(p);
  if (!in) {
    why = "missing summary.json";
    return nullptr;
  }
  try {
    json j;
    in >> j;
    if (!j.is_object()) {
      why = "invalid summary.json (not an object)";
      return nullptr;
    }
    return j;
  } catch (const std::exception& e) {
    why = std::string("invalid summary.json (") + e.what() + ")";
    return nullptr;
  }
}

/// "finished", or why the run does not count (missing/invalid file, interrupted, error).
std::string runStatus(const json& s, const std::string& why) {
  if (s.is_null()) return why;
  if (!s.contains("stop_reason") || !s["stop_reason"].is_string())
    return "invalid summary.json (no stop_reason)";
  const std::string r = s["stop_reason"].get<std::string>();
  if (r == "interrupted" || r.rfind("error", 0) == 0) return r;
  return "finished";
}

double number(const json& s, const char* key) {
  if (!s.is_object() || !s.contains(key) || !s[key].is_number()) return NAN;
  return s[key].get<double>();
}

/// The last non-empty line of a file (the error a failed run printed last).
std::string lastLine(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (!trim(line).empty()) last = trim(line);
  return last;
}

pid_t spawnRun(const std::vector<std::string>& args, const std::string& log, std::string& error) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawnattr_t at;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  posix_spawnattr_init(&at);
  // Own process group: a terminal's Ctrl-C reaches only the experiment, which forwards one
  // SIGINT to each child. Default SIGINT/SIGTERM dispositions: asf run installs its own.
  sigset_t def, none;
  sigemptyset(&def);
  sigaddset(&def, SIGINT);
  sigaddset(&def, SIGTERM);
  sigemptyset(&none);
  posix_spawnattr_setsigdefault(&at, &def);
  posix_spawnattr_setsigmask(&at, &none);
  posix_spawnattr_setpgroup(&at, 0);
  posix_spawnattr_setflags(&at,
                           POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, argv[0], &fa, &at, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  posix_spawnattr_destroy(&at);
  if (rc != 0) {
    error = args[0] + ": cannot start: " + std::strerror(rc);
    return -1;
  }
  return pid;
}

struct Stat {
  double mean = NAN, std = NAN;
  std::size_t n = 0;
};

Stat stat(const std::vector<double>& v) {
  Stat s;
  s.n = v.size();
  if (v.empty()) return s;
  double sum = 0;
  for (double x : v) sum += x;
  s.mean = sum / v.size();
  double ss = 0;
  for (double x : v) ss += (x - s.mean) * (x - s.mean);
  s.std = v.size() > 1 ? std::sqrt(ss / (v.size() - 1)) : 0;
  return s;
}

/// The metrics of the summary tables: key in summary.json, column title, scale, digits.
struct Metric {
  const char* key;
  const char* title;
  double scale;
  int digits;
};
const Metric kMetrics[] = {
    {"distance_m", "distance (m)", 1, 2},
    {"coverage", "coverage (%)", 100, 1},
    {"mean_pose_error_m", "mean pose error (m)", 1, 3},
    {"final_pose_error_m", "final pose error (m)", 1, 3},
    {"loop_closures", "loop closures", 1, 1},
    {"decision_ms_mean", "decision time (ms)", 1, 2},
    {"wall_time_s", "wall time (s)", 1, 1},
};

struct RunData {
  std::string policy;
  int seed = 0;
  std::string dir;
  std::string status;  ///< "finished" or why not
  json summary;        ///< null when missing/invalid
  bool ok() const { return status == "finished"; }
};

/// One run's curve: y(distance) from rows with both finite.
struct Curve {
  std::vector<double> d, y;
};

/// y at distance x by linear interpolation; before the first row NaN, after the last the
/// last value when `hold` (coverage stays what it was when the run ended) else NaN.
double at(const Curve& c, double x, bool hold) {
  if (c.d.empty() || x < c.d.front()) return NAN;
  if (x >= c.d.back()) return x == c.d.back() || hold ? c.y.back() : NAN;
  const std::size_t i = std::upper_bound(c.d.begin(), c.d.end(), x) - c.d.begin();
  const double d0 = c.d[i - 1], d1 = c.d[i];
  if (d1 <= d0) return c.y[i];
  return c.y[i - 1] + (c.y[i] - c.y[i - 1]) * (x - d0) / (d1 - d0);
}

/// Mean +- std band of several runs' curves on a common grid of distances.
plot::Series meanCurve(const std::string& label, const std::vector<Curve>& curves, bool hold,
                       double dmax) {
  plot::Series s;
  s.label = label;
  const int n = 101;
  for (int k = 0; k < n; ++k) {
    const double x = dmax * k / (n - 1);
    std::vector<double> v;
    for (const auto& c : curves) {
      const double y = at(c, x, hold);
      if (std::isfinite(y)) v.push_back(y);
    }
    const Stat st = stat(v);
    s.x.push_back(x);
    s.y.push_back(st.mean);
    s.y_low.push_back(st.n ? st.mean - st.std : NAN);
    s.y_high.push_back(st.n ? st.mean + st.std : NAN);
  }
  return s;
}

/// The coverage (%) and error-per-distance curves of a run's timeseries.csv; false when
/// the file is missing or unusable.
bool readCurves(const std::string& dir, Curve& coverage, Curve& epd) {
  std::map<std::string, std::vector<double>> ts;
  try {
    ts = report::readCsvColumns((fs::path(dir) / "timeseries.csv").string());
  } catch (const Error&) {
    return false;
  }
  if (!ts.count("distance_m")) return false;
  const auto& d = ts["distance_m"];
  const std::vector<double> none(d.size(), NAN);
  const auto& c = ts.count("coverage") ? ts["coverage"] : none;
  const auto& e = ts.count("pose_error_m") ? ts["pose_error_m"] : none;
  double last = -INFINITY;
  for (std::size_t i = 0; i < d.size(); ++i) {
    // Distance never decreases; a row that says otherwise is dropped, not interpolated.
    if (!std::isfinite(d[i]) || d[i] < last) continue;
    last = d[i];
    if (std::isfinite(c[i])) {
      coverage.d.push_back(d[i]);
      coverage.y.push_back(100 * c[i]);
    }
    if (std::isfinite(e[i]) && d[i] > 0) {
      epd.d.push_back(d[i]);
      epd.y.push_back(e[i] / d[i]);
    }
  }
  return true;
}

std::string cell(const Stat& s, const Metric& m, std::size_t finished) {
  if (s.n == 0) return "–";
  std::string c =
      formatFixed(s.mean * m.scale, m.digits) + " ± " + formatFixed(s.std * m.scale, m.digits);
  if (s.n < finished) c += " (n=" + std::to_string(s.n) + ")";
  return c;
}

std::string csvNumber(double v) {
  if (!std::isfinite(v)) return "";
  char b[64];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
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

  cfg.policies = splitTrim(p.getString("policies"), ',');
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
  for (const auto& o : splitTrim(p.getString("overrides"), ';')) {
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

std::vector<ExperimentRun> runExperiment(const ExperimentConfig& cfg, const std::string& asf_exe,
                                         const std::function<void(const std::string&)>& progress,
                                         const std::atomic<bool>* stop) {
  auto say = [&](const std::string& line) {
    if (progress) progress(line);
  };
  std::vector<ExperimentRun> runs;
  // Seeds outer, policies inner: an interrupted experiment has comparable runs per policy.
  for (int r = 0; r < cfg.replications; ++r)
    for (const auto& p : cfg.policies) {
      ExperimentRun run;
      run.policy = p;
      run.seed = cfg.first_seed + r;
      run.dir = runDir(cfg, p, run.seed);
      runs.push_back(run);
    }
  const std::size_t total = runs.size();
  std::size_t done = 0;
  auto prefix = [&] { return "[" + std::to_string(done) + "/" + std::to_string(total) + "] "; };

  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (runFinished(runs[i].dir)) {
      runs[i].skipped = true;
      ++done;
      say(prefix() + runs[i].policy + " seed " + std::to_string(runs[i].seed) +
          ": already finished, skipped");
    } else {
      todo.push_back(i);
    }
  }
  const std::size_t jobs = cfg.jobs > 0
                               ? static_cast<std::size_t>(cfg.jobs)
                               : std::max<std::size_t>(1, std::thread::hardware_concurrency());

  struct Running {
    std::size_t run;
    pid_t pid;
    std::chrono::steady_clock::time_point t0;
  };
  std::vector<Running> running;
  std::size_t next = 0;
  bool forwarded = false, killed = false;
  std::chrono::steady_clock::time_point stop_time;
  while (true) {
    const bool stopping = stop && stop->load();
    if (stopping && !forwarded) {
      forwarded = true;
      if (!running.empty())
        say("interrupted: stopping " + std::to_string(running.size()) +
            " running run(s); they write their outputs first");
      for (const auto& r : running) kill(r.pid, SIGINT);
      stop_time = std::chrono::steady_clock::now();
    }
    // A run that ignores SIGINT (hung in a plugin) must not keep the experiment forever.
    if (forwarded && !killed && std::chrono::steady_clock::now() - stop_time > kStopGrace) {
      killed = true;
      for (const auto& r : running) kill(r.pid, SIGKILL);
    }
    while (!stopping && running.size() < jobs && next < todo.size()) {
      ExperimentRun& run = runs[todo[next++]];
      std::error_code ec;
      fs::create_directories(run.dir, ec);
      if (ec) throw Error(run.dir + ": cannot create: " + ec.message());
      // A stale summary.json (interrupted, error) must not pass for this run's result.
      fs::remove(fs::path(run.dir) / "summary.json", ec);
      std::vector<std::string> args{asf_exe,
                                    "run",
                                    cfg.pipeline_ini,
                                    "--out",
                                    run.dir,
                                    "--set",
                                    "pipeline.policy=" + run.policy,
                                    "--set",
                                    "pipeline.seed=" + std::to_string(run.seed)};
      for (const auto& o : cfg.overrides) {
        args.push_back("--set");
        args.push_back(o);
      }
      args.insert(args.end(), {"-v", "WARN"});
      std::string error;
      const std::string log = (fs::path(run.dir) / "run.log").string();
      const pid_t pid = spawnRun(args, log, error);
      if (pid < 0) {
        run.exit_code = 127;
        ++done;
        say(prefix() + run.policy + " seed " + std::to_string(run.seed) + ": " + error);
        continue;
      }
      running.push_back(
          {static_cast<std::size_t>(&run - runs.data()), pid, std::chrono::steady_clock::now()});
      say("started " + run.policy + " seed " + std::to_string(run.seed) + " -> " + run.dir);
    }
    if (running.empty() && (stopping || next >= todo.size())) break;

    bool reaped = false;
    for (auto it = running.begin(); it != running.end();) {
      int st = 0;
      const pid_t w = waitpid(it->pid, &st, WNOHANG);
      if (w == 0 || (w < 0 && errno == EINTR)) {
        ++it;
        continue;
      }
      reaped = true;
      ExperimentRun& run = runs[it->run];
      const double secs =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - it->t0).count();
      ++done;
      std::string line = prefix() + run.policy + " seed " + std::to_string(run.seed) + ": ";
      const std::string log = (fs::path(run.dir) / "run.log").string();
      if (w < 0) {
        run.exit_code = -1;
        line += std::string("lost (waitpid: ") + std::strerror(errno) + ")";
      } else if (WIFSIGNALED(st)) {
        run.exit_code = 128 + WTERMSIG(st);
        line += "killed by signal " + std::to_string(WTERMSIG(st)) + " after " +
                formatFixed(secs, 1) + " s" +
                (killed ? " (did not stop within " + std::to_string(kStopGrace.count()) +
                              " s of SIGINT)"
                        : "") +
                "; see " + log;
      } else {
        run.exit_code = WEXITSTATUS(st);
        std::string why;
        const json s = readSummary(run.dir, why);
        const std::string status = runStatus(s, why);
        if (status == "finished") {
          line += "finished in " + formatFixed(secs, 1) + " s (";
          const double c = number(s, "coverage"), d = number(s, "distance_m");
          if (std::isfinite(c)) line += "coverage " + formatFixed(100 * c, 1) + "%, ";
          line += "distance " + (std::isfinite(d) ? formatFixed(d, 1) : std::string("?")) + " m)";
        } else if (status == "interrupted") {
          line += "interrupted after " + formatFixed(secs, 1) + " s";
        } else {
          line += "failed (exit " + std::to_string(run.exit_code) + ", " + status + ") after " +
                  formatFixed(secs, 1) + " s: " + lastLine(log) + " (see " + log + ")";
        }
      }
      say(line);
      it = running.erase(it);
    }
    if (!reaped) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  summarizeExperiment(cfg);
  return runs;
}

std::string summarizeExperiment(const ExperimentConfig& cfg) {
  const fs::path out(cfg.out_dir);
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw Error(cfg.out_dir + ": cannot create: " + ec.message());

  std::vector<RunData> runs;
  for (const auto& p : cfg.policies)
    for (int r = 0; r < cfg.replications; ++r) {
      RunData d;
      d.policy = p;
      d.seed = cfg.first_seed + r;
      d.dir = runDir(cfg, p, d.seed);
      std::string why;
      d.summary = readSummary(d.dir, why);
      d.status = runStatus(d.summary, why);
      runs.push_back(std::move(d));
    }

  // Per policy: statistics of each metric over the finished runs.
  std::map<std::string, std::map<std::string, Stat>> stats;
  std::map<std::string, std::size_t> finished;
  for (const auto& p : cfg.policies) {
    finished[p] = 0;
    for (const auto& m : kMetrics) {
      std::vector<double> v;
      for (const auto& r : runs)
        if (r.policy == p && r.ok() && std::isfinite(number(r.summary, m.key)))
          v.push_back(number(r.summary, m.key));
      stats[p][m.key] = stat(v);
    }
    for (const auto& r : runs) finished[p] += r.policy == p && r.ok();
  }
  const std::string total = std::to_string(cfg.replications);

  // Markdown.
  std::ostringstream md;
  md << "| policy | finished |";
  for (const auto& m : kMetrics) md << ' ' << m.title << " |";
  md << "\n|---|---:|";
  for (std::size_t i = 0; i < sizeof kMetrics / sizeof *kMetrics; ++i) md << "---:|";
  md << '\n';
  for (const auto& p : cfg.policies) {
    md << "| " << p << " | " << finished[p] << '/' << total << " |";
    for (const auto& m : kMetrics) md << ' ' << cell(stats[p][m.key], m, finished[p]) << " |";
    md << '\n';
  }
  std::vector<const RunData*> not_ok;
  for (const auto& r : runs)
    if (!r.ok()) not_ok.push_back(&r);
  std::string notes;
  if (!not_ok.empty()) {
    notes = "\nRuns not counted (mean ± sample std over the finished runs only):\n\n";
    for (const auto* r : not_ok)
      notes += "- " + r->policy + " seed " + std::to_string(r->seed) + ": " + r->status + "\n";
  }
  const std::string table = md.str();
  writeFileAtomically((out / "summary.md").string(), table + notes);

  // CSV: raw values (coverage as a fraction), as summary.json.
  std::ostringstream csv;
  csv << "policy,finished,total";
  for (const auto& m : kMetrics)
    csv << ',' << m.key << "_mean," << m.key << "_std," << m.key << "_n";
  csv << '\n';
  for (const auto& p : cfg.policies) {
    csv << p << ',' << finished[p] << ',' << total;
    for (const auto& m : kMetrics) {
      const Stat& s = stats[p][m.key];
      csv << ',' << csvNumber(s.mean) << ',' << csvNumber(s.std) << ',' << s.n;
    }
    csv << '\n';
  }
  writeFileAtomically((out / "summary.csv").string(), csv.str());

  // JSON.
  json j;
  j["experiment"] = {{"pipeline", cfg.pipeline_ini},
                     {"policies", cfg.policies},
                     {"replications", cfg.replications},
                     {"first_seed", cfg.first_seed},
                     {"overrides", cfg.overrides}};
  json pols = json::object();
  for (const auto& p : cfg.policies) {
    json jp;
    for (const auto& m : kMetrics) {
      const Stat& s = stats[p][m.key];
      jp[m.key] = {{"mean", s.n ? json(s.mean) : json(nullptr)},
                   {"std", s.n ? json(s.std) : json(nullptr)},
                   {"n", s.n}};
    }
    jp["finished"] = finished[p];
    jp["total"] = cfg.replications;
    pols[p] = jp;
  }
  j["policies"] = pols;
  json jr = json::array();
  for (const auto& r : runs) {
    json e = r.summary.is_object() ? r.summary : json::object();
    if (!e.contains("policy") || e["policy"].is_null()) e["policy"] = r.policy;
    if (!e.contains("seed") || e["seed"].is_null()) e["seed"] = r.seed;
    e["dir"] = fs::absolute(r.dir).lexically_normal().string();
    e["status"] = r.status;
    jr.push_back(e);
  }
  j["runs"] = jr;
  writeFileAtomically((out / "summary.json").string(), j.dump(2) + "\n");

  // Curves over all runs of a policy.
  plot::Figure cov{"Coverage vs distance (mean ± std over runs)",
                   "distance travelled (m)",
                   "coverage of the reachable area (%)",
                   {}};
  plot::Figure epd{"Pose error per distance travelled (mean ± std over runs)",
                   "distance travelled (m)",
                   "pose error / distance",
                   {}};
  std::size_t without_ts = 0;
  for (const auto& p : cfg.policies) {
    std::vector<Curve> cc, ec2;
    for (const auto& r : runs) {
      if (r.policy != p || !r.ok()) continue;
      Curve c, e;
      if (!readCurves(r.dir, c, e)) {
        ++without_ts;
        continue;
      }
      if (!c.d.empty()) cc.push_back(c);
      if (!e.d.empty()) ec2.push_back(e);
    }
    auto dmax = [](const std::vector<Curve>& cs) {
      double m = 0;
      for (const auto& c : cs) m = std::max(m, c.d.back());
      return m;
    };
    const std::string label_c = p + " (" + std::to_string(cc.size()) + " runs)";
    const std::string label_e = p + " (" + std::to_string(ec2.size()) + " runs)";
    if (!cc.empty() && dmax(cc) > 0)
      cov.series.push_back(meanCurve(label_c, cc, true, dmax(cc)));
    else
      cov.series.push_back(plot::series(label_c, {}, {}));
    if (!ec2.empty() && dmax(ec2) > 0)
      epd.series.push_back(meanCurve(label_e, ec2, false, dmax(ec2)));
    else
      epd.series.push_back(plot::series(label_e, {}, {}));
  }
  plot::writeSvg(cov, (out / "coverage_vs_distance.svg").string());
  plot::writeSvg(epd, (out / "error_per_distance_vs_distance.svg").string());

  // report.html: everything above in one file.
  std::ostringstream h;
  const std::string name = fs::absolute(out).lexically_normal().filename().string();
  h << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>asf "
    << "experiment: " << htmlEscape(name) << "</title>\n<style>\n"
    << report::css() << "</style>\n</head>\n<body>\n<h1>asf experiment: " << htmlEscape(name)
    << "</h1>\n<p class=\"sub\">pipeline " << htmlEscape(cfg.pipeline_ini) << " · "
    << cfg.replications << " replications (seeds " << cfg.first_seed << "–"
    << cfg.first_seed + cfg.replications - 1 << ")";
  if (!cfg.overrides.empty()) {
    h << " · overrides";
    for (const auto& o : cfg.overrides) h << ' ' << htmlEscape(o);
  }
  h << "</p>\n<h2>Summary</h2>\n<p>Mean ± sample standard deviation over each policy's "
    << "finished runs.</p>\n<table>\n<tr><th>policy</th><th>finished</th>";
  for (const auto& m : kMetrics) h << "<th>" << htmlEscape(m.title) << "</th>";
  h << "</tr>\n";
  for (const auto& p : cfg.policies) {
    h << "<tr><td>" << htmlEscape(p) << "</td><td class=\"num\">" << finished[p] << '/' << total
      << "</td>";
    for (const auto& m : kMetrics)
      h << "<td class=\"num\">" << htmlEscape(cell(stats[p][m.key], m, finished[p])) << "</td>";
    h << "</tr>\n";
  }
  h << "</table>\n<h2>Curves</h2>\n<div class=\"grid\">\n<div>" << plot::svg(cov) << "</div>\n<div>"
    << plot::svg(epd) << "</div>\n</div>\n";
  if (without_ts)
    h << "<p class=\"note\">" << without_ts
      << " finished run(s) without a usable timeseries.csv: no curves from them.</p>\n";
  h << "<h2>Maps</h2>\n<div class=\"grid\">\n";
  for (const auto& p : cfg.policies) {
    const RunData* first = nullptr;
    for (const auto& r : runs)
      if (r.policy == p && fs::exists(fs::path(r.dir) / "map.png", ec)) {
        first = &r;
        break;
      }
    h << "<div><figure>";
    if (first) {
      const std::string img =
          report::embeddedPng((fs::path(first->dir) / "map.png").string(), p + " map");
      h << (img.empty() ? "<p class=\"note\">map.png unreadable</p>" : img);
      h << "<figcaption>" << htmlEscape(p) << ", seed " << first->seed << "</figcaption>";
    } else {
      h << "<p class=\"note\">" << htmlEscape(p) << ": no run has a map.png</p>";
    }
    h << "</figure></div>\n";
  }
  h << "</div>\n<h2>Runs</h2>\n<table>\n<tr><th>policy</th><th>seed</th><th>status</th>"
       "<th>distance (m)</th><th>coverage (%)</th><th>wall time (s)</th><th>files</th></tr>\n";
  for (const auto& r : runs) {
    const std::string rel = r.policy + "/seed_" + std::to_string(r.seed) + "/";
    auto val = [&](const char* k, double scale, int digits) {
      const double v = number(r.summary, k);
      return std::isfinite(v) ? formatFixed(v * scale, digits) : std::string("–");
    };
    h << "<tr><td>" << htmlEscape(r.policy) << "</td><td class=\"num\">" << r.seed << "</td><td"
      << (r.ok() ? "" : " class=\"note\"") << ">" << htmlEscape(r.status)
      << "</td><td class=\"num\">" << val("distance_m", 1, 2) << "</td><td class=\"num\">"
      << val("coverage", 100, 1) << "</td><td class=\"num\">" << val("wall_time_s", 1, 1)
      << "</td><td>";
    if (fs::exists(fs::path(r.dir) / "report.html", ec))
      h << "<a href=\"" << htmlEscape(rel) << "report.html\">report</a> ";
    if (fs::exists(fs::path(r.dir) / "run.log", ec))
      h << "<a href=\"" << htmlEscape(rel) << "run.log\">log</a>";
    h << "</td></tr>\n";
  }
  h << "</table>\n<p class=\"foot\">asf " ASF_VERSION_STRING "</p>\n</body>\n</html>\n";
  writeFileAtomically((out / "report.html").string(), h.str());
  return table + notes;
}

}  // namespace asf
