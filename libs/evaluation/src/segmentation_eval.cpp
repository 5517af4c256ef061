#include <asf/atomic_file.h>
#include <asf/errors.h>
#include <asf/evaluation/run_report.h>
#include <asf/evaluation/segmentation_eval.h>
#include <asf/segmenter.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <map>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <unordered_map>

#include "region_render.h"
#include "reveal_map.h"

namespace asf::evaluation {

namespace fs = std::filesystem;
using Grid = mrpt::maps::COccupancyGridMap2D;

// ---------------------------------------------------------------- benchmark reading -------

io::LabelRaster groundTruthRooms(const io::GrayImage& gt, int min_pixels) {
  cv::Mat mask(gt.height, gt.width, CV_8U, cv::Scalar(0));
  for (int r = 0; r < gt.height; ++r)
    for (int c = 0; c < gt.width; ++c)
      if (gt.at(c, r) > 250) mask.at<std::uint8_t>(r, c) = 1;
  cv::Mat comp, stats, centroids;
  cv::connectedComponentsWithStats(mask, comp, stats, centroids, 8, CV_32S);
  // Renumber 1..N by first pixel in row-major order (OpenCV's order is its own business).
  std::unordered_map<int, std::int32_t> id_of;
  io::LabelRaster L;
  L.width = gt.width;
  L.height = gt.height;
  L.labels.assign(static_cast<std::size_t>(gt.width) * gt.height, 0);
  for (int r = 0; r < gt.height; ++r)
    for (int c = 0; c < gt.width; ++c) {
      const int k = comp.at<int>(r, c);
      if (k == 0 || stats.at<int>(k, cv::CC_STAT_AREA) <= min_pixels) continue;
      auto it = id_of.find(k);
      if (it == id_of.end())
        it = id_of.emplace(k, static_cast<std::int32_t>(id_of.size() + 1)).first;
      L.labels[static_cast<std::size_t>(r) * gt.width + c] = it->second;
    }
  return L;
}

io::LabelRaster toRaster(const LabelImage& labels) {
  io::LabelRaster R;
  R.width = labels.width;
  R.height = labels.height;
  R.labels.resize(labels.labels.size());
  for (int cy = 0; cy < labels.height; ++cy)
    for (int cx = 0; cx < labels.width; ++cx)
      R.labels[static_cast<std::size_t>(labels.height - 1 - cy) * labels.width + cx] =
          labels.at(cx, cy);
  return R;
}

LabelImage fromRaster(const io::LabelRaster& raster, double resolution, double origin_x,
                      double origin_y) {
  LabelImage L;
  L.width = raster.width;
  L.height = raster.height;
  L.resolution = resolution;
  L.origin_x = origin_x;
  L.origin_y = origin_y;
  L.labels.resize(raster.labels.size());
  for (int row = 0; row < raster.height; ++row)
    for (int col = 0; col < raster.width; ++col)
      L.labels[static_cast<std::size_t>(raster.height - 1 - row) * raster.width + col] =
          raster.at(col, row);
  return L;
}

// ---------------------------------------------------------------- scoring -----------------

SegmentationScore scoreSegmentation(const io::LabelRaster& segmentation,
                                    const io::LabelRaster& rooms, int min_pixels) {
  if (segmentation.width != rooms.width || segmentation.height != rooms.height ||
      segmentation.labels.size() != rooms.labels.size())
    throw Error("scoreSegmentation: the segmentation is " + std::to_string(segmentation.width) +
                " x " + std::to_string(segmentation.height) + ", the ground truth " +
                std::to_string(rooms.width) + " x " + std::to_string(rooms.height));
  std::map<std::int32_t, long> seg_size, room_size;  // sorted: reports by increasing label
  for (std::size_t i = 0; i < rooms.labels.size(); ++i) {
    if (segmentation.labels[i] > 0) ++seg_size[segmentation.labels[i]];
    if (rooms.labels[i] > 0) ++room_size[rooms.labels[i]];
  }
  // Dense indices of the counted segments and rooms (-1: not counted).
  std::unordered_map<std::int32_t, int> seg_index, room_index;
  std::vector<long> seg_n, room_n;
  for (const auto& [l, n] : seg_size)
    if (n > min_pixels) seg_index[l] = static_cast<int>(seg_n.size()), seg_n.push_back(n);
  for (const auto& [l, n] : room_size)
    if (n > min_pixels) room_index[l] = static_cast<int>(room_n.size()), room_n.push_back(n);
  const std::size_t S = seg_n.size(), R = room_n.size();

  auto indexOf = [](const std::unordered_map<std::int32_t, int>& m, std::int32_t l) {
    if (l <= 0) return -1;
    auto it = m.find(l);
    return it == m.end() ? -1 : it->second;
  };
  std::unordered_map<std::uint64_t, long> overlap;  // (s << 32 | r) -> pixels
  long universe = 0;
  for (std::size_t i = 0; i < rooms.labels.size(); ++i) {
    const int s = indexOf(seg_index, segmentation.labels[i]);
    const int r = indexOf(room_index, rooms.labels[i]);
    if (s >= 0 || r >= 0) ++universe;
    if (s >= 0 && r >= 0)
      ++overlap[(static_cast<std::uint64_t>(s) << 32) | static_cast<std::uint32_t>(r)];
  }
  std::vector<long> best_s(S, 0), best_r(R, 0);
  auto pairs = [](long double n) { return n * (n - 1) / 2; };
  long double tp = 0;
  for (const auto& [k, n] : overlap) {
    const auto s = static_cast<std::size_t>(k >> 32), r = static_cast<std::size_t>(k & 0xffffffffu);
    best_s[s] = std::max(best_s[s], n);
    best_r[r] = std::max(best_r[r], n);
    tp += pairs(n);
  }

  SegmentationScore sc;
  sc.segments = static_cast<int>(S);
  sc.rooms = static_cast<int>(R);
  long sum_best_s = 0, sum_s = 0, sum_best_r = 0, sum_r = 0;
  long double same_seg = 0, same_room = 0;
  for (std::size_t s = 0; s < S; ++s) {
    sc.segment_precision.push_back(static_cast<double>(best_s[s]) / seg_n[s]);
    sum_best_s += best_s[s], sum_s += seg_n[s];
    same_seg += pairs(seg_n[s]);
  }
  for (std::size_t r = 0; r < R; ++r) {
    sc.room_recall.push_back(static_cast<double>(best_r[r]) / room_n[r]);
    sum_best_r += best_r[r], sum_r += room_n[r];
    same_room += pairs(room_n[r]);
  }
  sc.precision = meanStd(sc.segment_precision).mean;
  sc.recall = meanStd(sc.room_recall).mean;
  sc.precision_pooled = sum_s > 0 ? static_cast<double>(sum_best_s) / sum_s : 0;
  sc.recall_pooled = sum_r > 0 ? static_cast<double>(sum_best_r) / sum_r : 0;

  const long double all = pairs(universe);
  const long double fp = same_seg - tp, fn = same_room - tp, tn = all - same_seg - same_room + tp;
  const long double den = (tp + fp) * (tp + fn) * (tn + fp) * (tn + fn);
  if (den > 0)
    sc.mcc = static_cast<double>((tp * tn - fp * fn) / std::sqrt(den));
  else
    sc.mcc = (fp == 0 && fn == 0 && universe > 0) ? 1.0 : 0.0;
  return sc;
}

// ---------------------------------------------------------------- overlay, JSON -----------

void writeSegmentationOverlay(const std::string& path, const GridMap& map, const Segmentation& seg,
                              const TopoGraph* topo, const io::LabelRaster* rooms) {
  if (!map.grid) throw Error(path + ": no map to draw");
  render::MapImage m = render::renderGrid(*map.grid);
  render::drawRegions(m, seg.labels);
  if (rooms && rooms->width == m.img.cols && rooms->height == m.img.rows) {
    // Ground-truth room outlines: room pixels with a 4-neighbour outside the room.
    for (int r = 0; r < rooms->height; ++r)
      for (int c = 0; c < rooms->width; ++c) {
        const std::int32_t l = rooms->at(c, r);
        if (l <= 0) continue;
        const bool border = c == 0 || r == 0 || c == rooms->width - 1 || r == rooms->height - 1 ||
                            rooms->at(c - 1, r) != l || rooms->at(c + 1, r) != l ||
                            rooms->at(c, r - 1) != l || rooms->at(c, r + 1) != l;
        if (border) m.img.at<cv::Vec3b>(r, c) = {0, 0, 150};
      }
  }
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".svg" || ext == ".SVG") {
    // Vector graph over the raster regions: ids and edges stay sharp when zoomed.
    const TopoGraph none;
    writeFileAtomically(path, render::topologySvg(m, m.img, topo ? *topo : none), "SVG");
    return;
  }
  if (topo) render::drawTopology(m, *topo);
  render::drawRegionIds(m, seg);
  io::writeBgrImage(path, m.img.cols, m.img.rows, m.img.ptr());
}

