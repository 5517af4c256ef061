// The pictures of `asf plan-eval` (thesis Figs. 3.4 and 3.5) as standalone SVG.
#include "plan_eval_figure.h"

#include <asf/atomic_file.h>
#include <asf/errors.h>
#include <asf/evaluation/run_report.h>
#include <asf/text.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace asf::studies {

namespace {

/// Map metres to pixels: the bounding box of the nodes and the zone, y up, aspect kept.
struct Frame {
  double x0, y1, scale, margin;
  double px(double x) const { return margin + (x - x0) * scale; }
  double py(double y) const { return margin + 40 + (y1 - y) * scale; }  // 40 px of title
};

}  // namespace

std::string scenarioSvg(const PoseGraph& g, const planning::Zone& zone,
                        const std::vector<PathDrawing>& paths, const std::string& title) {
  for (const auto& p : paths)
    for (NodeId v : p.nodes)
      if (v >= g.size())
        throw InputError("plan-eval figure: path '" + p.label + "' names node " +
                         std::to_string(v) + " of a graph of " + std::to_string(g.size()));
  double x0 = std::min(zone.x0, zone.x1), x1 = std::max(zone.x0, zone.x1);
  double y0 = std::min(zone.y0, zone.y1), y1 = std::max(zone.y0, zone.y1);
  for (const auto& n : g.nodes) {
    x0 = std::min(x0, n.pose.x());
    x1 = std::max(x1, n.pose.x());
    y0 = std::min(y0, n.pose.y());
    y1 = std::max(y1, n.pose.y());
  }
  const double width_px = 640, margin = 16;
  const double span = std::max({x1 - x0, y1 - y0, 1e-6});
  const Frame f{x0, y1, (width_px - 2 * margin) / span, margin};
  const double w = 2 * margin + (x1 - x0) * f.scale;
  const double h = 2 * margin + 40 + (y1 - y0) * f.scale + 18.0 * paths.size();
  std::ostringstream s;
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << formatFixed(std::max(w, 360.0), 1)
    << "\" height=\"" << formatFixed(h, 1) << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
    << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    << "<text x=\"" << margin << "\" y=\"22\" font-size=\"14\">" << htmlEscape(title)
    << "</text>\n";
  const double zx = f.px(std::min(zone.x0, zone.x1)), zy = f.py(std::max(zone.y0, zone.y1));
  s << "<rect x=\"" << formatFixed(zx, 1) << "\" y=\"" << formatFixed(zy, 1) << "\" width=\""
    << formatFixed(std::abs(zone.x1 - zone.x0) * f.scale, 1) << "\" height=\""
    << formatFixed(std::abs(zone.y1 - zone.y0) * f.scale, 1)
    << "\" fill=\"#2c6fdc\" fill-opacity=\"0.22\" stroke=\"#2c6fdc\" stroke-width=\"1.5\"/>\n";
  for (const auto& e : g.edges) {
    if (e.from >= g.size() || e.to >= g.size()) continue;
    const auto &a = g.nodes[e.from].pose, &b = g.nodes[e.to].pose;
    const bool consecutive = e.from + 1 == e.to || e.to + 1 == e.from;
    s << "<line x1=\"" << formatFixed(f.px(a.x()), 1) << "\" y1=\"" << formatFixed(f.py(a.y()), 1)
      << "\" x2=\"" << formatFixed(f.px(b.x()), 1) << "\" y2=\"" << formatFixed(f.py(b.y()), 1)
      << "\" stroke=\"" << (consecutive ? "#888" : "#bbb") << "\" stroke-width=\"0.8\""
      << (consecutive ? "" : " stroke-dasharray=\"3,2\"") << "/>\n";
  }
  for (const auto& n : g.nodes)
    s << "<circle cx=\"" << formatFixed(f.px(n.pose.x()), 1) << "\" cy=\""
      << formatFixed(f.py(n.pose.y()), 1) << "\" r=\"1.6\" fill=\""
      << (zone.contains(n.pose) ? "#2c6fdc" : "#333") << "\"/>\n";
  double legend_y = 2 * margin + 40 + (y1 - y0) * f.scale + 4;
  for (const auto& p : paths) {
    s << "<polyline fill=\"none\" stroke=\"" << p.color
      << "\" stroke-width=\"3\" stroke-opacity=\"0.75\" stroke-linejoin=\"round\" points=\"";
    for (NodeId v : p.nodes)
      s << formatFixed(f.px(g.nodes[v].pose.x()), 1) << ","
        << formatFixed(f.py(g.nodes[v].pose.y()), 1) << " ";
    s << "\"/>\n<line x1=\"" << margin << "\" y1=\"" << formatFixed(legend_y, 1) << "\" x2=\""
      << margin + 24 << "\" y2=\"" << formatFixed(legend_y, 1) << "\" stroke=\"" << p.color
      << "\" stroke-width=\"3\"/><text x=\"" << margin + 30 << "\" y=\""
      << formatFixed(legend_y + 4, 1) << "\">" << htmlEscape(p.label) << "</text>\n";
    legend_y += 18;
  }
  if (!paths.empty() && !paths.front().nodes.empty()) {
    const auto& a = g.nodes[paths.front().nodes.front()].pose;
    const auto& b = g.nodes[paths.front().nodes.back()].pose;
    for (const auto& [pose, mark] : {std::make_pair(a, "S"), std::make_pair(b, "G")})
      s << "<circle cx=\"" << formatFixed(f.px(pose.x()), 1) << "\" cy=\""
        << formatFixed(f.py(pose.y()), 1)
        << "\" r=\"6\" fill=\"white\" stroke=\"black\"/><text x=\""
        << formatFixed(f.px(pose.x()) - 4, 1) << "\" y=\"" << formatFixed(f.py(pose.y()) + 4, 1)
        << "\" font-size=\"10\">" << mark << "</text>\n";
  }
  s << "</svg>\n";
  return s.str();
}

