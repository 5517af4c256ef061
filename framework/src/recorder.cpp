#include "recorder.h"

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <filesystem>
#include <iomanip>
#include <sstream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace asf {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

void writeAtomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp);
    f << text;
    if (!f) throw Error(path + ": write failed");
  }
  fs::rename(tmp, path);
}

cv::Vec3b regionColour(RegionId id) {
  // Distinct, deterministic colours from the id (golden-ratio hue walk).
  const double h = std::fmod(id * 0.618033988749895, 1.0) * 180.0;
  cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar(h, 140, 230)), bgr;
  cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
  return bgr.at<cv::Vec3b>(0, 0);
}

/// Grid as a BGR image, y up, and a map-point -> pixel function.
struct MapImage {
  cv::Mat img;
  double x0 = 0, y0 = 0, res = 1;
  cv::Point px(double x, double y) const {
    return {static_cast<int>((x - x0) / res), img.rows - 1 - static_cast<int>((y - y0) / res)};
  }
};

MapImage renderGrid(const mrpt::maps::COccupancyGridMap2D& g) {
  MapImage m;
  m.x0 = g.getXMin(), m.y0 = g.getYMin(), m.res = g.getResolution();
  const int w = static_cast<int>(g.getSizeX()), h = static_cast<int>(g.getSizeY());
  m.img = cv::Mat(h, w, CV_8UC3);
  for (int cy = 0; cy < h; ++cy)
    for (int cx = 0; cx < w; ++cx) {
      const auto v = static_cast<unsigned char>(255.0 * g.getCell(cx, cy));  // p(free)
      m.img.at<cv::Vec3b>(h - 1 - cy, cx) = {v, v, v};
    }
  return m;
}

}  // namespace

