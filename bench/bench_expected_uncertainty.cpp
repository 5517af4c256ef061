// Expected-uncertainty planning (asf/planning/expected_uncertainty.h): Algorithm 1
// on one path of m steps (m = 10, 100, 1000), exact (every hypothesis kept: O(m^2) window
// integrals) and with the default pruning of negligible hypotheses; and a sweep of start/goal
// pairs on intel.g2o (skipped without ../shared/datasets/g2o/intel.g2o): search of the reduced
// graph plus evaluation of every candidate path, per criterion.
//
// Also the generalized Voronoi graph and its virtual edges (asf/planning/voronoi_graph.h) on the
// shipped cave world (datasets/cave/cave_filled.png as a 5 cm grid).
//
//   build/bench/bench_expected_uncertainty [--benchmark_filter=Intel|Cave]
#include <asf/backend.h>
#include <asf/planning/expected_uncertainty.h>
#include <asf/framework/registry.h>
#include <asf/planning/voronoi_graph.h>
#include <benchmark/benchmark.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <opencv2/imgcodecs.hpp>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <random>
#include <set>

namespace {

namespace planning = asf::planning;

/// A corridor of m steps with a consistent joint covariance: node i's marginal grows
/// linearly, Cov(x_i, x_j) = Sigma_min(i, j) (a random walk), every cross block present.
struct Corridor {
  asf::PoseGraph g;
  asf::Marginals m;
  std::vector<asf::NodeId> path;
  explicit Corridor(int steps) {
    const Eigen::Matrix3d step = Eigen::Vector3d(0.002, 0.002, 0.0005).asDiagonal();
    for (int i = 0; i <= steps; ++i) {
      g.addNode(mrpt::poses::CPose2D(0.5 * i, 0.1 * std::sin(i), 0.05 * std::cos(i)));
      path.push_back(static_cast<asf::NodeId>(i));
      m.node.push_back(step * i);
      if (i == 0) continue;
      asf::PoseEdge e;
      e.from = i - 1;
      e.to = i;
      e.mean = g.nodes[i].pose - g.nodes[i - 1].pose;
      e.information = Eigen::Vector3d(400, 400, 1600).asDiagonal();
      g.addEdge(e);
    }
    for (int i = 0; i <= steps; ++i)
      for (int j = i + 1; j <= steps; ++j)
        m.cross[{static_cast<asf::NodeId>(i), static_cast<asf::NodeId>(j)}] = step * i;
  }
};

void BM_EvaluatePath(benchmark::State& state) {
  const Corridor c(static_cast<int>(state.range(0)));
  const planning::PathModel model = planning::makePathModel(c.g, &c.m, c.path);
  planning::CriterionOptions o;
  o.prune_below = state.range(1) ? 1e-12 : 0.0;
  std::size_t evaluations = 0;
  for (auto _ : state) {
    const planning::RelocProbFn p = planning::relocalizationProbability(model, o.reloc);
    const auto r = planning::expectedCovariance(model, p, o.prune_below);
    evaluations = r.evaluations;
    benchmark::DoNotOptimize(r.mean);
  }
  state.counters["window_integrals"] = static_cast<double>(evaluations);
}
BENCHMARK(BM_EvaluatePath)
    ->ArgNames({"m", "pruned"})
    ->Args({10, 0})->Args({100, 0})->Args({1000, 0})
    ->Args({10, 1})->Args({100, 1})->Args({1000, 1})
    ->Unit(benchmark::kMillisecond);

/// The Gaussian window integral alone (3D, correlated), per lattice size.
void BM_WindowIntegral(benchmark::State& state) {
  Eigen::Matrix3d cov;
  cov << 0.04, 0.01, 0.003, 0.01, 0.05, 0.002, 0.003, 0.002, 0.02;
  const Eigen::Vector3d half(0.3, 0.3, 0.5236);
  for (auto _ : state)
    benchmark::DoNotOptimize(planning::gaussianBoxProbability(Eigen::Vector3d::Zero(), cov, -half,
                                                        half, static_cast<int>(state.range(0))));
}
BENCHMARK(BM_WindowIntegral)->Arg(128)->Arg(1024)->Unit(benchmark::kMicrosecond);

// ---- intel.g2o sweep ------------------------------------------------------------------

const std::string kIntel = ASF_BENCH_SOURCE_DIR "/../shared/datasets/g2o/intel.g2o";
constexpr int kPairs = 20;

/// The planners' candidate search with the defaults of plan-eval's config: all simple routes
/// of the alias-merged reduced graph while at most 200, else Yen's 20 shortest and 20 routes
/// of the penalty method, plus the Dijkstra path.
planning::PathSearchOptions sweepSearch() {
  planning::PathSearchOptions o;
  o.max_paths = 200;
  o.k_paths = 20;
  o.diverse_paths = 20;
  return o;
}

struct Intel {
  asf::PoseGraph g;
  asf::Marginals m;
  std::vector<std::pair<asf::NodeId, asf::NodeId>> pairs;
  bool ok = false;
  Intel() {
    if (!std::filesystem::exists(kIntel)) return;
    g = asf::readG2o(kIntel);
    auto info = asf::framework::Registry::loadFile(ASF_BENCH_PLUGIN_DIR "/backend_sparse_lm.so");
    auto be = asf::framework::Registry::create<asf::Backend>(info);
    be->setMinLoggingLevel(mrpt::system::LVL_ERROR);
    be->configure(asf::Params::fromSpecs("sparse_lm", info->descriptor->keys,
                                         info->descriptor->num_keys),
                  asf::PluginContext{});
    be->optimize(g);  // the file is the raw initial guess; plan on the optimized graph
    std::mt19937 rng(42);
    while (static_cast<int>(pairs.size()) < kPairs) {
      const asf::NodeId s = rng() % g.size(), t = rng() % g.size();
      if (s != t) pairs.emplace_back(s, t);
    }
    // Every cross block (1.5M): the union over the candidates' node pairs is about as large
    // and slower to gather.
    std::vector<std::pair<asf::NodeId, asf::NodeId>> cross;
    cross.reserve(g.size() * (g.size() - 1) / 2);
    for (asf::NodeId a = 0; a < g.size(); ++a)
      for (asf::NodeId b = a + 1; b < g.size(); ++b) cross.emplace_back(a, b);
    m = be->marginals(g, cross);
    ok = true;
  }
};

const Intel& intel() {
  static const Intel i;
  return i;
}

void BM_IntelSearch(benchmark::State& state) {
  // The candidate search alone over the sweep's pairs: search = all capped at 200 (the
  // first slice's depth-first enumeration), or auto (Yen's + penalty routes beyond 200),
  // without / with the alias merge (radius 1 m).
  const Intel& d = intel();
  if (!d.ok) {
    state.SkipWithError("intel.g2o not found (../shared/datasets/g2o)");
    return;
  }
  planning::PathSearchOptions o = sweepSearch();
  o.method = state.range(0) ? planning::SearchMethod::Auto : planning::SearchMethod::All;
  // The depth-first enumeration alone may not find 200 routes in hours: the first slice's
  // 10 s budget per pair.
  if (!state.range(0)) o.max_seconds = 10;
  o.merge_radius = state.range(1) ? 1.0 : 0.0;
  state.SetLabel(std::string(state.range(0) ? "auto" : "all<=200") +
                 (state.range(1) ? ", merged" : ", unmerged"));
  std::size_t paths = 0, vertices = 0, fell_back = 0, capped = 0, timed_out = 0;
  for (auto _ : state) {
    paths = vertices = fell_back = capped = timed_out = 0;
    for (const auto& [s, t] : d.pairs) {
      const auto r = planning::searchPaths(d.g, s, t, o);
      paths += r.paths.size();
      vertices += r.reduced_nodes;
      fell_back += r.fell_back;
      capped += r.capped;
      timed_out += r.timed_out;
    }
  }
  state.counters["timed_out"] = static_cast<double>(timed_out);
  state.counters["pairs"] = kPairs;
  state.counters["paths_per_pair"] = static_cast<double>(paths) / kPairs;
  state.counters["search_vertices"] = static_cast<double>(vertices) / kPairs;
  state.counters["fell_back"] = static_cast<double>(fell_back);
  state.counters["capped"] = static_cast<double>(capped);
}
BENCHMARK(BM_IntelSearch)
    ->Args({0, 0})
    ->Args({0, 1})
    ->Args({1, 0})
    ->Args({1, 1})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

void BM_IntelSweep(benchmark::State& state) {
  // Planning (search + evaluation of every candidate) for kPairs random start/goal pairs
  // of the optimized intel.g2o (1728 nodes).
  const Intel& d = intel();
  if (!d.ok) {
    state.SkipWithError("intel.g2o not found (../shared/datasets/g2o)");
    return;
  }
  const auto c = static_cast<planning::Criterion>(state.range(0));
  state.SetLabel(planning::criterionName(c));
  planning::CriterionOptions o;
  const planning::PathSearchOptions search = sweepSearch();
  std::size_t candidates = 0, capped = 0;
  for (const auto& [s, t] : d.pairs) {  // counters, outside the timing
    const auto paths = planning::searchPaths(d.g, s, t, search);
    candidates += paths.paths.size();
    capped += paths.capped;
  }
  for (auto _ : state)
    for (const auto& [s, t] : d.pairs) {
      asf::PlanRequest req{&d.g, &d.m, nullptr, s, t};
      benchmark::DoNotOptimize(planning::planBest(req, c, o, search).cost);
    }
  state.counters["pairs"] = kPairs;
  state.counters["candidate_paths"] = static_cast<double>(candidates);
  state.counters["capped_pairs"] = static_cast<double>(capped);
  state.counters["nodes"] = static_cast<double>(d.g.size());
}
BENCHMARK(BM_IntelSweep)
    ->Arg(static_cast<int>(planning::Criterion::ExpectedUncertainty))
    ->Arg(static_cast<int>(planning::Criterion::MechanicalWork))
    ->Arg(static_cast<int>(planning::Criterion::SumDopt))
    ->Arg(static_cast<int>(planning::Criterion::Distance))
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

/// The cave world as a fully known grid (dark pixels occupied), 0.05 m per pixel, and a
/// serpentine of pose-graph nodes 1 m apart over its free cells, chained in visiting order
/// (so graph routes are long and the GVG offers shortcuts).
struct CaveMap {
  asf::GridMap map;
  asf::PoseGraph g;
  CaveMap() {
    const cv::Mat img =
        cv::imread(ASF_BENCH_SOURCE_DIR "/datasets/cave/cave_filled.png", cv::IMREAD_GRAYSCALE);
    if (img.empty()) throw std::runtime_error("datasets/cave/cave_filled.png not readable");
    const double res = 0.05;
    auto grid = std::make_shared<mrpt::maps::COccupancyGridMap2D>(
        0.f, static_cast<float>(img.cols * res), 0.f, static_cast<float>(img.rows * res),
        static_cast<float>(res));
    for (int r = 0; r < img.rows; ++r)
      for (int c = 0; c < img.cols; ++c)
        grid->setCell(c, img.rows - 1 - r, img.at<unsigned char>(r, c) > 127 ? 1.0f : 0.0f);
    map.grid = grid;
    map.version = 1;
    bool left = false;
    for (double y = 0.5; y < img.rows * res; y += 1.0, left = !left)
      for (int k = 0; k < img.cols * res; ++k) {
        const double x = left ? img.cols * res - 0.5 - k : 0.5 + k;
        if (grid->getPos(static_cast<float>(x), static_cast<float>(y)) < 0.9f) continue;
        const asf::NodeId id = g.addNode(mrpt::poses::CPose2D(x, y, 0));
        if (id == 0) continue;
        asf::PoseEdge e;
        e.from = id - 1;
        e.to = id;
        e.mean = g.nodes[id].pose - g.nodes[id - 1].pose;
        g.addEdge(e);
      }
  }
};

void BM_CaveGvg(benchmark::State& state) {
  const CaveMap cave;
  asf::planning::Gvg gvg;
  for (auto _ : state) gvg = asf::planning::computeGvg(cave.map);
  state.counters["skeleton_cells"] = static_cast<double>(gvg.skeleton_cells);
  state.counters["vertices"] = static_cast<double>(gvg.vertices.size());
  state.counters["edges"] = static_cast<double>(gvg.edges.size());
}
BENCHMARK(BM_CaveGvg)->Unit(benchmark::kMillisecond);

void BM_CaveVirtualEdges(benchmark::State& state) {
  const CaveMap cave;
  asf::planning::VirtualEdges ve;
  for (auto _ : state) ve = asf::planning::computeVirtualEdges(cave.g, cave.map);
  state.counters["nodes"] = static_cast<double>(cave.g.size());
  state.counters["attached"] = static_cast<double>(ve.attached);
  state.counters["candidates"] = static_cast<double>(ve.candidates);
  state.counters["virtual_edges"] = static_cast<double>(ve.edges.size());
}
BENCHMARK(BM_CaveVirtualEdges)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
