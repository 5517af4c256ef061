// sparse_lm's incremental mode against the plain back-end on graphs replayed as they grew:
// nodes in id order, each edge added once both its ends exist, a new node placed where its
// first edge from an older node puts it (as a front-end does), then optimize() and
// marginals() after every node, as the pipeline calls them. Graphs: intel and MIT from the
// shared datasets beside the repository, and any g2o file named by ASF_BENCH_GRAPH (e.g. a
// run's graph.g2o). Modes: plain (incremental = false), incremental (its exact marginals)
// updated and propagated (incremental_marginals = updated | propagated). One replay per
// benchmark (it is long); the
// counters say how the modes' answers compare: the final chi2 against the plain back-end's, and at
// every 25th node the trace of the newest node's marginal and the median over all nodes against an
// exact computation (outside the timing).
//
//   build/bench/bench_incremental [--benchmark_filter=intel]
//   ASF_BENCH_GRAPH=/tmp/run/graph.g2o build/bench/bench_incremental --benchmark_filter=env
//   ASF_BENCH_SET="incremental_update_nodes=32;incremental_update_touched=8" ... (other keys)
#include <asf/backend.h>
#include <asf/framework/registry.h>
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

const std::string kDir = ASF_BENCH_SOURCE_DIR "/../shared/datasets/g2o/";

asf::framework::PluginHandle<asf::Backend> make(const std::map<std::string, std::string>& keys) {
  static std::shared_ptr<const asf::framework::PluginInfo> info;
  if (!info)
    info = asf::framework::Registry::loadFile(std::string(ASF_BENCH_PLUGIN_DIR) +
                                              "/backend_sparse_lm.so");
  auto h = asf::framework::Registry::create<asf::Backend>(info);
  h->setMinLoggingLevel(mrpt::system::LVL_ERROR);
  h->configure(
      asf::Params::fromSpecs("sparse_lm", info->descriptor->keys, info->descriptor->num_keys, keys),
      asf::PluginContext{});
  return h;
}

const asf::PoseGraph* graph(benchmark::State& state, const std::string& name) {
  static std::map<std::string, asf::PoseGraph> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return &it->second;
  std::string f = kDir + name + ".g2o";
  if (name == "env") {
    const char* e = std::getenv("ASF_BENCH_GRAPH");
    if (!e) {
      state.SkipWithError("set ASF_BENCH_GRAPH to a g2o file");
      return nullptr;
    }
    f = e;
  }
  if (!std::filesystem::exists(f)) {
    state.SkipWithError(("missing " + f).c_str());
    return nullptr;
  }
  return &cache.emplace(name, asf::readG2o(f)).first->second;
}

/// Edge indices by the later of their two ends (when the replay can add them).
std::vector<std::vector<std::size_t>> edgesByNewestEnd(const asf::PoseGraph& g) {
  std::vector<std::vector<std::size_t>> by(g.size());
  for (std::size_t k = 0; k < g.edges.size(); ++k)
    by[std::max(g.edges[k].from, g.edges[k].to)].push_back(k);
  return by;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

/// The final chi2 of the plain back-end's replay, for the ratio counters.
std::map<std::string, double>& plainFinalChi2() {
  static std::map<std::string, double> m;
  return m;
}

void BM_Replay(benchmark::State& state, const std::string& name, const std::string& mode) {
  const asf::PoseGraph* full = graph(state, name);
  if (!full) return;
  std::map<std::string, std::string> keys;
  if (mode != "plain") keys["incremental"] = "true";
  if (mode == "propagated" || mode == "updated") keys["incremental_marginals"] = mode;
  if (const char* set = std::getenv("ASF_BENCH_SET"); set && mode != "plain") {
    std::string item;  // key=value;key=value, for the incremental modes
    for (std::istringstream in(set); std::getline(in, item, ';');)
      if (const auto eq = item.find('='); eq != std::string::npos)
        keys[item.substr(0, eq)] = item.substr(eq + 1);
  }
  const auto by_end = edgesByNewestEnd(*full);
  double chi2 = 0;
  std::vector<double> newest_ratio, median_ratio;
  for (auto _ : state) {
    auto be = make(keys);
    auto exact = make({});
    asf::PoseGraph g;
    for (std::size_t n = 0; n < full->size(); ++n) {
      g.addNode(full->nodes[n].pose, full->nodes[n].timestamp);
      bool placed = n == 0;
      for (std::size_t k : by_end[n]) {
        const asf::PoseEdge& e = full->edges[k];
        if (!placed && e.to == n && e.from < n) {
          g.nodes[n].pose = g.nodes[e.from].pose + e.mean;
          placed = true;
        }
        g.addEdge(e);
      }
      be->optimize(g);
      const asf::Marginals m = be->marginals(g);
      if (n % 25 == 0 && n > 0 && mode != "plain") {
        state.PauseTiming();
        const asf::Marginals x = exact->marginals(g);
        std::vector<double> r;
        for (std::size_t i = 1; i < g.size(); ++i)
          r.push_back(m.node[i].trace() / x.node[i].trace());
        newest_ratio.push_back(r.back());
        median_ratio.push_back(median(r));
        state.ResumeTiming();
      }
    }
    chi2 = g.chi2();
  }
  state.counters["nodes"] = static_cast<double>(full->size());
  state.counters["final_chi2"] = chi2;
  if (mode == "plain") plainFinalChi2()[name] = chi2;
  auto it = plainFinalChi2().find(name);
  if (it != plainFinalChi2().end() && it->second > 0)
    state.counters["chi2_vs_plain"] = chi2 / it->second;
  if (!newest_ratio.empty()) {
    state.counters["newest_trace_ratio_median"] = median(newest_ratio);
    state.counters["newest_trace_ratio_max"] =
        *std::max_element(newest_ratio.begin(), newest_ratio.end());
    state.counters["all_trace_ratio_median"] = median(median_ratio);
  }
}

void registerAll() {
  for (const char* name : {"intel", "MIT", "env"})
    for (const char* mode : {"plain", "incremental", "updated", "propagated"})
      benchmark::RegisterBenchmark((std::string("BM_Replay/") + name + "/" + mode).c_str(),
                                   [name = std::string(name), mode = std::string(mode)](
                                       benchmark::State& s) { BM_Replay(s, name, mode); })
          ->Iterations(1)
          ->Unit(benchmark::kMillisecond);
}

}  // namespace

int main(int argc, char** argv) {
  registerAll();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
