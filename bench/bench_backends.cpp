// Back-ends side by side on the shared 2D pose-graph benchmarks (../shared/datasets/g2o):
// sparse_lm (defaults; and without its LAGO initial guess, to show what it buys) against
// mrpt_levmarq (MRPT's optimizer, the baseline), time to converge from the file's initial
// guess with the final chi2 and iterations as counters; and all-node marginals of sparse_lm.
// Every timed run uses a fresh back-end instance (cold: ordering and symbolic analysis
// included); marginals run on the instance that optimized, as `asf optimize --marginals`.
//
//   build/bench/bench_backends [--benchmark_filter=city10000]
#include <asf/backend.h>
#include <asf/framework/registry.h>
#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace {

const std::string kDir = ASF_BENCH_SOURCE_DIR "/../shared/datasets/g2o/";

struct Backend {
  const char* label;
  const char* plugin_file;
  const char* section;
  std::map<std::string, std::string> keys;
};

const Backend kSparse{"sparse_lm", "backend_sparse_lm.so", "sparse_lm", {}};
const Backend kSparseNoLago{"sparse_lm_no_lago", "backend_sparse_lm.so", "sparse_lm",
                            {{"lago_init", "false"}}};
const Backend kMrpt{"mrpt_levmarq", "backend_mrpt_levmarq.so", "mrpt_levmarq", {}};

asf::framework::PluginHandle<asf::Backend> make(const Backend& b) {
  static std::map<std::string, std::shared_ptr<const asf::framework::PluginInfo>> infos;
  auto& info = infos[b.plugin_file];
  if (!info)
    info =
        asf::framework::Registry::loadFile(std::string(ASF_BENCH_PLUGIN_DIR) + "/" + b.plugin_file);
  auto h = asf::framework::Registry::create<asf::Backend>(info);
  h->setMinLoggingLevel(mrpt::system::LVL_ERROR);
  h->configure(asf::Params::fromSpecs(b.section, info->descriptor->keys,
                                      info->descriptor->num_keys, b.keys),
               asf::PluginContext{});
  return h;
}

/// The dataset, read once; nullptr (and an error on the benchmark) if it is missing.
const asf::PoseGraph* dataset(benchmark::State& state, const std::string& name) {
  static std::map<std::string, asf::PoseGraph> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    const std::string f = kDir + name + ".g2o";
    if (!std::filesystem::exists(f)) {
      state.SkipWithError(
          ("missing " + f + " (the shared datasets beside the repository)").c_str());
      return nullptr;
    }
    it = cache.emplace(name, asf::readG2o(f)).first;
  }
  return &it->second;
}

void optimize(benchmark::State& state, const Backend& b, const std::string& name) {
  const asf::PoseGraph* original = dataset(state, name);
  if (!original) return;
  asf::OptimizeReport r;
  double chi2 = 0;
  for (auto _ : state) {
    state.PauseTiming();
    asf::PoseGraph g = *original;
    auto be = make(b);
    state.ResumeTiming();
    r = be->optimize(g);
    state.PauseTiming();
    chi2 = g.chi2();
    state.ResumeTiming();
  }
  state.counters["chi2_initial"] = original->chi2();
  state.counters["chi2_final"] = chi2;
  state.counters["iterations"] = r.iterations;
  state.counters["nodes"] = static_cast<double>(original->size());
}

void marginals(benchmark::State& state, const std::string& name) {
  const asf::PoseGraph* original = dataset(state, name);
  if (!original) return;
  asf::PoseGraph g = *original;
  auto be = make(kSparse);
  be->optimize(g);
  double trace = 0;
  for (auto _ : state) {
    const asf::Marginals m = be->marginals(g);
    state.PauseTiming();
    trace = m.node.back().trace();
    state.ResumeTiming();
  }
  state.counters["nodes"] = static_cast<double>(g.size());
  state.counters["last_node_trace"] = trace;
}

double minimum(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }

}  // namespace

int main(int argc, char** argv) {
  for (const char* name : {"intel", "MIT", "city10000"})
    for (const Backend* b : {&kSparse, &kSparseNoLago, &kMrpt})
      benchmark::RegisterBenchmark(
          ("Optimize/" + std::string(name) + "/" + b->label).c_str(),
          [b, name](benchmark::State& s) { optimize(s, *b, name); })
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->Repetitions(5)
          ->ReportAggregatesOnly(true)
          ->ComputeStatistics("min", minimum);
  for (const char* name : {"intel", "MIT", "city10000"})
    benchmark::RegisterBenchmark(("Marginals/" + std::string(name) + "/sparse_lm").c_str(),
                                 [name](benchmark::State& s) { marginals(s, name); })
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->Repetitions(5)
        ->ReportAggregatesOnly(true)
        ->ComputeStatistics("min", minimum);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
