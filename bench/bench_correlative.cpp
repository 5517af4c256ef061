// Correlative scan matching (plugins/frontend_icp_graph/correlative_matcher.h): branch and
// bound against scoring the whole lattice (levels = 1: every pose is a leaf, nothing pruned),
// on a 360-ray-like scan of a 20 m x 12 m floor of rooms, windows of +-2 m / +-20 deg and
// +-6 m. The ratio bb / exhaustive is the figure to quote (same run, same machine).
#include <benchmark/benchmark.h>

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

}  // namespace

BENCHMARK_MAIN();