// ---------------------------------------------------------------- exploration -------------

struct ExplorationSimulator::State {
  ExplorationOptions opt;
  int W = 0, H = 0;
  double res = 0;
  std::vector<std::uint8_t> truth_free;    // image orientation, 1 = free
  std::vector<std::int8_t> known;          // -1 unknown, 0 free, 1 occupied
  std::vector<std::uint8_t> in_component;  // the start's free component
  std::size_t component_size = 0, component_revealed = 0;
  int robot = 0;  // pixel index
  double path_m = 0;
  std::size_t scans = 0;
  bool started = false;
  std::shared_ptr<Grid> grid;
  GridMap map;
  std::vector<int> parent;  // BFS scratch (-2 = not visited)
  std::vector<int> queue;
  std::vector<int> plan;  // remaining path to the current goal (goal last)

  int col(int i) const { return i % W; }
  int row(int i) const { return i / W; }

  // Reveals by ray casting (exact grid traversal: no ray slips between two wall pixels that
  // touch at a corner) and the robot's 8-neighbourhood (so the cell reached is no frontier).
  std::vector<int> scan() {
    std::vector<int> revealed;
    auto reveal = [&](int i) {
      if (known[i] != -1) return;
      known[i] = truth_free[i] ? 0 : 1;
      if (truth_free[i] && in_component[i]) ++component_revealed;
      revealed.push_back(i);
    };
    const int rc = col(robot), rr = row(robot);
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc) {
        const int c = rc + dc, r = rr + dr;
        if (c >= 0 && r >= 0 && c < W && r < H) reveal(r * W + c);
      }
    const double range = opt.sensor_range / res;  // in cells
    const double px = rc + 0.5, py = rr + 0.5;
    constexpr double kInf = std::numeric_limits<double>::infinity();
    for (int k = 0; k < opt.rays; ++k) {
      const double a = 2.0 * M_PI * k / opt.rays;
      const double dx = std::cos(a), dy = std::sin(a);
      int c = rc, r = rr;
      const int sx = dx > 0 ? 1 : -1, sy = dy > 0 ? 1 : -1;
      const double tdx = std::abs(dx) > 1e-12 ? 1.0 / std::abs(dx) : kInf;
      const double tdy = std::abs(dy) > 1e-12 ? 1.0 / std::abs(dy) : kInf;
      double tx = std::abs(dx) > 1e-12 ? (dx > 0 ? c + 1 - px : px - c) * tdx : kInf;
      double ty = std::abs(dy) > 1e-12 ? (dy > 0 ? r + 1 - py : py - r) * tdy : kInf;
      while (true) {
        const int i = r * W + c;
        reveal(i);
        if (!truth_free[i]) break;
        const double t = std::min(tx, ty);
        if (t > range) break;
        if (tx < ty)
          c += sx, tx += tdx;
        else
          r += sy, ty += tdy;
        if (c < 0 || r < 0 || c >= W || r >= H) break;
      }
    }
    return revealed;
  }

  bool frontier(int i) const {
    const int c = col(i), r = row(i);
    return (c > 0 && known[i - 1] == -1) || (c < W - 1 && known[i + 1] == -1) ||
           (r > 0 && known[i - W] == -1) || (r < H - 1 && known[i + W] == -1);
  }

  // BFS over revealed free cells from the robot to the nearest frontier; its path (robot
  // excluded, goal last), or empty when none is reachable.
  std::vector<int> pathToNearestFrontier() {
    std::fill(parent.begin(), parent.end(), -2);
    queue.clear();
    queue.push_back(robot);
    parent[robot] = -1;
    static const int kDc[8] = {1, 0, -1, 0, 1, -1, -1, 1};
    static const int kDr[8] = {0, 1, 0, -1, 1, 1, -1, -1};
    auto knownFree = [&](int c, int r) {
      return c >= 0 && r >= 0 && c < W && r < H && known[r * W + c] == 0;
    };
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const int i = queue[head];
      if (frontier(i)) {
        std::vector<int> path;
        for (int j = i; j != robot; j = parent[j]) path.push_back(j);
        std::reverse(path.begin(), path.end());
        return path;
      }
      const int c = col(i), r = row(i);
      for (int k = 0; k < 8; ++k) {
        const int nc = c + kDc[k], nr = r + kDr[k];
        if (!knownFree(nc, nr)) continue;
        if (k >= 4 && !(knownFree(nc, r) && knownFree(c, nr))) continue;  // no corner cutting
        const int j = nr * W + nc;
        if (parent[j] != -2) continue;
        parent[j] = i;
        queue.push_back(j);
      }
    }
    return {};
  }

  void publish(const std::vector<int>& revealed) {
    Box2 changed;
    for (int i : revealed) {
      const int c = col(i), cy = H - 1 - row(i);
      changed.extend(c * res, cy * res);
      changed.extend((c + 1) * res, (cy + 1) * res);
    }
    detail::publishReveal(
        grid, map, W, H, res, revealed, [&](int i) { return known[i] == 0; }, changed);
  }
};

