// asf experiment's summary: statistics per policy over the run folders, as Markdown, CSV,
// JSON, curves (SVG) and report.html.
#include <asf/abi.h>
#include <asf/atomic_file.h>
#include <asf/errors.h>
#include <asf/studies/experiment.h>
#include <asf/evaluation/run_report.h>
#include <asf/evaluation/svg_plot.h>
#include <asf/text.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "experiment_runs.h"

namespace asf::studies {

namespace fs = std::filesystem;
using detail::number;
using nlohmann::json;

namespace {

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
    // Where the coverage first reached 90 % and 99 % (summary.json has 25 / 50 / 75 too).
    {"distance_to_coverage_90_m", "distance to 90 % (m)", 1, 1},
    {"distance_to_coverage_99_m", "distance to 99 % (m)", 1, 1},
    {"mean_pose_error_m", "mean pose error (m)", 1, 3},
    {"final_pose_error_m", "final pose error (m)", 1, 3},
    {"ate_rmse_m", "keyframe ATE (m)", 1, 4},        // the SLAM estimate's, at the end of the run
    {"rpe_trans_rmse_m", "keyframe RPE (m)", 1, 4},  // consecutive keyframes' motion
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
evaluation::plot::Series meanCurve(const std::string& label, const std::vector<Curve>& curves,
                                   bool hold, double dmax) {
  evaluation::plot::Series s;
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
bool readCurves(const std::string& dir, Curve& coverage, Curve& epd, Curve& info) {
  std::map<std::string, std::vector<double>> ts;
  try {
    ts = evaluation::report::readCsvColumns((fs::path(dir) / "timeseries.csv").string());
  } catch (const Error&) {
    return false;
  }
  if (!ts.count("distance_m")) return false;
  const auto& d = ts["distance_m"];
  const std::vector<double> none(d.size(), NAN);
  const auto& c = ts.count("coverage") ? ts["coverage"] : none;
  const auto& e = ts.count("pose_error_m") ? ts["pose_error_m"] : none;
  const auto& m = ts.count("map_information_bits") ? ts["map_information_bits"] : none;
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
    if (std::isfinite(m[i])) {
      info.d.push_back(d[i]);
      info.y.push_back(m[i] / 1000);
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

/// Each configured run's folder, summary.json and status.
std::vector<RunData> readRuns(const ExperimentConfig& cfg) {
  std::vector<RunData> runs;
  for (const auto& p : cfg.policies)
    for (int r = 0; r < cfg.replications; ++r) {
      RunData d;
      d.policy = p;
      d.seed = cfg.first_seed + r;
      d.dir = detail::runDir(cfg, p, d.seed);
      std::string why;
      d.summary = detail::readSummary(d.dir, why);
      d.status = detail::runStatus(d.summary, why);
      runs.push_back(std::move(d));
    }
  return runs;
}

/// Per policy: statistics of each metric over the finished runs.
struct PolicyStats {
  std::map<std::string, std::map<std::string, Stat>> stats;
  std::map<std::string, std::size_t> finished;
  std::string total;  ///< replications per policy
};

PolicyStats policyStats(const ExperimentConfig& cfg, const std::vector<RunData>& runs) {
  PolicyStats ps;
  for (const auto& p : cfg.policies) {
    ps.finished[p] = 0;
    for (const auto& m : kMetrics) {
      std::vector<double> v;
      for (const auto& r : runs)
        if (r.policy == p && r.ok() && std::isfinite(number(r.summary, m.key)))
          v.push_back(number(r.summary, m.key));
      ps.stats[p][m.key] = stat(v);
    }
    for (const auto& r : runs) ps.finished[p] += r.policy == p && r.ok();
  }
  ps.total = std::to_string(cfg.replications);
  return ps;
}

std::string markdownTable(const ExperimentConfig& cfg, PolicyStats& ps) {
  std::ostringstream md;
  md << "| policy | finished |";
  for (const auto& m : kMetrics) md << ' ' << m.title << " |";
  md << "\n|---|---:|";
  for (std::size_t i = 0; i < sizeof kMetrics / sizeof *kMetrics; ++i) md << "---:|";
  md << '\n';
  for (const auto& p : cfg.policies) {
    md << "| " << p << " | " << ps.finished[p] << '/' << ps.total << " |";
    for (const auto& m : kMetrics) md << ' ' << cell(ps.stats[p][m.key], m, ps.finished[p]) << " |";
    md << '\n';
  }
  return md.str();
}

/// The runs not counted and why; empty when every run finished.
std::string notCountedNotes(const std::vector<RunData>& runs) {
  std::string notes;
  for (const auto& r : runs) {
    if (r.ok()) continue;
    if (notes.empty())
      notes = "\nRuns not counted (mean ± sample std over the finished runs only):\n\n";
    notes += "- " + r.policy + " seed " + std::to_string(r.seed) + ": " + r.status + "\n";
  }
  return notes;
}

/// Raw values (coverage as a fraction), as summary.json.
std::string summaryCsv(const ExperimentConfig& cfg, PolicyStats& ps) {
  std::ostringstream csv;
  csv << "policy,finished,total";
  for (const auto& m : kMetrics)
    csv << ',' << m.key << "_mean," << m.key << "_std," << m.key << "_n";
  csv << '\n';
  for (const auto& p : cfg.policies) {
    csv << p << ',' << ps.finished[p] << ',' << ps.total;
    for (const auto& m : kMetrics) {
      const Stat& s = ps.stats[p][m.key];
      csv << ',' << csvNumber(s.mean) << ',' << csvNumber(s.std) << ',' << s.n;
    }
    csv << '\n';
  }
  return csv.str();
}

json summaryJson(const ExperimentConfig& cfg, PolicyStats& ps, const std::vector<RunData>& runs) {
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
      const Stat& s = ps.stats[p][m.key];
      jp[m.key] = {{"mean", s.n ? json(s.mean) : json(nullptr)},
                   {"std", s.n ? json(s.std) : json(nullptr)},
                   {"n", s.n}};
    }
    jp["finished"] = ps.finished[p];
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
  return j;
}

/// Curves over all finished runs of each policy.
struct CurveFigures {
  evaluation::plot::Figure coverage{"Coverage vs distance (mean ± std over runs)",
                        "distance travelled (m)",
                        "coverage of the reachable area (%)",
                        {}};
  evaluation::plot::Figure epd{"Pose error per distance travelled (mean ± std over runs)",
                   "distance travelled (m)",
                   "pose error / distance",
                   {}};
  evaluation::plot::Figure information{"Map information vs distance (mean ± std over runs)",
                           "distance travelled (m)",
                           "map information (kbit: cells' 1 - entropy)",
                           {}};
  std::size_t without_timeseries = 0;  ///< finished runs without a usable timeseries.csv
};

/// The mean curve of `curves` labelled with the number of runs, or an empty series.
evaluation::plot::Series policyCurve(const std::string& policy, const std::vector<Curve>& curves,
                                     bool hold) {
  const std::string label = policy + " (" + std::to_string(curves.size()) + " runs)";
  double dmax = 0;
  for (const auto& c : curves) dmax = std::max(dmax, c.d.back());
  if (!curves.empty() && dmax > 0) return meanCurve(label, curves, hold, dmax);
  return evaluation::plot::series(label, {}, {});
}

CurveFigures curveFigures(const ExperimentConfig& cfg, const std::vector<RunData>& runs) {
  CurveFigures f;
  for (const auto& p : cfg.policies) {
    std::vector<Curve> cc, ec, ic;
    for (const auto& r : runs) {
      if (r.policy != p || !r.ok()) continue;
      Curve c, e, i;
      if (!readCurves(r.dir, c, e, i)) {
        ++f.without_timeseries;
        continue;
      }
      if (!c.d.empty()) cc.push_back(c);
      if (!e.d.empty()) ec.push_back(e);
      if (!i.d.empty()) ic.push_back(i);
    }
    f.coverage.series.push_back(policyCurve(p, cc, true));
    f.epd.series.push_back(policyCurve(p, ec, false));
    f.information.series.push_back(policyCurve(p, ic, true));
  }
  return f;
}

void htmlSummary(std::ostringstream& h, const ExperimentConfig& cfg, PolicyStats& ps) {
  h << "<h2>Summary</h2>\n<p>Mean ± sample standard deviation over each policy's "
    << "finished runs.</p>\n<table>\n<tr><th>policy</th><th>finished</th>";
  for (const auto& m : kMetrics) h << "<th>" << htmlEscape(m.title) << "</th>";
  h << "</tr>\n";
  for (const auto& p : cfg.policies) {
    h << "<tr><td>" << htmlEscape(p) << "</td><td class=\"num\">" << ps.finished[p] << '/'
      << ps.total << "</td>";
    for (const auto& m : kMetrics)
      h << "<td class=\"num\">" << htmlEscape(cell(ps.stats[p][m.key], m, ps.finished[p]))
        << "</td>";
    h << "</tr>\n";
  }
  h << "</table>\n";
}

/// The map of each policy's first run that has one.
void htmlMaps(std::ostringstream& h, const ExperimentConfig& cfg,
              const std::vector<RunData>& runs) {
  std::error_code ec;
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
          evaluation::report::embeddedPng((fs::path(first->dir) / "map.png").string(), p + " map");
      h << (img.empty() ? "<p class=\"note\">map.png unreadable</p>" : img);
      h << "<figcaption>" << htmlEscape(p) << ", seed " << first->seed << "</figcaption>";
    } else {
      h << "<p class=\"note\">" << htmlEscape(p) << ": no run has a map.png</p>";
    }
    h << "</figure></div>\n";
  }
  h << "</div>\n";
}

void htmlRuns(std::ostringstream& h, const std::vector<RunData>& runs) {
  std::error_code ec;
  h << "<h2>Runs</h2>\n<table>\n<tr><th>policy</th><th>seed</th><th>status</th>"
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
  h << "</table>\n";
}

/// report.html: everything above in one file.
std::string reportHtml(const ExperimentConfig& cfg, PolicyStats& ps,
                       const std::vector<RunData>& runs, const CurveFigures& curves) {
  std::ostringstream h;
  const std::string name = fs::absolute(cfg.out_dir).lexically_normal().filename().string();
  h << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>asf "
    << "experiment: " << htmlEscape(name) << "</title>\n<style>\n"
    << evaluation::report::css()
    << "</style>\n</head>\n<body>\n<h1>asf experiment: " << htmlEscape(name)
    << "</h1>\n<p class=\"sub\">pipeline " << htmlEscape(cfg.pipeline_ini) << " · "
    << cfg.replications << " replications (seeds " << cfg.first_seed << "–"
    << cfg.first_seed + cfg.replications - 1 << ")";
  if (!cfg.overrides.empty()) {
    h << " · overrides";
    for (const auto& o : cfg.overrides) h << ' ' << htmlEscape(o);
  }
  h << "</p>\n";
  htmlSummary(h, cfg, ps);
  h << "<h2>Curves</h2>\n<div class=\"grid\">\n<div>" << evaluation::plot::svg(curves.coverage)
    << "</div>\n<div>" << evaluation::plot::svg(curves.epd) << "</div>\n<div>"
    << evaluation::plot::svg(curves.information) << "</div>\n</div>\n";
  if (curves.without_timeseries)
    h << "<p class=\"note\">" << curves.without_timeseries
      << " finished run(s) without a usable timeseries.csv: no curves from them.</p>\n";
  htmlMaps(h, cfg, runs);
  htmlRuns(h, runs);
  h << "<p class=\"foot\">asf " ASF_VERSION_STRING "</p>\n</body>\n</html>\n";
  return h.str();
}

}  // namespace

std::string summarizeExperiment(const ExperimentConfig& cfg) {
  const fs::path out(cfg.out_dir);
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw Error(cfg.out_dir + ": cannot create: " + ec.message());
  const std::vector<RunData> runs = readRuns(cfg);
  PolicyStats ps = policyStats(cfg, runs);
  const std::string table = markdownTable(cfg, ps), notes = notCountedNotes(runs);
  writeFileAtomically((out / "summary.md").string(), table + notes);
  writeFileAtomically((out / "summary.csv").string(), summaryCsv(cfg, ps));
  writeFileAtomically((out / "summary.json").string(), summaryJson(cfg, ps, runs).dump(2) + "\n");
  const CurveFigures curves = curveFigures(cfg, runs);
  evaluation::plot::writeSvg(curves.coverage, (out / "coverage_vs_distance.svg").string());
  evaluation::plot::writeSvg(curves.epd, (out / "error_per_distance_vs_distance.svg").string());
  evaluation::plot::writeSvg(curves.information,
                             (out / "map_information_vs_distance.svg").string());
  writeFileAtomically((out / "report.html").string(), reportHtml(cfg, ps, runs, curves));
  return table + notes;
}

}  // namespace asf::studies
