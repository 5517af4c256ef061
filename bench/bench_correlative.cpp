// Correlative scan matching (plugins/frontend_icp_graph/correlative_matcher.h): branch and
// bound against scoring the whole lattice (levels = 1: every pose is a leaf, nothing pruned),
// on a 360-ray-like scan of a 20 m x 12 m floor of rooms, windows of +-2 m / +-20 deg and
// +-6 m. The ratio bb / exhaustive is the figure to quote (same run, same machine).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "../plugins/frontend_icp_graph/correlative_matcher.h"

namespace {

using asf::icp_graph::CorrelativeOptions;
using asf::icp_graph::LikelihoodGrid;
using asf::icp_graph::Points2;

struct Scene {
  std::vector<float> rx, ry, sx, sy;
};

void segment(std::vector<float>& x, std::vector<float>& y, double x0, double y0, double x1,
             double y1) {
  const int n = std::max(1, static_cast<int>(std::hypot(x1 - x0, y1 - y0) / 0.05));
  for (int i = 0; i <= n; ++i) {
    x.push_back(static_cast<float>(x0 + (x1 - x0) * i / n));
    y.push_back(static_cast<float>(y0 + (y1 - y0) * i / n));
  }
}

const Scene& scene() {
  static const Scene s = [] {
    Scene c;
    // Outer walls and three rooms with doors along a corridor at y in [5, 7].
    segment(c.rx, c.ry, 0, 0, 20, 0);
    segment(c.rx, c.ry, 20, 0, 20, 12);
    segment(c.rx, c.ry, 20, 12, 0, 12);
    segment(c.rx, c.ry, 0, 12, 0, 0);
    for (double x : {6.0, 13.0}) {
      segment(c.rx, c.ry, x, 0, x, 5);
      segment(c.rx, c.ry, x, 7, x, 12);
    }
    for (double x0 : {0.0, 6.0, 13.0}) {
      segment(c.rx, c.ry, x0, 5, x0 + 2.5, 5);
      segment(c.rx, c.ry, x0 + 3.5, 5, x0 + 6, 5);
      segment(c.rx, c.ry, x0, 7, x0 + 4, 7);
    }
    // The scan: points within 8 m of (9, 6), in the frame of (9, 6, 0.3), 1 cm noise.
    std::mt19937 rng(1);
    std::normal_distribution<double> n(0, 0.01);
    const double c0 = std::cos(0.3), s0 = std::sin(0.3);
    for (std::size_t i = 0; i < c.rx.size(); i += 3) {
      const double dx = c.rx[i] - 9, dy = c.ry[i] - 6;
      if (std::hypot(dx, dy) > 8) continue;
      c.sx.push_back(static_cast<float>(c0 * dx + s0 * dy + n(rng)));
      c.sy.push_back(static_cast<float>(-s0 * dx + c0 * dy + n(rng)));
    }
    return c;
  }();
  return s;
}

// Arguments: window [m], branch-and-bound levels (1 = exhaustive).
void BM_CorrelativeMatch(benchmark::State& state) {
  const Scene& s = scene();
  const double window = static_cast<double>(state.range(0));
  const int levels = static_cast<int>(state.range(1));
  const LikelihoodGrid grid(Points2{s.rx, s.ry}, 0.1, 0.1, levels, 0.0);
  CorrelativeOptions o;
  o.window_xy = window;
  o.window_phi = 20 * M_PI / 180;
  const Eigen::Vector3d guess(9.0 + 0.6, 6.0 - 0.4, 0.3 + 0.1);
  std::size_t scored = 0, lattice = 0;
  double score = 0;
  for (auto _ : state) {
    const auto r = asf::icp_graph::correlativeMatch(grid, Points2{s.sx, s.sy}, guess, o);
    scored = r.scored;
    lattice = r.lattice;
    score = r.score;
    benchmark::DoNotOptimize(r);
  }
  state.counters["scored"] = static_cast<double>(scored);
  state.counters["lattice"] = static_cast<double>(lattice);
  state.counters["score"] = score;
  state.counters["points"] = static_cast<double>(s.sx.size());
}
BENCHMARK(BM_CorrelativeMatch)
    ->Args({2, 1})
    ->Args({2, 6})
    ->Args({6, 1})
    ->Args({6, 7})
    ->Unit(benchmark::kMillisecond);

/// Range along the ray from (x, y) at angle a to the nearest wall of the scene (max `far`).
double castRay(const std::vector<std::array<double, 4>>& walls, double x, double y, double a,
               double far) {
  const double dx = std::cos(a), dy = std::sin(a);
  double best = far;
  for (const auto& w : walls) {
    const double ex = w[2] - w[0], ey = w[3] - w[1];
    const double den = dx * ey - dy * ex;
    if (std::abs(den) < 1e-12) continue;
    const double t = ((w[0] - x) * ey - (w[1] - y) * ex) / den;
    const double u = ((w[0] - x) * dy - (w[1] - y) * dx) / den;
    if (t > 0 && u >= 0 && u <= 1) best = std::min(best, t);
  }
  return best;
}

/// A 181-ray (1 degree) 180-degree scan from (x, y, phi), in the sensor frame, 1 cm noise.
void scanFrom(const std::vector<std::array<double, 4>>& walls, double x, double y, double phi,
              std::mt19937& rng, std::vector<float>& sx, std::vector<float>& sy) {
  std::normal_distribution<double> n(0, 0.01);
  for (int k = 0; k <= 180; ++k) {
    const double b = (k - 90) * M_PI / 180;
    const double r = castRay(walls, x, y, phi + b, 30.0);
    if (r >= 30.0) continue;
    sx.push_back(static_cast<float>((r + n(rng)) * std::cos(b)));
    sy.push_back(static_cast<float>((r + n(rng)) * std::sin(b)));
  }
}

// A loop search as the front-end runs it on a real log (plugins/frontend_icp_graph/
// loop_search.cpp): a 50 m x 40 m hall with pillars and a side corridor; the reference is 13
// scans along a path (grid built in the loop, as per candidate), the scan from 5 m and 40
// degrees off the estimate; window +-8 m / +-60 degrees, 6 levels; best pose, then the
// ambiguity run outside its peak.
void BM_LoopSearchHall(benchmark::State& state) {
  std::vector<std::array<double, 4>> walls = {
      {0, 0, 50, 0}, {50, 0, 50, 40}, {50, 40, 0, 40}, {0, 40, 0, 0}, {20, 18, 45, 18}};
  for (double px : {10.0, 20.0, 30.0, 40.0})  // 1 m square pillars
    for (double py : {8.0, 30.0}) {
      walls.push_back({px, py, px + 1, py});
      walls.push_back({px + 1, py, px + 1, py + 1});
      walls.push_back({px + 1, py + 1, px, py + 1});
      walls.push_back({px, py + 1, px, py});
    }
  std::mt19937 rng(7);
  std::vector<float> rx, ry;
  for (int k = 0; k < 13; ++k) {  // the reference, in the frame of its middle scan (x = 14)
    std::vector<float> sx, sy;
    const double x = 8 + k, y = 12 + 0.3 * k, phi = 0.2;
    scanFrom(walls, x, y, phi, rng, sx, sy);
    const double c = std::cos(phi), s = std::sin(phi);
    for (std::size_t i = 0; i < sx.size(); ++i) {
      rx.push_back(static_cast<float>(x - 14 + c * sx[i] - s * sy[i]));
      ry.push_back(static_cast<float>(y - 13.8 + s * sx[i] + c * sy[i]));
    }
  }
  std::vector<float> qx, qy;
  scanFrom(walls, 17, 14, 0.9, rng, qx, qy);
  const Eigen::Vector3d guess(3 + 4, 0.2 - 3, 0.7 - 0.5);  // truth (3, 0.2, 0.7) in the reference
  CorrelativeOptions o;
  o.window_xy = 8;
  o.window_phi = 60 * M_PI / 180;
  double score = 0, second = 0, error = 0;
  std::size_t scored = 0;
  for (auto _ : state) {
    const LikelihoodGrid grid(Points2{rx, ry}, 0.1, 0.1, 6, 0.0);
    const asf::icp_graph::CorrelativeSearch search(grid, Points2{qx, qy}, guess, o);
    const auto best = search.run(0.5);
    const auto other = search.run(0.9 * best.score, best.pose.head<2>(), 0.6);
    score = best.score, second = other.found ? other.score : 0, scored = best.scored;
    error = (best.pose.head<2>() - Eigen::Vector2d(3, 0.2)).norm();
    benchmark::DoNotOptimize(other);
  }
  state.counters["score"] = score;
  state.counters["second"] = second;
  state.counters["error_m"] = error;  // of the best pose from the truth
  state.counters["scored"] = static_cast<double>(scored);
  state.counters["points"] = static_cast<double>(qx.size());
}
BENCHMARK(BM_LoopSearchHall)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