ExplorationSimulator::ExplorationSimulator(const io::GrayImage& image, double resolution,
                                           const ExplorationOptions& options, int free_threshold)
    : s_(std::make_unique<State>()) {
  State& s = *s_;
  s.opt = options;
  s.W = image.width;
  s.H = image.height;
  s.res = resolution;
  if (!(resolution > 0)) throw Error("ExplorationSimulator: resolution must be > 0");
  if (s.opt.rays < 1) throw Error("ExplorationSimulator: rays must be >= 1");
  const std::size_t N = static_cast<std::size_t>(s.W) * s.H;
  s.truth_free.assign(N, 0);
  cv::Mat free(s.H, s.W, CV_8U, cv::Scalar(0));
  for (int r = 0; r < s.H; ++r)
    for (int c = 0; c < s.W; ++c)
      if (image.at(c, r) >= free_threshold) {
        s.truth_free[static_cast<std::size_t>(r) * s.W + c] = 1;
        free.at<std::uint8_t>(r, c) = 255;
      }
  cv::Mat comp, stats, centroids, dist;
  const int n = cv::connectedComponentsWithStats(free, comp, stats, centroids, 4, CV_32S);
  if (n < 2) throw Error("ExplorationSimulator: the map has no free pixel");
  int largest = 1;
  for (int k = 2; k < n; ++k)
    if (stats.at<int>(k, cv::CC_STAT_AREA) > stats.at<int>(largest, cv::CC_STAT_AREA)) largest = k;
  cv::distanceTransform(free, dist, cv::DIST_L2, 5);
  s.in_component.assign(N, 0);
  float best = -1;
  for (int r = 0; r < s.H; ++r)
    for (int c = 0; c < s.W; ++c) {
      if (comp.at<int>(r, c) != largest) continue;
      s.in_component[static_cast<std::size_t>(r) * s.W + c] = 1;
      ++s.component_size;
      if (dist.at<float>(r, c) > best) best = dist.at<float>(r, c), s.robot = r * s.W + c;
    }
  s.known.assign(N, -1);
  s.parent.assign(N, -2);
}

