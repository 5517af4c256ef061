// asf segment-report: segment-eval reports (JSON) side by side, as the thesis shows them:
// Table 4.1 (thesis value | asf value, both scoring protocols), Fig. 4.1 (precision and recall
// over the maps) and Fig. 4.2 (processing times), as Markdown, JSON and SVG.
#include <asf/abi.h>
#include <asf/atomic_file.h>
#include <asf/errors.h>
#include <asf/evaluation/run_report.h>
#include <asf/evaluation/svg_plot.h>
#include <tclap/CmdLine.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.h"

namespace asf::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct Run {
  std::string label, file;
  json report;
};

/// Thesis Table 4.1 (per-region means, %): Voronoi (Bormann et al.), DuDe batch, incremental.
struct ThesisCell {
  const char* scenario;
  const char* metric;
  double voronoi[2], batch[2], incremental[2];
};
const ThesisCell kTable41[] = {
    {"plain", "recall", {95.0, 2.3}, {86.3, 9.7}, {87.5, 10.7}},
    {"plain", "precision", {94.8, 5.0}, {94.1, 3.1}, {93.8, 3.1}},
    {"furnished", "recall", {86.6, 5.2}, {85.8, 10.3}, {87.5, 10.7}},
    {"furnished", "precision", {94.5, 5.1}, {94.0, 3.2}, {93.8, 3.1}},
};

Run readRun(const std::string& file, const std::string& label) {
  std::ifstream in(file);
  if (!in) throw InputError(file + ": cannot read");
  Run r;
  r.file = file;
  try {
    in >> r.report;
  } catch (const std::exception& e) {
    throw InputError(file + ": not a JSON report (" + e.what() + ")");
  }
  if (!r.report.is_object() || !r.report.contains("maps") || !r.report["maps"].is_array() ||
      !r.report.contains("summary"))
    throw InputError(file + ": not an asf segment-eval report (no maps / summary)");
  if (!r.report["summary"].is_object()) r.report["summary"] = json::object();  // no map scored
  r.label = label;
  if (r.label.empty()) {
    r.label = r.report.value("segmenter", fs::path(file).stem().string());
    const json& p = r.report.value("params", json::object());
    if (p.contains("variant")) r.label += " " + p["variant"].get<std::string>();
  }
  return r;
}

std::string pct(double mean, double std) {
  std::ostringstream o;
  o << std::fixed << std::setprecision(1) << 100 * mean << " ± " << 100 * std;
  return o.str();
}

/// "<key>_mean" / "<key>_std" of a summary object as "m ± s" (%), or "–" when absent.
std::string cell(const json& s, const std::string& key) {
  if (!s.contains(key + "_mean")) return "–";
  return pct(s[key + "_mean"].get<double>(), s[key + "_std"].get<double>());
}

json summaryOf(const Run& r, const std::string& scenario, bool incremental) {
  const json& s = r.report["summary"];
  if (!s.contains(scenario)) return json::object();
  if (!incremental) return s[scenario];
  return s[scenario].value("incremental", json::object());
}

