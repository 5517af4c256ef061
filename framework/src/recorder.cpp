#include "recorder.h"

#include <asf/atomic_file.h>
#include <asf/evaluation/map_views.h>
#include <asf/io/occupancy_io.h>
#include <asf/evaluation/run_report.h>
#include <asf/evaluation/segmentation_eval.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace asf::framework {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// One output file: a failure is noted in `error` and the next file is still written.
template <class Fn>
void writeOrNote(std::string& error, const char* what, Fn&& fn) {
  try {
    fn();
  } catch (const std::exception& e) {
    error += std::string(error.empty() ? "" : "; ") + what + ": " + e.what();
  }
}

/// Where a grid's image lies: its cells, their size and the lower-left corner (row 0 of the
/// PNG is the top, y_min + height * resolution).
json gridGeometry(const mrpt::maps::COccupancyGridMap2D& g) {
  return {{"x_min", g.getXMin()},
          {"y_min", g.getYMin()},
          {"resolution", g.getResolution()},
          {"width", g.getSizeX()},
          {"height", g.getSizeY()}};
}

void writeAtomically(const std::string& path, const std::string& text) {
  writeFileAtomically(path, text);
}

/// summary.json's fields from the run's summary (null where a figure was not measured).
json summaryJson(const RunSummary& summary, const std::map<std::string, std::string>& plugins) {
  json j;
  j["plugins"] = plugins;
  j["policy"] = summary.policy.empty() ? json(nullptr) : json(summary.policy);
  j["seed"] = summary.seed;
  j["coverage"] = summary.coverage < 0 ? json(nullptr) : json(summary.coverage);
  j["reachable_area_m2"] =
      summary.reachable_area_m2 < 0 ? json(nullptr) : json(summary.reachable_area_m2);
  j["explored_area_m2"] = summary.explored_area_m2;
  j["map_versions"] = summary.map_versions;
  j["map_rebuilds"] = summary.map_rebuilds;
  j["loop_closures"] = summary.loop_closures;
  j["decision_ms_mean"] = summary.decision_ms_mean;
  j["decision_ms_max"] = summary.decision_ms_max;
  j["segment_ms_median"] = summary.segment_ms_median;
  auto orNull = [](double v) { return v < 0 ? json(nullptr) : json(v); };
  j["segmentations"] = summary.segmentations;
  j["segmentations_incremental"] = summary.segmentations_incremental;
  j["segmentations_full"] = summary.segmentations_full;
  j["incremental_share"] = summary.segmentations == 0
                               ? json(nullptr)
                               : json(static_cast<double>(summary.segmentations_incremental) /
                                      static_cast<double>(summary.segmentations));
  j["segment_ms_median_incremental"] = orNull(summary.segment_ms_median_incremental);
  j["segment_ms_median_full"] = orNull(summary.segment_ms_median_full);
  j["changed_cells_median"] = orNull(summary.changed_cells_median);
  j["steps"] = summary.steps;
  j["distance_m"] = summary.distance_m;
  j["nodes"] = summary.nodes;
  j["edges"] = summary.edges;
  j["final_pose_error_m"] =
      summary.final_pose_error_m < 0 ? json(nullptr) : json(summary.final_pose_error_m);
  j["mean_pose_error_m"] =
      summary.mean_pose_error_m < 0 ? json(nullptr) : json(summary.mean_pose_error_m);
  j["ate_rmse_m"] = summary.ate_rmse_m < 0 ? json(nullptr) : json(summary.ate_rmse_m);
  j["ate_max_m"] = summary.ate_max_m < 0 ? json(nullptr) : json(summary.ate_max_m);
  j["ate_poses"] = summary.ate_poses;
  j["map_cells"] = summary.map_cells;
  j["map_information_bits"] = orNull(summary.map_information_bits);
  j["map_entropy_bits"] = orNull(summary.map_entropy_bits);
  j["rpe_trans_rmse_m"] = orNull(summary.rpe_trans_rmse_m);
  j["rpe_rot_rmse_deg"] = orNull(summary.rpe_rot_rmse_deg);
  for (int k = 0; k < 5; ++k) {  // distance_to_coverage_25_m ... time_to_coverage_99_s
    const std::string pct =
        std::to_string(static_cast<int>(100 * RunSummary::kCoverageMilestones[k] + 0.5));
    j["distance_to_coverage_" + pct + "_m"] = orNull(summary.coverage_distance_m[k]);
    j["time_to_coverage_" + pct + "_s"] = orNull(summary.coverage_time_s[k]);
  }
  j["regions"] = summary.regions;
  j["decisions"] = summary.decisions;
  if (!summary.resumed_from.empty())
    j["resumed"] = {{"from", summary.resumed_from},
                    {"after_steps", summary.resumed_after_steps},
                    {"replayed_decisions", summary.replayed_decisions},
                    {"replayed_decisions_differing", summary.replayed_decisions_differing}};
  j["finished"] = summary.finished;
  j["stop_reason"] = summary.stop_reason;
  j["wall_time_s"] = summary.wall_time_s;
return j;
}