ExplorationSimulator::~ExplorationSimulator() = default;

bool ExplorationSimulator::step() {
  State& s = *s_;
  const int hops_per_scan = std::max(1, static_cast<int>(std::lround(s.opt.scan_spacing / s.res)));
  while (s.scans < s.opt.max_scans) {
    if (s.started) {
      // Replan only when the goal stopped being a frontier: known cells never change, so
      // the rest of the plan stays free, and BFS over the whole map is the costly part.
      if (s.plan.empty() || !s.frontier(s.plan.back())) s.plan = s.pathToNearestFrontier();
      if (s.plan.empty()) return false;
      const int hops = std::min<int>(hops_per_scan, static_cast<int>(s.plan.size()));
      int prev = s.robot;
      for (int h = 0; h < hops; ++h) {
        const int next = s.plan[h];
        const bool diagonal = s.col(next) != s.col(prev) && s.row(next) != s.row(prev);
        s.path_m += (diagonal ? M_SQRT2 : 1.0) * s.res;
        prev = next;
      }
      s.plan.erase(s.plan.begin(), s.plan.begin() + hops);
      s.robot = prev;
    }
    s.started = true;
    ++s.scans;
    const std::vector<int> revealed = s.scan();
    if (revealed.empty()) continue;  // nothing new: no map update, keep going
    s.publish(revealed);
    return true;
  }
  return false;
}