nlohmann::json errorExample(const nlohmann::json& pair_results, const std::string& baseline) {
  for (const auto& p : pair_results) {
    const auto eu = p.value("expected_uncertainty", nlohmann::json());
    const auto b = p.value(baseline, nlohmann::json());
    if (eu.is_object() && b.is_object() && eu.value("crosses", true) == false &&
        b.value("crosses", false) && eu.contains("path") && b.contains("path"))
      return p;
  }
  return nullptr;
}

nlohmann::json writeScenarioFigures(const PoseGraph& g, const planning::Zone& zone,
                                    const nlohmann::json& scenario, const std::string& out_dir) {
  const std::string name = scenario.value("name", "?");
  const std::string what = "scenario " + name + " (zone " +
                           std::to_string(scenario.value("zone_index", 0)) + ", covariance x" +
                           formatFixed(scenario.value("factor", 0.0), 1) + ")";
  auto write = [&](const std::string& file, const std::string& text) {
    writeFileAtomically(out_dir + "/" + file, text, "figure");
    return file;
  };
  nlohmann::json rec{{"scenario", write("scenario_" + name + ".svg",
                                        scenarioSvg(g, zone, {}, "Fig. 3.4: " + what))},
                     {"error_example", nullptr}};
  const auto& pairs = scenario.value("pair_results", nlohmann::json::array());
  for (const char* baseline : {"mechanical_work", "sum_dopt"}) {
    const nlohmann::json p = errorExample(pairs, baseline);
    if (p.is_null()) continue;
    const auto path = [&](const char* k) { return p[k]["path"].get<std::vector<NodeId>>(); };
    const std::string label =
        std::string(baseline) == "sum_dopt" ? "sum of D-optimality" : "mechanical work";
    const std::vector<PathDrawing> drawn{
        {label + ": through the zone", "#d73027", path(baseline)},
        {"expected uncertainty: around it", "#1a9850", path("expected_uncertainty")}};
    const std::string file =
        write("error_example_" + name + ".svg",
              scenarioSvg(g, zone, drawn,
                          "Fig. 3.5: " + what + ", node " + std::to_string(p.value("start", 0)) +
                              " to node " + std::to_string(p.value("goal", 0))));
    rec["error_example"] = {{"file", file},
                            {"start", p["start"]},
                            {"goal", p["goal"]},
                            {"baseline", baseline},
                            {"baseline_nodes", p[baseline]["nodes"]},
                            {"expected_uncertainty_nodes", p["expected_uncertainty"]["nodes"]}};
    break;
  }
  return rec;
}

}  // namespace asf::studies
