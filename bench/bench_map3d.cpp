// The 3D map layer (libs/mapping/include/asf/mapping/map3d.h, issue 9): insertion rate and memory of
// asf::mapping::Map3d against the plain OctoMap calls a user would write (octomap::OcTree::
// insertPointCloud(cloud, origin), the cloud already in the map frame), on the same clouds,
// at 5 cm and 10 cm voxels.
//
// Scene: a 10 x 8 x 3 m room (240 m^3) with two pillars and a table, scanned by a synthetic 360 x 90
// degree sensor (400 azimuths x 256 elevations = 102,400 rays, exact ray-box hits) 1.2 m up
// from 4 robot poses. One iteration builds a fresh tree from all 4 clouds (409,600 points).
// Counters: points/s (items_per_second, over CPU time: the work is single-threaded and the
// machine is shared), bytes per m^3 of known space (memoryUsage() /
// volume of the leaves), known m^3, leaves. Map3d's time includes its sensor-to-map transform
// and filtering; the baseline gets the map-frame cloud ready made.
//
//   build/bench/bench_map3d --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include <asf/mapping/map3d.h>
#include <benchmark/benchmark.h>
#include <octomap/OcTree.h>

#include <cmath>
#include <limits>
#include <map>
#include <string>

namespace {

using mrpt::poses::CPose2D;
using mrpt::poses::CPose3D;

struct Box {
  Eigen::Vector3d lo, hi;
};

/// Distance along the ray to the room's inside walls or the first obstacle box.
double castRay(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Box& room,
               const std::vector<Box>& obstacles) {
  double t = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {  // leaving the room (the sensor is inside)
    if (d[a] > 1e-12) t = std::min(t, (room.hi[a] - o[a]) / d[a]);
    if (d[a] < -1e-12) t = std::min(t, (room.lo[a] - o[a]) / d[a]);
  }
  for (const Box& b : obstacles) {  // slab test
    double t0 = 0, t1 = t;
    for (int a = 0; a < 3 && t0 <= t1; ++a) {
      if (std::abs(d[a]) < 1e-12) {
        if (o[a] < b.lo[a] || o[a] > b.hi[a]) t1 = -1;
        continue;
      }
      double u = (b.lo[a] - o[a]) / d[a], v = (b.hi[a] - o[a]) / d[a];
      if (u > v) std::swap(u, v);
      t0 = std::max(t0, u);
      t1 = std::min(t1, v);
    }
    if (t0 <= t1 && t0 > 0) t = std::min(t, t0);
  }
  return t;
}

struct Scene {
  std::vector<CPose3D> sensors;                  // sensor poses in the map
  std::vector<std::vector<Eigen::Vector3f>> local;  // clouds in the sensor frame
  std::vector<octomap::Pointcloud> world;        // the same clouds in the map frame
  std::size_t points = 0;