/// Table 4.1: rows scenario x metric; columns: the thesis' three, then per run its batch and
/// (when measured) incremental values under the thesis' protocol and under roomseg-eval.md.
void writeTable(const std::vector<Run>& runs, const std::string& dir) {
  std::ostringstream md;
  json rows = json::array();
  md << "# Table 4.1: averaged precision and recall (%), mean ± std over the maps\n\n"
     << "asf columns: `thesis protocol` scores as the author's evaluation code does "
        "(asf::evaluation::scoreThesisProtocol: the thesis' \"precision\" is per room, its "
        "\"recall\" per "
        "segment, unlabelled pixels ignored, no size filter); `roomseg` scores as "
        "../shared/docs/roomseg-eval.md (Bormann et al.: precision per segment, recall per room, "
        "regions of more than 100 px) and is shown in the row of the same meaning: the thesis' "
        "recall row holds roomseg's precision, its precision row roomseg's recall. The thesis' "
        "Voronoi column copies Bormann et al.'s published figures under their names (their "
        "recall is per room, their precision per segment): in that column the two rows' "
        "meanings are swapped.\n\n";
  md << "| scenario | metric | thesis Voronoi | thesis DuDe batch | thesis DuDe incremental";
  for (const Run& r : runs)
    md << " | " << r.label << " (thesis protocol) | " << r.label
       << " incremental (thesis protocol) | " << r.label << " (roomseg)";
  md << " |\n|---|---|---|---|---";
  for (std::size_t i = 0; i < runs.size(); ++i) md << "|---|---|---";
  md << "|\n";
  for (const ThesisCell& t : kTable41) {
    const std::string metric = t.metric;
    const bool per_segment = metric == "recall";
    // The roomseg measure with the same meaning (per segment / per room).
    const std::string roomseg_key = per_segment ? "precision" : "recall";
    md << "| " << (std::string(t.scenario) == "plain" ? "no furniture" : "furnished") << " | "
       << metric << (per_segment ? " (per segment)" : " (per room)") << " | " << std::fixed
       << std::setprecision(1) << t.voronoi[0] << " ± " << t.voronoi[1] << " | " << t.batch[0]
       << " ± " << t.batch[1] << " | " << t.incremental[0] << " ± " << t.incremental[1];
    json row = {
        {"scenario", t.scenario},
        {"metric", metric},
        {"per", per_segment ? "segment" : "room"},
        {"thesis",
         {{"voronoi", t.voronoi}, {"dude_batch", t.batch}, {"dude_incremental", t.incremental}}},
        {"asf", json::array()}};
    for (const Run& r : runs) {
      const json batch = summaryOf(r, t.scenario, false), inc = summaryOf(r, t.scenario, true);
      const std::string thesis_key = "thesis_" + metric;
      md << " | " << cell(batch, thesis_key) << " | " << cell(inc, thesis_key) << " | "
         << cell(batch, roomseg_key);
      json a = {{"label", r.label}};
      auto put = [&](const char* name, const json& s, const std::string& key) {
        if (s.contains(key + "_mean"))
          a[name] = {100 * s[key + "_mean"].get<double>(), 100 * s[key + "_std"].get<double>()};
        else
          a[name] = nullptr;
      };
      put("thesis_protocol", batch, thesis_key);
      put("thesis_protocol_incremental", inc, thesis_key);
      put("roomseg", batch, roomseg_key);
      put("roomseg_incremental", inc, roomseg_key);
      row["asf"].push_back(a);
    }
    md << " |\n";
    rows.push_back(row);
  }
  md << "\nMaps: ";
  for (const Run& r : runs)
    md << r.label << " " << r.report["summary"].value("plain", json::object()).value("maps", 0)
       << " plain (" << r.file << "); ";
  md << "the thesis used the 20 maps of the benchmark.\n";
  writeFileAtomically((fs::path(dir) / "table_4_1.md").string(), md.str());
  writeFileAtomically((fs::path(dir) / "table_4_1.json").string(),
                      json{{"rows", rows}}.dump(2) + "\n");
}

/// A staircase over sorted values: with `at_least`, the share of values >= x ("95 % of the
/// maps score above ..."), else the share <= x ("95 % of the maps within ... ms"); values are
/// scaled by `scale` on x.
evaluation::plot::Series staircase(std::string label, std::vector<double> v, bool dashed,
                                   bool at_least, double scale) {
  std::sort(v.begin(), v.end());
  evaluation::plot::Series s;
  s.label = std::move(label);
  s.dashed = dashed;
  const double n = static_cast<double>(v.size());
  for (std::size_t k = 0; k < v.size(); ++k) {
    const double before = at_least ? (n - k) / n : k / n,
                 after = at_least ? (n - k - 1) / n : (k + 1) / n;
    s.x.push_back(scale * v[k]);
    s.y.push_back(100 * before);
    s.x.push_back(scale * v[k]);
    s.y.push_back(100 * after);
  }
  return s;
}
evaluation::plot::Series atLeast(std::string label, std::vector<double> v, bool dashed) {
  return staircase(std::move(label), std::move(v), dashed, true, 100);
}
evaluation::plot::Series within(std::string label, std::vector<double> v, bool dashed) {
  return staircase(std::move(label), std::move(v), dashed, false, 1);
}

std::vector<double> mapValues(const Run& r, const std::string& scenario, const std::string& key,
                              bool incremental) {
  std::vector<double> v;
  for (const json& m : r.report["maps"]) {
    if (m.value("variant", "") != scenario) continue;
    const json* src = &m;
    if (incremental) {
      if (!m.contains("incremental")) continue;
      src = &m["incremental"];
    }
    if (key.rfind("thesis_", 0) == 0) {
      if (src->contains("thesis_protocol"))
        v.push_back((*src)["thesis_protocol"][key.substr(7)].get<double>());
    } else if (src->contains(key)) {
      v.push_back((*src)[key].get<double>());
    }
  }
  return v;
}

