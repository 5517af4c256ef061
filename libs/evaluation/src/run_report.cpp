#include <asf/abi.h>
#include <asf/atomic_file.h>
#include <asf/errors.h>
#include <asf/io/recorded_run.h>
#include <asf/evaluation/run_report.h>
#include <asf/evaluation/svg_plot.h>
#include <asf/text.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace asf::evaluation {

namespace fs = std::filesystem;
using nlohmann::json;

namespace report {

namespace {

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> f;
  std::string cur;
  for (char c : line) {
    if (c == ',') {
      f.push_back(cur);
      cur.clear();
    } else if (c != '\r') {
      cur += c;
    }
  }
  f.push_back(cur);
  return f;
}

double parseNumber(const std::string& s) {
  const char* b = s.c_str();
  while (*b == ' ' || *b == '\t') ++b;
  if (!*b) return NAN;
  char* end = nullptr;
  const double v = std::strtod(b, &end);
  while (end && (*end == ' ' || *end == '\t')) ++end;
  return end && !*end ? v : NAN;
}

}  // namespace

std::string base64(const std::string& bytes) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string o;
  o.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    o += t[v >> 18];
    o += t[(v >> 12) & 63];
    o += t[(v >> 6) & 63];
    o += t[v & 63];
  }
  if (i < bytes.size()) {
    const bool two = i + 1 < bytes.size();
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (two ? static_cast<unsigned char>(bytes[i + 1]) << 8 : 0);
    o += t[v >> 18];
    o += t[(v >> 12) & 63];
    o += two ? t[(v >> 6) & 63] : '=';
    o += '=';
  }
  return o;
}

std::map<std::string, std::vector<double>> readCsvColumns(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read");
  std::string line;
  if (!std::getline(in, line) || line.empty()) throw InputError(path + ":1: no header line");
  const std::vector<std::string> names = splitCsv(line);
  std::map<std::string, std::vector<double>> cols;
  for (const auto& n : names) cols[n];
  while (std::getline(in, line)) {
    if (line.empty() || line == "\r") continue;
    const std::vector<std::string> f = splitCsv(line);
    for (std::size_t i = 0; i < names.size(); ++i)
      cols[names[i]].push_back(i < f.size() ? parseNumber(f[i]) : NAN);
  }
  return cols;
}

std::string embeddedPng(const std::string& path, const std::string& alt) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  std::ostringstream ss;
  ss << in.rdbuf();
  const std::string bytes = ss.str();
  if (bytes.empty()) return "";
  return "<img alt=\"" + htmlEscape(alt) + "\" src=\"data:image/png;base64," + base64(bytes) +
         "\">";
}