  Scene() {
    // Surfaces off the voxel borders (multiples of 5 cm), so float rounding cannot move a
    // wall by a voxel between the two ways of computing the same points.
    const double e = 0.013;
    const Box room{{-e, -e, -e}, {10 + e, 8 + e, 3 + e}};
    const std::vector<Box> obstacles{{{3 + e, 3 + e, -e}, {3.4 + e, 3.4 + e, 3 + e}},  // pillars
                                     {{7 + e, 5 + e, -e}, {7.4 + e, 5.4 + e, 3 + e}},
                                     {{5 + e, 1 + e, 0.7 + e}, {6.2 + e, 1.8 + e, 0.75 + e}}};
    const CPose3D on_robot(0, 0, 1.2, 0, 0, 0);
    for (const CPose2D& p : {CPose2D(2, 2, 0), CPose2D(8, 2, 1.5), CPose2D(8, 6.5, 3.0),
                             CPose2D(2, 6, -1.5)}) {
      const CPose3D s = CPose3D(p) + on_robot;
      sensors.push_back(s);
      std::vector<Eigen::Vector3f> loc;
      octomap::Pointcloud w;
      const Eigen::Vector3d o(s.x(), s.y(), s.z());
      const auto R = s.getRotationMatrix().asEigen();
      for (int i = 0; i < 256; ++i) {
        const double el = (-45.0 + 90.0 * i / 255) * M_PI / 180;
        for (int j = 0; j < 400; ++j) {
          const double az = 2 * M_PI * j / 400;
          const Eigen::Vector3d dl(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                                   std::sin(el));
          const Eigen::Vector3d dw = R * dl;
          const double t = castRay(o, dw, room, obstacles);
          const Eigen::Vector3d pl = t * dl, pw = o + t * dw;
          loc.emplace_back(pl.cast<float>());
          w.push_back(static_cast<float>(pw.x()), static_cast<float>(pw.y()),
                      static_cast<float>(pw.z()));
        }
      }
      points += loc.size();
      local.push_back(std::move(loc));
      world.push_back(std::move(w));
    }
  }
};

const Scene& scene() {
  static const Scene s;
  return s;
}

double resolutionOf(const benchmark::State& state) { return state.range(0) / 100.0; }

void report(benchmark::State& state, std::size_t points, std::size_t bytes, double volume,
            std::size_t leaves) {
  state.SetItemsProcessed(static_cast<std::int64_t>(points) * state.iterations());
  state.counters["bytes_per_m3"] = bytes / volume;
  state.counters["known_m3"] = volume;
  state.counters["MiB"] = bytes / 1048576.0;
  state.counters["leaves"] = static_cast<double>(leaves);
}

void BM_Map3d(benchmark::State& state, const char* flag) {
  const Scene& sc = scene();
  std::size_t n = 0;
  const asf::KeySpec* keys = asf::mapping::Map3d::keys(n);
  const double res = resolutionOf(state);
  const asf::Params p = asf::Params::fromSpecs(
      "map3d", keys, n,
      flag ? std::map<std::string, std::string>{{"resolution", std::to_string(res)}, {flag, "true"}}
           : std::map<std::string, std::string>{{"resolution", std::to_string(res)}});
  asf::mapping::Map3dStats s;
  for (auto _ : state) {
    asf::mapping::Map3d map;
    map.configure(p);
    for (std::size_t k = 0; k < sc.local.size(); ++k) map.insertPoints(sc.local[k], sc.sensors[k]);
    state.PauseTiming();
    s = map.stats();
    state.ResumeTiming();
  }
  report(state, sc.points, s.memory_bytes, s.known_volume_m3, s.occupied_leaves + s.free_leaves);
}

void BM_OctoMapPlain(benchmark::State& state) {
  const Scene& sc = scene();
  const double res = resolutionOf(state);
  std::size_t bytes = 0, leaves = 0;
  double volume = 0;
  for (auto _ : state) {
    octomap::OcTree tree(res);  // OctoMap's defaults: hit 0.7, miss 0.4, clamping 0.12/0.97
    for (std::size_t k = 0; k < sc.world.size(); ++k) {
      const CPose3D& s = sc.sensors[k];
      tree.insertPointCloud(sc.world[k], octomap::point3d(s.x(), s.y(), s.z()));
    }
    state.PauseTiming();
    bytes = tree.memoryUsage();
    leaves = 0;
    volume = 0;
    for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it, ++leaves)
      volume += std::pow(it.getSize(), 3);
    state.ResumeTiming();
  }
  report(state, sc.points, bytes, volume, leaves);
}

// Argument: the voxel size in cm.
// Map3d: the defaults, and with [map3d] lazy_eval = true or discretize = true.
BENCHMARK_CAPTURE(BM_Map3d, default, nullptr)->Arg(5)->Arg(10)->Unit(benchmark::kMillisecond)
    ->Iterations(2);
BENCHMARK_CAPTURE(BM_Map3d, lazy_eval, "lazy_eval")->Arg(5)->Arg(10)
    ->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK_CAPTURE(BM_Map3d, discretize, "discretize")->Arg(5)->Arg(10)
    ->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK(BM_OctoMapPlain)->Arg(5)->Arg(10)->Unit(benchmark::kMillisecond)
    ->Iterations(2);

}  // namespace

BENCHMARK_MAIN();