Recorder::Recorder(const std::string& out_dir, const ResolvedConfig& cfg) : dir_(out_dir) {
  fs::create_directories(dir_);
  writeAtomically(dir_ + "/config.ini", cfg.toIni());
  for (const auto& [slot, info] : cfg.slots) slots_[slot] = info->name();
  traj_.open(dir_ + "/trajectory.csv");
  traj_ << "step,time_s,x,y,phi,gt_x,gt_y,gt_phi,pose_error_m,nodes,edges,distance_m\n";
  decisions_.open(dir_ + "/decisions.csv");
  decisions_ << "step,time_s,previous_status,decision,goal_x,goal_y,reason\n";
  if (!traj_ || !decisions_) throw Error(dir_ + ": cannot write the run's files");
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

void Recorder::decision(long step, double time, const Decision& d, NavStatus previous) {
  std::string reason = d.reason;
  for (auto& c : reason)
    if (c == ',' || c == '\n') c = ';';
  decisions_ << step << ',' << time << ',' << navStatusName(previous) << ','
             << (d.type == Decision::Type::Done ? "done" : "goto") << ',';
  if (d.type == Decision::Type::GoTo) decisions_ << d.goal.x << ',' << d.goal.y;
  else decisions_ << ',';
  decisions_ << ',' << reason << '\n';
  decisions_.flush();
}

void Recorder::finish(const PoseGraph& graph, const GridMap& map, const Segmentation& seg,
                      const TopoGraph& topo, const std::vector<mrpt::poses::CPose2D>& path,
                      const RunSummary& summary, std::string& error) {
  auto attempt = [&](const char* what, auto&& fn) {
    try {
      fn();
    } catch (const std::exception& e) {
      error += std::string(error.empty() ? "" : "; ") + what + ": " + e.what();
    }
  };
  attempt("graph.g2o", [&] { writeG2o(graph, dir_ + "/graph.g2o"); });
  attempt("keyframes.txt", [&] {
    // Absolute times, so `asf ate keyframes.txt GT.txt` evaluates them like any trajectory.
    std::ostringstream os;
    os << "# final keyframe poses (graph nodes): t x y phi (s, m, m, rad)\n"
       << std::setprecision(17);
    for (const PoseNode& n : graph.nodes)
      os << n.timestamp << ' ' << n.pose.x() << ' ' << n.pose.y() << ' ' << n.pose.phi() << '\n';
    writeAtomically(dir_ + "/keyframes.txt", os.str());
  });
  attempt("map.png", [&] {
    if (!map.grid) return;
    MapImage m = renderGrid(*map.grid);
    if (!seg.labels.labels.empty()) {
      cv::Mat regions = m.img.clone();
      for (int cy = 0; cy < seg.labels.height; ++cy)
        for (int cx = 0; cx < seg.labels.width; ++cx) {
          const RegionId r = seg.labels.at(cx, cy);
          if (r <= 0) continue;
          const auto p = m.px(seg.labels.origin_x + (cx + 0.5) * seg.labels.resolution,
                              seg.labels.origin_y + (cy + 0.5) * seg.labels.resolution);
          if (p.x >= 0 && p.y >= 0 && p.x < regions.cols && p.y < regions.rows)
            regions.at<cv::Vec3b>(p) = regionColour(r);
        }
      for (const auto& e : topo.edges) {
        const TopoNode* a = topo.node(e.a);
        const cv::Point mid = m.px(e.midpoint.x, e.midpoint.y);
        if (e.frontier()) {
          cv::circle(regions, mid, 3, {0, 0, 255}, -1);
          if (a) cv::line(regions, m.px(a->centroid.x, a->centroid.y), mid, {0, 0, 200}, 1);
        } else if (const TopoNode* b = topo.node(e.b); a && b) {
          cv::line(regions, m.px(a->centroid.x, a->centroid.y), mid, {40, 40, 40}, 1);
          cv::line(regions, mid, m.px(b->centroid.x, b->centroid.y), {40, 40, 40}, 1);
        }
      }
      for (const auto& n : topo.nodes)
        if (n.region > 0) cv::circle(regions, m.px(n.centroid.x, n.centroid.y), 4, {0, 0, 0}, -1);
      if (!cv::imwrite(dir_ + "/regions.png", regions)) throw Error("cannot write");
    }
    for (std::size_t i = 1; i < path.size(); ++i)
      cv::line(m.img, m.px(path[i - 1].x(), path[i - 1].y()), m.px(path[i].x(), path[i].y()),
               {200, 80, 0}, 1, cv::LINE_AA);
    for (const auto& n : graph.nodes) cv::circle(m.img, m.px(n.pose.x(), n.pose.y()), 2, {0, 0, 220}, -1);
    if (!cv::imwrite(dir_ + "/map.png", m.img)) throw Error("cannot write");
  });
  attempt("topology.json", [&] {
    json j;
    j["current"] = topo.current;
    j["nodes"] = json::array();
    for (const auto& n : topo.nodes)
      j["nodes"].push_back({{"region", n.region}, {"centroid", {n.centroid.x, n.centroid.y}},
                            {"area_m2", n.area}, {"visited", n.visited},
                            {"entrance_edge", n.entrance_edge}});
    j["edges"] = json::array();
    for (const auto& e : topo.edges) {
      json t = json::array();
      for (const auto& tr : e.traversals) t.push_back({{"forward", tr.forward}, {"time_s", tr.time}});
      j["edges"].push_back({{"a", e.a}, {"b", e.b}, {"frontier", e.frontier()},
                            {"midpoint", {e.midpoint.x, e.midpoint.y}}, {"width_m", e.width},
                            {"traversals", t}});
    }
    writeAtomically(dir_ + "/topology.json", j.dump(2) + "\n");
  });
  attempt("summary.json", [&] {
    json j;
    j["plugins"] = slots_;
    j["steps"] = summary.steps;
    j["distance_m"] = summary.distance_m;
    j["nodes"] = summary.nodes;
    j["edges"] = summary.edges;
    j["final_pose_error_m"] = summary.final_pose_error_m < 0 ? json(nullptr) : json(summary.final_pose_error_m);
    j["mean_pose_error_m"] = summary.mean_pose_error_m < 0 ? json(nullptr) : json(summary.mean_pose_error_m);
    j["ate_rmse_m"] = summary.ate_rmse_m < 0 ? json(nullptr) : json(summary.ate_rmse_m);
    j["ate_max_m"] = summary.ate_max_m < 0 ? json(nullptr) : json(summary.ate_max_m);
    j["ate_poses"] = summary.ate_poses;
    j["regions"] = summary.regions;
    j["decisions"] = summary.decisions;
    j["finished"] = summary.finished;
    j["stop_reason"] = summary.stop_reason;
    j["wall_time_s"] = summary.wall_time_s;
    j["final_chi2"] = graph.chi2();
    if (!error.empty()) j["output_errors"] = error;
    writeAtomically(dir_ + "/summary.json", j.dump(2) + "\n");
  });
}

}  // namespace asf
