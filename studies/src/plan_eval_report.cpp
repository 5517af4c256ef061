// The tables of `asf plan-eval` (thesis Table 3.1 protocol) from its json record.
#include "plan_eval_report.h"

#include <iomanip>
#include <sstream>
#include <vector>

namespace asf::studies {

namespace {

std::string percent(double x) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(1) << 100 * x << " %";
  return os.str();
}

}  // namespace

std::string planEvalMarkdown(const nlohmann::json& j) {
  std::vector<std::string> slots;
  for (const auto& s : j["planners"]) slots.push_back(s.get<std::string>());
  const std::string search_of = j["candidate_search_of"].get<std::string>();
  std::ostringstream md;
  md << "# Unreliable-path avoidance (thesis Table 3.1 protocol)\n\n"
     << "Graph: `" << j["graph"].get<std::string>() << "` (" << j["nodes"].get<std::size_t>()
     << " nodes, " << j["edges"].get<std::size_t>() << " edges)"
     << (j["rawlog"].is_null()
             ? std::string(", without its log (no scans)")
             : ", scans and wheel odometry from `" + j["rawlog"].get<std::string>() + "`")
     << ". Config: `" << j["config"].get<std::string>()
     << "`. Zone edges: " << j["zone_covariance"].get<std::string>()
     << ". Error rate: share of the start/goal "
     << "pairs whose chosen path crosses the zone (in parentheses: the count). \"no avoiding "
     << "candidate\": pairs for which no candidate path of the criterion planners' search ("
     << (search_of.empty() ? std::string("none") : search_of) << "'s keys) avoids the zone, so "
     << "that every criterion planner must cross it.\n\n| scenario | zone | factor | pairs | "
     << "no avoiding candidate |";
  for (const auto& s : slots) md << " " << s << " |";
  md << "\n|---|---|---:|---:|---:|";
  for (std::size_t k = 0; k < slots.size(); ++k) md << "---:|";
  md << "\n";
  for (const auto& js : j["scenarios"]) {
    const auto z = js["zone"];
    md << "| " << js["name"].get<std::string>() << " | " << js["zone_index"].get<int>() << ": ("
       << z[0].get<double>() << ", " << z[1].get<double>() << ")-(" << z[2].get<double>() << ", "
       << z[3].get<double>() << ") | x" << js["factor"].get<double>() << " | "
       << js["pairs"].get<std::size_t>() << " | "
       << js["pairs_without_avoiding_candidate"].get<std::size_t>() << " |";
    for (const auto& s : slots) {
      const auto& jp = js["planners"][s];
      md << " " << percent(jp["error_rate"].get<double>()) << " ("
         << jp["errors"].get<std::size_t>() << ")";
      if (jp["not_found"].get<std::size_t>())
        md << ", " << jp["not_found"].get<std::size_t>() << " not found";
      md << " |";
    }
    md << "\n";
  }
  md << "\nZones: nodes, scans removed, consecutive edges made odometry, loop closures "
        "dropped; p_recognition outside the zone (Monte Carlo ICP) mean [min, max], nodes at 0; "
        "det of the nodes' marginal covariances, max in the zone and max / median outside:\n\n"
        "| scenario | zone nodes | scans removed | odometry edges | closures dropped | "
        "p_recognition | det zone max | det outside max / median |\n"
        "|---|---:|---:|---:|---:|---|---:|---:|\n";
  for (const auto& js : j["scenarios"]) {
    md << "| " << js["name"].get<std::string>() << " | " << js["zone_nodes"] << " | "
       << js["scans_removed"] << " | " << js["scaled_edges"] << " | " << js["dropped_loop_closures"]
       << " | ";
    const auto& r = js["recognition"];
    if (r.is_null())
      md << "constant |";
    else
      md << std::fixed << std::setprecision(3) << r["mean"].get<double>() << " ["
         << r["min"].get<double>() << ", " << r["max"].get<double>() << "], "
         << r["zero"].get<std::size_t>() << " |" << std::defaultfloat;
    const auto& d = js["marginal_det"];
    md << std::setprecision(3);
    if (d["zone"].is_null() || d["outside"].is_null())
      md << " - | - |\n";
    else
      md << " " << d["zone"]["max"].get<double>() << " | " << d["outside"]["max"].get<double>()
         << " / " << d["outside"]["median"].get<double>() << " |\n";
    md << std::defaultfloat;
  }
  md << "\nPlanning time of the sweep (all pairs of the scenario) [s], mean / max per pair "
        "[ms]:\n\n"
     << "| scenario |";
  for (const auto& s : slots) md << " " << s << " |";
  md << "\n|---|";
  for (std::size_t k = 0; k < slots.size(); ++k) md << "---:|";
  md << "\n";
  for (const auto& js : j["scenarios"]) {
    md << "| " << js["name"].get<std::string>() << " |";
    for (const auto& s : slots) {
      const auto& jp = js["planners"][s];
      md << std::fixed << std::setprecision(2) << " " << jp["sweep_time_s"].get<double>() << " ("
         << std::setprecision(1) << 1000 * jp["mean_time_s"].get<double>() << " / "
         << 1000 * jp["max_time_s"].get<double>() << ") |" << std::defaultfloat;
    }
    md << "\n";
  }
  bool any_warning = false;
  for (const auto& js : j["scenarios"])
    for (const auto& s : slots)
      if (js["planners"][s]["warnings"].get<std::size_t>()) {
        if (!any_warning) md << "\nPlanner warnings (count, first):\n\n";
        any_warning = true;
        md << "- " << js["name"].get<std::string>() << " " << s << ": "
           << js["planners"][s]["warnings"].get<std::size_t>() << ", "
           << js["planners"][s]["first_warning"].get<std::string>() << "\n";
      }
  md << "\nTotal " << std::setprecision(4) << j["time_s"].get<double>() << " s.\n";
  return md.str();
}

}  // namespace asf::studies