void writeFigures(const std::vector<Run>& runs, const std::string& dir) {
  for (const char* metric : {"precision", "recall"}) {
    evaluation::plot::Figure f;
    f.title = std::string("Fig. 4.1: ") + metric + " over the maps (thesis protocol)";
    f.x_label = std::string(metric) + " (%)";
    f.y_label = "maps scoring at least x (%)";
    for (const Run& r : runs) {
      const std::string key = std::string("thesis_") + metric;
      f.series.push_back(atLeast(r.label + " plain", mapValues(r, "plain", key, false), false));
      f.series.push_back(
          atLeast(r.label + " furnished", mapValues(r, "furnished", key, false), true));
      for (const char* scenario : {"plain", "furnished"}) {
        const auto inc = mapValues(r, scenario, key, true);
        if (!inc.empty())
          f.series.push_back(atLeast(r.label + " incremental " + scenario, inc, true));
      }
    }
    evaluation::plot::writeSvg(
        f, (fs::path(dir) / (std::string("fig4_1_") + metric + ".svg")).string());
  }
  evaluation::plot::Figure batch;
  batch.title = "Fig. 4.2: batch segmentation time per map";
  batch.x_label = "time (ms)";
  batch.y_label = "maps segmented within x (%)";
  evaluation::plot::Figure inc;
  // As the thesis: each map's mean time per update (the author's cum_time / valid_images).
  inc.title = "Fig. 4.2: incremental, mean time per update of each map";
  inc.x_label = "time (ms)";
  inc.y_label = "maps within x (%)";
  for (const Run& r : runs) {
    batch.series.push_back(
        within(r.label + " plain", mapValues(r, "plain", "time_ms", false), false));
    batch.series.push_back(
        within(r.label + " furnished", mapValues(r, "furnished", "time_ms", false), true));
    for (const char* scenario : {"plain", "furnished"}) {
      const auto means = mapValues(r, scenario, "mean_ms", true);
      if (!means.empty())
        inc.series.push_back(within(r.label + " " + scenario, means, scenario[0] == 'f'));
    }
  }
  evaluation::plot::writeSvg(batch, (fs::path(dir) / "fig4_2_batch_time.svg").string());
  evaluation::plot::writeSvg(inc, (fs::path(dir) / "fig4_2_incremental_time.svg").string());
}

}  // namespace

int cmdSegmentReport(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Puts asf segment-eval reports (--json) side by side as the thesis shows them: "
      "table_4_1.md / .json (the thesis' Table 4.1 next to every report, scored with the "
      "thesis' own protocol and with roomseg-eval.md's), fig4_1_precision.svg and "
      "fig4_1_recall.svg (share of maps scoring at least x), fig4_2_batch_time.svg and "
      "fig4_2_incremental_time.svg (share of maps processed within x ms: batch time, and the "
      "mean time per incremental update of each map, as the thesis plots them).",
      ' ', ASF_VERSION_STRING);
  TCLAP::UnlabeledMultiArg<std::string> files("reports", "segment-eval JSON reports", true,
                                              "REPORT.json", cmd);
  TCLAP::MultiArg<std::string> labels("l", "label",
                                      "Column label of each report, in order (default: "
                                      "segmenter and variant)",
                                      false, "NAME", cmd);
  TCLAP::ValueArg<std::string> out("o", "out", "Output folder", true, "", "DIR", cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);
  if (!labels.getValue().empty() && labels.getValue().size() != files.getValue().size())
    throw ConfigError("--label: " + std::to_string(labels.getValue().size()) + " labels for " +
                      std::to_string(files.getValue().size()) + " reports");
  std::vector<Run> runs;
  for (std::size_t i = 0; i < files.getValue().size(); ++i)
    runs.push_back(
        readRun(files.getValue()[i], labels.getValue().empty() ? "" : labels.getValue()[i]));
  fs::create_directories(out.getValue());
  writeTable(runs, out.getValue());
  writeFigures(runs, out.getValue());
  std::cout << "wrote " << (fs::path(out.getValue()) / "table_4_1.md").string()
            << ", table_4_1.json, fig4_1_precision.svg, fig4_1_recall.svg, "
               "fig4_2_batch_time.svg, fig4_2_incremental_time.svg\n";
  return kOk;
}

}  // namespace asf::app