const char* css() {
  return R"(body{font-family:system-ui,sans-serif;margin:1.5em auto;max-width:1400px;padding:0 1em;color:#222}
h1{font-size:1.5em;margin-bottom:.2em}h2{font-size:1.2em;margin-top:1.6em;border-bottom:1px solid #ddd}
.sub{color:#666;margin-top:0}
table{border-collapse:collapse;font-size:.9em}td,th{border:1px solid #ccc;padding:3px 8px;text-align:left}
th{background:#f3f3f3}td.num{text-align:right;font-variant-numeric:tabular-nums}
.grid{display:flex;flex-wrap:wrap;gap:12px}.grid>div{flex:0 0 auto}
figure{margin:0}figure img{max-width:660px;image-rendering:pixelated;border:1px solid #ccc}
figcaption{color:#555;font-size:.85em}
.note{color:#a33}.foot{color:#888;font-size:.8em;margin-top:2em}
)";
}


}  // namespace report

namespace {

/// Units and readable names of the summary keys, in the order the table shows them.
struct KeyInfo {
  const char* key;
  const char* label;
};
const KeyInfo kSummaryKeys[] = {
    {"policy", "policy"},
    {"seed", "seed"},
    {"stop_reason", "stop reason"},
    {"finished", "finished"},
    {"distance_m", "distance (m)"},
    {"coverage", "coverage"},
    {"explored_area_m2", "explored area (m²)"},
    {"reachable_area_m2", "reachable area (m²)"},
    {"map_information_bits", "map information (bits)"},
    {"map_entropy_bits", "map entropy over its grid (bits)"},
    {"distance_to_coverage_50_m", "distance to 50 % coverage (m)"},
    {"distance_to_coverage_90_m", "distance to 90 % coverage (m)"},
    {"distance_to_coverage_99_m", "distance to 99 % coverage (m)"},
    {"time_to_coverage_99_s", "time to 99 % coverage (s)"},
    {"mean_pose_error_m", "mean pose error (m)"},
    {"final_pose_error_m", "final pose error (m)"},
    {"ate_rmse_m", "ATE RMSE (m)"},
    {"ate_max_m", "ATE max (m)"},
    {"rpe_trans_rmse_m", "RPE RMSE, consecutive keyframes (m)"},
    {"rpe_rot_rmse_deg", "RPE RMSE, consecutive keyframes (deg)"},
    {"loop_closures", "loop closures"},
    {"decisions", "decisions"},
    {"decision_ms_mean", "decision time, mean (ms)"},
    {"decision_ms_max", "decision time, max (ms)"},
    {"segment_ms_median", "segmentation time, median (ms)"},
    {"segmentations", "segmentations"},
    {"incremental_share", "incremental segmentations (share)"},
    {"segment_ms_median_incremental", "incremental segmentation, median (ms)"},
    {"segment_ms_median_full", "full segmentation, median (ms)"},
    {"changed_cells_median", "changed cells per segmentation, median"},
    {"wall_time_s", "wall time (s)"},
    {"steps", "steps"},
    {"nodes", "nodes"},
    {"edges", "edges"},
    {"regions", "regions"},
};

std::string fmtNumber(double v) {
  char b[64];
  if (std::fabs(v) >= 1e5 || (v != 0 && std::fabs(v) < 1e-3))
    std::snprintf(b, sizeof b, "%.4g", v);
  else
    std::snprintf(b, sizeof b, "%.3f", v);
  return b;
}

std::string fmtValue(const std::string& key, const json& v) {
  if (v.is_null()) return "unknown";
  if (v.is_boolean()) return v.get<bool>() ? "yes" : "no";
  if (v.is_number_integer() || v.is_number_unsigned()) return v.dump();
  if (v.is_number()) {
    const double d = v.get<double>();
    if (key == "coverage" || key == "incremental_share") return fmtNumber(100 * d) + " %";
    return fmtNumber(d);
  }
  if (v.is_string()) return v.get<std::string>();
  if (v.is_object()) {
    std::string s;
    for (auto it = v.begin(); it != v.end(); ++it)
      s += (s.empty() ? "" : ", ") + it.key() + ": " + fmtValue(it.key(), it.value());
    return s;
  }
  return v.dump();
}

std::string summaryTable(const json& j) {
  std::ostringstream o;
  o << "<table>\n";
  auto row = [&](const std::string& label, const std::string& key, const json& v) {
    const bool numeric = v.is_number();
    o << "<tr><th>" << htmlEscape(label) << "</th><td" << (numeric ? " class=\"num\"" : "") << ">"
      << htmlEscape(fmtValue(key, v)) << "</td></tr>\n";
  };
  std::vector<std::string> shown;
  for (const auto& k : kSummaryKeys)
    if (j.contains(k.key)) {
      row(k.label, k.key, j[k.key]);
      shown.push_back(k.key);
    }
  for (auto it = j.begin(); it != j.end(); ++it)
    if (std::find(shown.begin(), shown.end(), it.key()) == shown.end())
      row(it.key(), it.key(), it.value());
  o << "</table>\n";
  return o.str();
}

using io::DecisionRow;

std::string field(const DecisionRow& r, const char* key) {
  const auto it = r.find(key);
  return it == r.end() ? std::string() : it->second;
}

/// "(x, y)" of a decision's goal, empty without one.
std::string goalText(const DecisionRow& r) {
  return field(r, "goal_x").empty() ? ""
                                    : "(" + field(r, "goal_x") + ", " + field(r, "goal_y") + ")";
}

/// The last `n` decisions as a table (step, decision, goal, reason); empty without any.
std::string decisionsTable(const std::vector<DecisionRow>& rows, std::size_t n) {
  if (rows.empty()) return "";
  const std::size_t first = rows.size() > n ? rows.size() - n : 0;
  std::ostringstream o;
  o << "<p>The last " << rows.size() - first << " of " << rows.size() << " decisions.</p>\n"
    << "<table>\n<tr><th>step</th><th>decision</th><th>goal (m)</th><th>reason</th></tr>\n";
  for (std::size_t i = first; i < rows.size(); ++i)
    o << "<tr><td class=\"num\">" << htmlEscape(field(rows[i], "step")) << "</td><td>"
      << htmlEscape(field(rows[i], "decision")) << "</td><td>" << htmlEscape(goalText(rows[i]))
      << "</td><td>" << htmlEscape(field(rows[i], "reason")) << "</td></tr>\n";
  o << "</table>\n";
  return o.str();
}

/// Each decision's caption (step, time, decision, goal, reason), in order.
std::vector<std::string> decisionCaptions(const std::vector<DecisionRow>& rows) {
  std::vector<std::string> out;
  for (const auto& r : rows) {
    std::string c = "step " + field(r, "step") + " · t = " + field(r, "time_s") + " s · " +
                    field(r, "decision");
    if (!goalText(r).empty()) c += " " + goalText(r);
    out.push_back(c + " · " + field(r, "reason"));
  }
  return out;
}

/// The timeline: timeline/NNNN.png of every decision in one image with a slider and a play
/// button (inline script; the pictures as data URLs: no file or network needed). Empty
/// without pictures.
std::string timelineSection(const fs::path& dir, const std::vector<DecisionRow>& decisions) {
  std::vector<fs::path> frames;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir / "timeline", ec))
    if (e.path().extension() == ".png") frames.push_back(e.path());
  if (frames.empty()) return "";
  std::sort(frames.begin(), frames.end());
  const std::vector<std::string> captions = decisionCaptions(decisions);
  // At most kMaxFrames pictures, evenly spread, keep the report's size bounded on long runs.
  constexpr std::size_t kMaxFrames = 150;
  std::vector<std::size_t> pick(std::min(frames.size(), kMaxFrames));
  for (std::size_t k = 0; k < pick.size(); ++k)
    pick[k] = pick.size() == 1 ? 0 : k * (frames.size() - 1) / (pick.size() - 1);
  json urls = json::array(), caps = json::array();
  for (const std::size_t i : pick) {
    std::ifstream in(frames[i], std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    urls.push_back("data:image/png;base64," + report::base64(bytes));
    // NNNN.png is the run's NNNN-th decision (the first ones may have no picture: no map yet).
    const long n = std::strtol(frames[i].stem().string().c_str(), nullptr, 10);
    const bool known = n >= 1 && static_cast<std::size_t>(n) <= captions.size();
    caps.push_back("decision " + std::to_string(n) + " of " + std::to_string(captions.size()) +
                   (known ? " · " + captions[n - 1] : std::string()));
  }
  std::string data = "[" + urls.dump() + "," + caps.dump() + "]";
  // Inside <script>: no "<" may open a tag.
  for (std::size_t p = 0; (p = data.find('<', p)) != std::string::npos;)
    data.replace(p, 1, "\\u003c");
  std::ostringstream o;
  o << "<h2>Timeline</h2>\n<p>The run at each decision: regions, topological graph, path, "
       "robot (red) and goal (green cross).</p>\n<figure><img id=\"tl-img\" alt=\"timeline\" src=\""
    << urls[0].get<std::string>() << "\"/><figcaption><button id=\"tl-play\" type=\"button\">"
    << "play</button> <input id=\"tl-pos\" type=\"range\" min=\"0\" max=\"" << pick.size() - 1
    << "\" value=\"0\"/> <span id=\"tl-cap\"></span></figcaption></figure>\n"
    << "<script>\n(function () {\n  const d = " << data << ";\n"
    << "  const img = document.getElementById('tl-img'), pos = document.getElementById('tl-pos');\n"
    << "  const cap = document.getElementById('tl-cap'), btn = "
       "document.getElementById('tl-play');\n"
    << "  let timer = null;\n"
    << "  function show(i) { pos.value = i; img.src = d[0][i]; cap.textContent = d[1][i]; }\n"
    << "  pos.addEventListener('input', function () { show(+pos.value); });\n"
    << "  btn.addEventListener('click', function () {\n"
    << "    if (timer) { clearInterval(timer); timer = null; btn.textContent = 'play'; return; }\n"
    << "    if (+pos.value >= d[0].length - 1) show(0);\n"
    << "    btn.textContent = 'pause';\n"
    << "    timer = setInterval(function () {\n"
    << "      const i = +pos.value + 1;\n"
    << "      if (i >= d[0].length) { clearInterval(timer); timer = null; btn.textContent = "
       "'play'; }\n"
    << "      else show(i);\n"
    << "    }, 400);\n  });\n  show(0);\n})();\n</script>\n";
  return o.str();
}

std::vector<double> column(const std::map<std::string, std::vector<double>>& cols,
                           const std::string& name, std::size_t rows) {
  auto it = cols.find(name);
  return it == cols.end() ? std::vector<double>(rows, NAN) : it->second;
}

bool anyFinite(const std::vector<double>& v) {
  for (double x : v)
    if (std::isfinite(x)) return true;
  return false;
}

/// `map_cells`: the final grid's cells (summary.json), NaN when unknown: the map entropy
/// over that grid is its cells minus each row's map_information_bits.
std::string plots(const std::string& path, double map_cells, std::vector<std::string>& notes) {
  std::map<std::string, std::vector<double>> ts;
  try {
    ts = report::readCsvColumns(path);
  } catch (const Error& e) {
    notes.push_back(fs::exists(path) ? e.what() : "timeseries.csv: missing (no plots)");
    return "";
  }
  if (!ts.count("distance_m")) {
    notes.push_back("timeseries.csv: no distance_m column (no plots)");
    return "";
  }
  const std::vector<double>& d = ts["distance_m"];
  const std::size_t rows = d.size();
  const std::string xl = "distance travelled (m)";
  std::vector<plot::Figure> figs;

  plot::Figure cov{"Coverage", xl, "coverage of the reachable area (%)", {}};
  std::vector<double> c = column(ts, "coverage", rows);
  for (double& v : c) v *= 100;
  cov.series.push_back(plot::series("coverage", d, c));
  if (!anyFinite(c)) notes.push_back("coverage: unknown (the source does not know the world)");
  figs.push_back(cov);

  const std::vector<double> e = column(ts, "pose_error_m", rows);
  plot::Figure err{"Pose error", xl, "|true - estimated position| (m)", {}};
  err.series.push_back(plot::series("pose error", d, e));
  if (!anyFinite(e)) notes.push_back("pose error: unknown (no ground truth)");
  figs.push_back(err);

  std::vector<double> epd(rows, NAN);
  for (std::size_t i = 0; i < rows; ++i)
    if (d[i] > 0) epd[i] = e[i] / d[i];
  plot::Figure rel{"Pose error per distance travelled", xl, "pose error / distance", {}};
  rel.series.push_back(plot::series("pose error / distance", d, epd));
  figs.push_back(rel);

  if (ts.count("map_information_bits") && std::isfinite(map_cells)) {
    std::vector<double> h = column(ts, "map_information_bits", rows);
    for (double& v : h) v = (map_cells - v) / 1000;
    plot::Figure ent{"Map entropy over the final grid", xl, "entropy (kbit)", {}};
    ent.series.push_back(plot::series("map entropy", d, h));
    figs.push_back(ent);
  }

  // Cumulative time per stage: per-row milliseconds are too noisy to read. Seconds once
  // some stage passes one second, else milliseconds.
  plot::Figure cpu{"Compute time per stage (cumulative)", xl, "", {}};
  double most = 0;
  for (const char* stage : {"frontend", "backend", "map", "segment", "policy"}) {
    const std::string name = std::string(stage) + "_ms";
    if (!ts.count(name)) continue;
    std::vector<double> cum(rows, NAN);
    double sum = 0;
    for (std::size_t i = 0; i < rows; ++i) {
      if (std::isfinite(ts[name][i])) sum += ts[name][i];
      cum[i] = sum;
    }
    most = std::max(most, sum);
    cpu.series.push_back(plot::series(stage, d, cum));
  }
  const bool seconds = most >= 1000;
  cpu.y_label = seconds ? "compute time (s)" : "compute time (ms)";
  if (seconds)
    for (auto& s : cpu.series)
      for (double& v : s.y) v /= 1000;
  figs.push_back(cpu);

  std::ostringstream o;
  o << "<div class=\"grid\">\n";
  for (auto& f : figs) {
    f.width = 560;
    f.height = 340;
    o << "<div>" << plot::svg(f) << "</div>\n";
  }
  o << "</div>\n";
  return o.str();
}

std::string nowText() {
  const std::time_t t = std::time(nullptr);
  char b[64];
  std::tm tm{};
  localtime_r(&t, &tm);
  std::strftime(b, sizeof b, "%Y-%m-%d %H:%M:%S", &tm);
  return b;
}

/// summary.json of the run, or false with a note saying why not.
bool readSummary(const fs::path& dir, json& summary, std::vector<std::string>& notes) {
  std::ifstream in(dir / "summary.json");
  if (!in) {
    notes.push_back("summary.json: missing (the run did not finish writing its outputs)");
    return false;
  }
  try {
    in >> summary;
    if (summary.is_object()) return true;
    notes.push_back("summary.json: not a JSON object");
  } catch (const std::exception& e) {
    notes.push_back(std::string("summary.json: invalid JSON: ") + e.what());
  }
  return false;
}

/// "policy tigre · seed 1 · all_regions_explored" from the summary's keys it has.
std::string runSubtitle(const json& summary) {
  std::string sub;
  auto str = [&](const char* k) {
    return summary.contains(k) && !summary[k].is_null() ? fmtValue(k, summary[k]) : "";
  };
  for (const auto& [k, label] : {std::pair<const char*, const char*>{"policy", "policy "},
                                 {"seed", "seed "},
                                 {"stop_reason", ""}})
    if (!str(k).empty()) sub += (sub.empty() ? "" : " · ") + std::string(label) + str(k);
  return sub;
}

/// The run's map pictures embedded; a missing one is a note (map3d_grid.png only in runs with
/// [pipeline] map3d).
std::string mapsSection(const fs::path& dir, std::vector<std::string>& notes) {
  std::ostringstream body;
  body << "<h2>Maps</h2>\n<div class=\"grid\">\n";
  for (const auto& [file, caption] :
       {std::pair<const char*, const char*>{"map.png", "map.png: occupancy grid, path, keyframes"},
        {"regions.png", "regions.png: regions and topological graph"},
        {"map3d_grid.png", "map3d_grid.png: the 3D map projected to 2D (robot body band)"}}) {
    const bool optional = std::string(file) == "map3d_grid.png";
    if (optional && !fs::exists(dir / file)) continue;
    const std::string img = report::embeddedPng((dir / file).string(), file);
    if (img.empty()) {
      notes.push_back(std::string(file) + ": missing");
      continue;
    }
    body << "<div><figure>" << img << "<figcaption>" << htmlEscape(caption)
         << "</figcaption></figure></div>\n";
  }
  body << "</div>\n";
  return body.str();
}

}  // namespace

std::string writeRunReport(const std::string& run_dir) {
  const fs::path dir(run_dir);
  std::vector<std::string> notes;
  std::ostringstream body;

  json summary;
  const bool have_summary = readSummary(dir, summary, notes);
  std::string name = fs::absolute(dir).lexically_normal().filename().string();
  if (name.empty()) name = fs::absolute(dir).lexically_normal().parent_path().filename().string();
  const std::string sub = have_summary ? runSubtitle(summary) : "";

  body << "<h1>asf run: " << htmlEscape(name) << "</h1>\n";
  if (!sub.empty()) body << "<p class=\"sub\">" << htmlEscape(sub) << "</p>\n";
  body << "<p class=\"sub\">" << htmlEscape(fs::absolute(dir).lexically_normal().string())
       << "</p>\n";

  body << "<h2>Summary</h2>\n";
  if (have_summary)
    body << summaryTable(summary);
  else
    body << "<p class=\"note\">No summary (see the notes below).</p>\n";
  body << mapsSection(dir, notes);

  body << "<h2>Progress</h2>\n";
  const double map_cells =
      have_summary && summary.contains("map_cells") && summary["map_cells"].is_number()
          ? summary["map_cells"].get<double>()
          : NAN;
  const std::string p = plots((dir / "timeseries.csv").string(), map_cells, notes);
  body << (p.empty() ? "<p class=\"note\">No time series (see the notes below).</p>\n" : p);

  std::string dnote;
  const std::vector<DecisionRow> decisions =
      io::readDecisionRows((dir / "decisions.csv").string(), dnote);
  body << timelineSection(dir, decisions) << "<h2>Decisions</h2>\n";
  const std::string dt = decisionsTable(decisions, 20);
  if (!dnote.empty()) notes.push_back(dnote);
  body << (dt.empty() ? "<p class=\"note\">" + htmlEscape(dnote) + "</p>\n" : dt);

  if (!notes.empty()) {
    body << "<h2>Notes</h2>\n<ul>\n";
    for (const auto& n : notes) body << "<li class=\"note\">" << htmlEscape(n) << "</li>\n";
    body << "</ul>\n";
  }
  body << "<p class=\"foot\">asf " ASF_VERSION_STRING ", report written " << nowText() << "</p>\n";

  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>asf run: "
       << htmlEscape(name) << "</title>\n<style>\n"
       << report::css() << "</style>\n</head>\n<body>\n"
       << body.str() << "</body>\n</html>\n";
  const std::string out = (dir / "report.html").string();
  writeFileAtomically(out, html.str());
  return out;
}

}  // namespace asf::evaluation