const GridMap& ExplorationSimulator::map() const { return s_->map; }
Point2 ExplorationSimulator::robot() const {
  const State& s = *s_;
  return {(s.col(s.robot) + 0.5) * s.res, (s.H - 1 - s.row(s.robot) + 0.5) * s.res};
}
double ExplorationSimulator::pathLength() const { return s_->path_m; }
std::size_t ExplorationSimulator::scans() const { return s_->scans; }
double ExplorationSimulator::coverage() const {
  return s_->component_size ? static_cast<double>(s_->component_revealed) / s_->component_size : 0;
}

IncrementalResult evaluateIncremental(Segmenter& segmenter, MapReveal& reveal,
                                      const io::LabelRaster& rooms,
                                      const std::function<void(std::size_t, double)>& progress) {
  IncrementalResult out;
  bool have_previous = false;
  while (reveal.step()) {
    const auto t0 = std::chrono::steady_clock::now();
    Segmentation s =
        segmenter.segment(reveal.map(), have_previous ? &out.final_segmentation : nullptr);
    out.update_ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    out.final_segmentation = std::move(s);
    have_previous = true;
    if (progress) progress(out.update_ms.size(), reveal.coverage());
  }
  out.final_map = reveal.map();
  out.coverage = reveal.coverage();
  out.path_length_m = reveal.pathLength();
  io::LabelRaster labels = toRaster(out.final_segmentation.labels);
  if (labels.labels.empty()) {  // no update at all, or a segmenter that labelled nothing
    labels.width = rooms.width;
    labels.height = rooms.height;
    labels.labels.assign(rooms.labels.size(), 0);
  }
  if (labels.width != rooms.width || labels.height != rooms.height)
    throw Error("the segmenter returned a " + std::to_string(labels.width) + " x " +
                std::to_string(labels.height) + " label image for a " +
                std::to_string(rooms.width) + " x " + std::to_string(rooms.height) + " map");
  out.final_score = scoreSegmentation(labels, rooms);
  return out;
}

IncrementalResult evaluateIncremental(Segmenter& segmenter, const io::GrayImage& image,
                                      const io::LabelRaster& rooms, double resolution,
                                      const ExplorationOptions& options,
                                      const std::function<void(std::size_t, double)>& progress) {
  if (rooms.width != image.width || rooms.height != image.height)
    throw Error("evaluateIncremental: the rooms are " + std::to_string(rooms.width) + " x " +
                std::to_string(rooms.height) + " px, the map " + std::to_string(image.width) +
                " x " + std::to_string(image.height));
  ExplorationSimulator sim(image, resolution, options);
  return evaluateIncremental(segmenter, sim, rooms, progress);
}

}  // namespace asf::evaluation