/// keyframes.txt: absolute times, so `asf ate keyframes.txt GT.txt` evaluates them like any
/// trajectory.
std::string keyframesText(const PoseGraph& graph) {
  std::ostringstream os;
  os << "# final keyframe poses (graph nodes): t x y phi (s, m, m, rad)\n"
     << std::setprecision(17);
  for (const PoseNode& n : graph.nodes)
    os << n.timestamp << ' ' << n.pose.x() << ' ' << n.pose.y() << ' ' << n.pose.phi() << '\n';
  return os.str();
}

}  // namespace

void SegmentationLog::add(const Segmentation& s, double ms) {
  ++total;
  if (s.mode == Segmentation::Mode::Incremental) ++incremental, ms_incremental_.push_back(ms);
  if (s.mode == Segmentation::Mode::Full) ++full, ms_full_.push_back(ms);
  if (s.changed_cells >= 0) {
    changed_.push_back(static_cast<double>(s.changed_cells));
    changed_since_row_ = std::max<std::int64_t>(changed_since_row_, 0) + s.changed_cells;
  }
}

std::int64_t SegmentationLog::takeChangedSinceRow() {
  const std::int64_t c = changed_since_row_;
  changed_since_row_ = -1;
  return c;
}

void SegmentationLog::summarize(RunSummary& sum) const {
  auto median = [](std::vector<double> v) {
    if (v.empty()) return -1.0;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  sum.segmentations = total;
  sum.segmentations_incremental = incremental;
  sum.segmentations_full = full;
  sum.segment_ms_median_incremental = median(ms_incremental_);
  sum.segment_ms_median_full = median(ms_full_);
  sum.changed_cells_median = median(changed_);
}

Recorder::Recorder(const std::string& out_dir, const ResolvedConfig& cfg) : dir_(out_dir) {
  fs::create_directories(dir_);
  writeAtomically(dir_ + "/config.ini", cfg.toIni());
  for (const auto& [slot, info] : cfg.slots) slots_[slot] = info->name();
  traj_.open(dir_ + "/trajectory.csv");
  traj_ << "step,time_s,x,y,phi,gt_x,gt_y,gt_phi,pose_error_m,nodes,edges,distance_m\n";
  decisions_.open(dir_ + "/decisions.csv");
  decisions_ << "step,time_s,previous_status,decision,goal_x,goal_y,reason\n";
  series_.open(dir_ + "/timeseries.csv");
  series_ << "step,time_s,distance_m,coverage,explored_area_m2,pose_error_m,loop_closures,nodes,"
             "edges,regions,decisions,frontend_ms,backend_ms,map_ms,segment_ms,policy_ms,"
             "segmentations,incremental_segmentations,changed_cells,map_information_bits\n";
  if (!traj_ || !decisions_ || !series_) throw Error(dir_ + ": cannot write the run's files");
}

void Recorder::step(const Step& s) {
  traj_ << s.step << ',' << std::setprecision(10) << s.time << ',' << s.estimate.x() << ','
        << s.estimate.y() << ',' << s.estimate.phi() << ',';
  if (s.truth)
    traj_ << s.truth->x() << ',' << s.truth->y() << ',' << s.truth->phi() << ','
          << std::hypot(s.truth->x() - s.estimate.x(), s.truth->y() - s.estimate.y());
  else
    traj_ << ",,,";
  traj_ << ',' << s.nodes << ',' << s.edges << ',' << s.distance << '\n';
  traj_.flush();  // an interrupted run keeps every step written
}

void Recorder::series(const SeriesRow& r) {
  series_ << r.step << ',' << std::setprecision(10) << r.time << ',' << r.distance << ',';
  if (r.coverage >= 0) series_ << r.coverage;
  series_ << ',' << r.explored_area << ',';
  if (r.pose_error >= 0) series_ << r.pose_error;
  series_ << ',' << r.loop_closures << ',' << r.nodes << ',' << r.edges << ',' << r.regions << ','
          << r.decisions << std::setprecision(4);
  for (double v : r.ms) series_ << ',' << v;
  series_ << ',' << r.segmentations << ',' << r.incremental_segmentations << ',';
  if (r.changed_cells >= 0) series_ << r.changed_cells;
  series_ << ',';
  if (r.map_information_bits >= 0) series_ << std::setprecision(10) << r.map_information_bits;
  series_ << '\n';
  series_.flush();
  last_row_ = r;
  const auto now = std::chrono::steady_clock::now();
  if (!progress_written_ || now - last_progress_ >= std::chrono::seconds(5)) {
    last_progress_ = now;
    progress_written_ = true;
    try {
      writeProgress("running", r);
    } catch (const std::exception& e) {  // the run goes on; finish() reports its outputs
      std::cerr << "asf run: progress.json not written: " << e.what() << "\n";
    }
  }
}

void Recorder::timelineFrame(int n, const GridMap& map, const Segmentation& seg,
                             const TopoGraph& topo, const std::vector<mrpt::poses::CPose2D>& path,
                             const mrpt::poses::CPose2D& robot, const Point2* goal, int max_side) {
  char name[32];
  std::snprintf(name, sizeof name, "/timeline/%04d.png", n);
  try {
    std::filesystem::create_directories(dir_ + "/timeline");
    evaluation::writeTimelineFrame(dir_ + name, map, seg, topo, path, robot, goal, max_side);
  } catch (const std::exception& e) {
    std::cerr << "asf run: timeline frame " << n << " not written: " << e.what() << "\n";
  }
}

void Recorder::status(const std::string& status) {
  try {
    writeProgress(status, last_row_);
  } catch (const std::exception& e) {
    std::cerr << "asf run: progress.json not written: " << e.what() << "\n";
  }
}

void Recorder::writeProgress(const std::string& status, const SeriesRow& r) {
  json j{{"status", status},
         {"step", r.step},
         {"time_s", r.time},
         {"distance_m", r.distance},
         {"coverage", r.coverage < 0 ? json(nullptr) : json(r.coverage)},
         {"pose_error_m", r.pose_error < 0 ? json(nullptr) : json(r.pose_error)},
         {"nodes", r.nodes},
         {"edges", r.edges},
         {"regions", r.regions},
         {"loop_closures", r.loop_closures},
         {"decisions", r.decisions},
         {"segmentations", r.segmentations}};
  writeAtomically(dir_ + "/progress.json", j.dump(1) + "\n");
}

void Recorder::decision(long step, double time, const Decision& d, NavStatus previous) {
  std::string reason = d.reason;
  for (auto& c : reason)
    if (c == ',' || c == '\n') c = ';';
  decisions_ << step << ',' << time << ',' << navStatusName(previous) << ','
             << (d.type == Decision::Type::Done ? "done" : "goto") << ',';
  if (d.type == Decision::Type::GoTo)
    decisions_ << d.goal.x << ',' << d.goal.y;
  else
    decisions_ << ',';
  decisions_ << ',' << reason << '\n';
  decisions_.flush();
}

void Recorder::writeMapViews(const std::string& prefix, const PoseGraph& graph, const GridMap& map,
                             const Segmentation& seg, const TopoGraph& topo,
                             const std::vector<mrpt::poses::CPose2D>& path) {
  asf::evaluation::writeMapViews(prefix, graph, map, seg, topo, path);
}

void Recorder::snapshot(double distance, const PoseGraph& graph, const GridMap& map,
                        const Segmentation& seg, const TopoGraph& topo,
                        const std::vector<mrpt::poses::CPose2D>& path) {
  char name[64];
  std::snprintf(name, sizeof name, "/snapshots/at_%gm_", distance);
  try {
    std::filesystem::create_directories(dir_ + "/snapshots");
    evaluation::writeMapViews(dir_ + name, graph, map, seg, topo, path);
  } catch (const std::exception& e) {
    std::cerr << "asf run: snapshot at " << distance << " m not written: " << e.what() << "\n";
  }
}

void Recorder::finish(const PoseGraph& graph, const GridMap& map, const Segmentation& seg,
                      const TopoGraph& topo, const std::vector<mrpt::poses::CPose2D>& path,
                      const RunSummary& summary, std::string& error) {
  auto attempt = [&](const char* what, auto&& fn) { writeOrNote(error, what, fn); };
  attempt("progress.json", [&] { writeProgress("writing outputs", last_row_); });
  attempt("graph.g2o", [&] { writeG2o(graph, dir_ + "/graph.g2o"); });
  attempt("keyframes.txt",
          [&] { writeAtomically(dir_ + "/keyframes.txt", keyframesText(graph)); });
  attempt("map views (topology.svg, regions.png, map.png)",
          [&] { evaluation::writeMapViews(dir_ + "/", graph, map, seg, topo, path); });
  // The bare grid in its frame (map_server; nav2 loads it unchanged): `asf plan --map map.yaml`.
  attempt("map.pgm + map.yaml", [&] { io::writeOccupancyMap(map, dir_ + "/map"); });
  attempt("topology.json",
          [&] { writeAtomically(dir_ + "/topology.json", graph::topologyJson(topo)); });
  attempt("summary.json", [&] {
    json j = summaryJson(summary, slots_);
    j["final_chi2"] = graph.chi2();
    if (map.grid)  // the grid of map.png (row 0 = top = y_min + height * resolution)
      j["map"] = gridGeometry(*map.grid);
    if (!error.empty()) j["output_errors"] = error;
    writeAtomically(dir_ + "/summary.json", j.dump(2) + "\n");
  });
}

void Recorder::finalStatus(const RunSummary& summary, std::string& error) {
  writeOrNote(error, "progress.json", [&] {
    writeProgress(summary.finished ? "finished" : "stopped: " + summary.stop_reason, last_row_);
  });
}

void Recorder::finishMap3d(const mapping::Map3d& map, const GridMap& projected,
                           const Params& params, const Map3dInfo& info, std::string& error) {
  auto attempt = [&](const char* what, auto&& fn) { writeOrNote(error, what, fn); };
  attempt("map3d.bt", [&] { map.writeBt(dir_ + "/map3d.bt"); });
  attempt("map3d.ot", [&] { map.writeOt(dir_ + "/map3d.ot"); });
  attempt("map3d_grid.png", [&] {
    if (projected.grid) evaluation::writeGridPng(dir_ + "/map3d_grid.png", projected);
  });
  attempt("map3d.json", [&] {
    const mapping::Map3dStats st = map.stats();
    json j;
    json jp = json::object();
    for (const auto& [k, v] : params.values()) jp[k] = v.text;
    j["params"] = jp;
    j["navigation_map"] = info.navigation_map;
    j["observations"] = info.observations;
    j["keyframes"] = info.keyframes;
    j["observations_not_at_keyframes"] = info.not_keyframes;
    j["observations_unsupported"] = info.unsupported;
    j["observations_over_cap"] = info.over_cap;
    j["stats"] = json::parse(st.toJson());
    j["timings_ms"] = {
        {"insert", info.insert_ms}, {"project", info.project_ms}, {"rebuild", info.rebuild_ms}};
    if (projected.grid) j["projected"] = gridGeometry(*projected.grid);
    writeAtomically(dir_ + "/map3d.json", j.dump(2) + "\n");
  });
}

}  // namespace asf::framework
