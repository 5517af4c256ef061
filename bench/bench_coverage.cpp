// Coverage bookkeeping per map version: asf::mapping::freeArea (a scan of the whole grid, what a run
// did for every time-series row) against asf::mapping::MapAreaTracker::update (the cells in the
// version's change box, old and new grid), on a grid of infinite-corridor's size (~25 million
// cells at 5 cm) with one keyframe's box (15 m insertion range: a 30 m square).
#include <asf/mapping/coverage.h>
#include <benchmark/benchmark.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <memory>

namespace {

using Grid = mrpt::maps::COccupancyGridMap2D;

/// A half-free grid of side `side_m` metres, 5 cm cells.
std::shared_ptr<Grid> grid(double side_m) {
  const float h = static_cast<float>(side_m / 2);
  auto g = std::make_shared<Grid>(-h, h, -h, h, 0.05f);
  for (unsigned y = 0; y < g->getSizeY(); ++y)
    for (unsigned x = 0; x < g->getSizeX(); x += 2) g->setCell(x, y, 0.9f);
  return g;
}

asf::GridMap version(std::shared_ptr<const Grid> g, std::uint64_t v, double box_half_m) {
  asf::GridMap m;
  m.grid = std::move(g);
  m.version = v;
  m.changed.extend(-box_half_m, -box_half_m);
  m.changed.extend(box_half_m, box_half_m);
  return m;
}

void BM_FreeAreaFullScan(benchmark::State& state) {
  const auto g = grid(static_cast<double>(state.range(0)));
  const asf::GridMap m = version(g, 1, 15);
  for (auto _ : state) benchmark::DoNotOptimize(asf::mapping::freeArea(m));
  state.counters["cells"] = static_cast<double>(g->getSizeX()) * g->getSizeY();
}

void BM_TrackerUpdate(benchmark::State& state) {
  const auto a = grid(static_cast<double>(state.range(0)));
  const auto b = std::make_shared<Grid>(*a);  // the next version: another object
  asf::mapping::MapAreaTracker t;
  std::uint64_t v = 1;
  t.update(version(a, v, 15));
  for (auto _ : state) {
    ++v;
    t.update(version(v % 2 ? a : b, v, 15));
    benchmark::DoNotOptimize(t.freeArea());
  }
  state.counters["cells"] = static_cast<double>(a->getSizeX()) * a->getSizeY();
}

}  // namespace

// Grid sides 100 m (4 M cells) and 250 m (25 M cells).
BENCHMARK(BM_FreeAreaFullScan)->Arg(100)->Arg(250)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TrackerUpdate)->Arg(100)->Arg(250)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
