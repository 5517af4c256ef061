// Routes on known graphs (libs/graph/include/asf/graph/routes.h) at the sizes of the optimal
// analysis (issue 6: random graphs of 100 nodes and 297 edges; topological graphs of up to
// ~120 nodes): Chinese postman, the blossom alone, TSP (heuristic + bound, and Held-Karp at its
// limit), and the explorers. Counters: walk length relative to the total edge length (cpp,
// tarry) or the TSP gap to its lower bound.
//
//   build/bench/bench_graph_routes [--benchmark_filter=Postman]
#include <asf/graph/routes.h>
#include <benchmark/benchmark.h>

#include <random>

namespace {

using namespace asf::graph;

/// Random connected graph: a random spanning tree plus random extra edges (no self-loops),
/// lengths uniform in [1, 10).
Multigraph randomGraph(int n, int m, unsigned seed) {
  std::mt19937 rng(seed);
  Multigraph g;
  g.n = n;
  auto len = [&] { return 1.0 + 9.0 * (rng() % 100000) / 100000.0; };
  for (int v = 1; v < n; ++v) g.edges.push_back({static_cast<int>(rng() % v), v, len()});
  while (g.m() < m) {
    const int u = rng() % n, v = rng() % n;
    if (u != v) g.edges.push_back({u, v, len()});
  }
  return g;
}

double total(const Multigraph& g) {
  double t = 0;
  for (const auto& e : g.edges) t += e.length;
  return t;
}

void BM_Postman(benchmark::State& state) {
  const Multigraph g = randomGraph(state.range(0), state.range(1), 1);
  PostmanResult r;
  for (auto _ : state) benchmark::DoNotOptimize(r = chinesePostman(g, 0));
  state.counters["odd"] = static_cast<double>(r.odd_vertices.size());
  state.counters["length/total"] = r.walk.length / total(g);
}
BENCHMARK(BM_Postman)->Args({100, 297})->Args({120, 200})->Args({400, 1200})
    ->Unit(benchmark::kMillisecond);

void BM_BlossomMatching(benchmark::State& state) {
  const int k = state.range(0);
  std::mt19937 rng(2);
  std::vector<std::vector<double>> c(k, std::vector<double>(k, 0));
  for (int i = 0; i < k; ++i)
    for (int j = i + 1; j < k; ++j) c[i][j] = c[j][i] = rng() % 100000 / 100.0;
  for (auto _ : state)
    benchmark::DoNotOptimize(minWeightPerfectMatching(c, MatchingMethod::Blossom));
}
BENCHMARK(BM_BlossomMatching)->Arg(20)->Arg(100)->Arg(400)->Unit(benchmark::kMillisecond);

void BM_MatchingDp(benchmark::State& state) {
  const int k = state.range(0);
  std::mt19937 rng(2);
  std::vector<std::vector<double>> c(k, std::vector<double>(k, 0));
  for (int i = 0; i < k; ++i)
    for (int j = i + 1; j < k; ++j) c[i][j] = c[j][i] = rng() % 100000 / 100.0;
  for (auto _ : state)
    benchmark::DoNotOptimize(minWeightPerfectMatching(c, MatchingMethod::BitmaskDP));
}
BENCHMARK(BM_MatchingDp)->Arg(12)->Arg(20)->Unit(benchmark::kMillisecond);

void BM_TspHeuristic(benchmark::State& state) {
  const Multigraph g = randomGraph(state.range(0), state.range(1), 3);
  TspResult r;
  for (auto _ : state) benchmark::DoNotOptimize(r = travelingSalesman(g, 0));
  state.counters["gap_%"] = 100 * (r.walk.length - r.lower_bound) / r.walk.length;
}
BENCHMARK(BM_TspHeuristic)->Args({100, 297})->Args({120, 200})->Unit(benchmark::kMillisecond);

void BM_TspHeldKarp16(benchmark::State& state) {
  const Multigraph g = randomGraph(16, 40, 4);
  for (auto _ : state) benchmark::DoNotOptimize(travelingSalesman(g, 0));
}
BENCHMARK(BM_TspHeldKarp16)->Unit(benchmark::kMillisecond);

void BM_TarryModified(benchmark::State& state) {
  const Multigraph g = randomGraph(state.range(0), state.range(1), 5);
  ExploreResult r;
  for (auto _ : state) benchmark::DoNotOptimize(r = tarry(g, 0, TarryOptions::modified(), 7));
  state.counters["length/total"] = r.walk.length / total(g);
}
BENCHMARK(BM_TarryModified)->Args({100, 297})->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
