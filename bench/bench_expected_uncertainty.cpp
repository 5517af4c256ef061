// Expected-uncertainty planning (framework/include/asf/expected_uncertainty.h): Algorithm 1
// on one path of m steps (m = 10, 100, 1000), exact (every hypothesis kept: O(m^2) window
// integrals) and with the default pruning of negligible hypotheses; and a sweep of start/goal
// pairs on intel.g2o (skipped without ../shared/datasets/g2o/intel.g2o): search of the reduced
// graph plus evaluation of every candidate path, per criterion.
//
//   build/bench/bench_expected_uncertainty [--benchmark_filter=Intel]
#include <asf/backend.h>
#include <asf/expected_uncertainty.h>
#include <asf/registry.h>
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <random>
#include <set>

namespace {

namespace eu = asf::eu;

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
  const eu::PathModel model = eu::makePathModel(c.g, &c.m, c.path);
  eu::CriterionOptions o;
  o.prune_below = state.range(1) ? 1e-12 : 0.0;
  std::size_t evaluations = 0;
  for (auto _ : state) {
    const eu::RelocProbFn p = eu::relocalizationProbability(model, o.reloc);
    const auto r = eu::expectedCovariance(model, p, o.prune_below);
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
    benchmark::DoNotOptimize(eu::gaussianBoxProbability(Eigen::Vector3d::Zero(), cov, -half,
                                                        half, static_cast<int>(state.range(0))));
}
BENCHMARK(BM_WindowIntegral)->Arg(128)->Arg(1024)->Unit(benchmark::kMicrosecond);

// ---- intel.g2o sweep ------------------------------------------------------------------

const std::string kIntel = ASF_BENCH_SOURCE_DIR "/../shared/datasets/g2o/intel.g2o";
constexpr int kPairs = 2;
constexpr std::size_t kMaxPaths = 2;

struct Intel {
  asf::PoseGraph g;
  asf::Marginals m;
  std::vector<std::pair<asf::NodeId, asf::NodeId>> pairs;
  bool ok = false;
  Intel() {
    if (!std::filesystem::exists(kIntel)) return;
    g = asf::readG2o(kIntel);
    auto info = asf::Registry::loadFile(ASF_BENCH_PLUGIN_DIR "/backend_sparse_lm.so");
    auto be = asf::Registry::create<asf::Backend>(info);
    be->setMinLoggingLevel(mrpt::system::LVL_ERROR);
    be->configure(asf::Params::fromSpecs("sparse_lm", info->descriptor->keys,
                                         info->descriptor->num_keys),
                  asf::PluginContext{});
    be->optimize(g);  // the file is the raw initial guess; plan on the optimized graph
    std::mt19937 rng(42);
    std::set<std::pair<asf::NodeId, asf::NodeId>> cross;
    eu::PathSearchOptions search;
    search.max_paths = kMaxPaths;
    while (static_cast<int>(pairs.size()) < kPairs) {
      const asf::NodeId s = rng() % g.size(), t = rng() % g.size();
      if (s == t) continue;
      pairs.emplace_back(s, t);
      for (const auto& p : eu::allSimplePaths(g, s, t, search).paths)
        for (std::size_t a = 0; a < p.size(); ++a)
          for (std::size_t b = a + 1; b < p.size(); ++b)
            cross.emplace(std::min(p[a], p[b]), std::max(p[a], p[b]));
    }
    m = be->marginals(g, {cross.begin(), cross.end()});
    ok = true;
  }
};

const Intel& intel() {
  static const Intel i;
  return i;
}

void BM_IntelSweep(benchmark::State& state) {
  // Opt-in: intel's paths run to ~1700 nodes, i.e. ~1.4M window integrals per path, so
  // even two pairs take minutes (see docs/BENCHMARKS.md).
  const char* on = std::getenv("ASF_BENCH_INTEL_SWEEP");
  if (!on || std::string(on) != "1") {
    state.SkipWithError("opt-in: set ASF_BENCH_INTEL_SWEEP=1 (takes minutes per pair)");
    return;
  }
  const Intel& d = intel();
  if (!d.ok) {
    state.SkipWithError("intel.g2o not found (../shared/datasets/g2o)");
    return;
  }
  const auto c = static_cast<eu::Criterion>(state.range(0));
  state.SetLabel(eu::criterionName(c));
  eu::CriterionOptions o;
  eu::PathSearchOptions search;
  search.max_paths = kMaxPaths;
  std::size_t candidates = 0, capped = 0;
  for (const auto& [s, t] : d.pairs) {  // counters, outside the timing
    const auto paths = eu::allSimplePaths(d.g, s, t, search);
    candidates += paths.paths.size();
    capped += paths.capped;
  }
  for (auto _ : state)
    for (const auto& [s, t] : d.pairs) {
      asf::PlanRequest req{&d.g, &d.m, nullptr, s, t};
      benchmark::DoNotOptimize(eu::planBest(req, c, o, search).cost);
    }
  state.counters["pairs"] = kPairs;
  state.counters["candidate_paths"] = static_cast<double>(candidates);
  state.counters["capped_pairs"] = static_cast<double>(capped);
  state.counters["nodes"] = static_cast<double>(d.g.size());
}
BENCHMARK(BM_IntelSweep)
    ->Arg(static_cast<int>(eu::Criterion::ExpectedUncertainty))
    ->Arg(static_cast<int>(eu::Criterion::MechanicalWork))
    ->Arg(static_cast<int>(eu::Criterion::SumDopt))
    ->Arg(static_cast<int>(eu::Criterion::Distance))
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
