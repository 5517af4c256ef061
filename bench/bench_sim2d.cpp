// Throughput of the sim2d source on the cave world (20 m x 20 m, 0.04 m cells): simulated
// steps per second, driving between goals, with the laser of the issue (1081 rays over
// 270 degrees) and without it, with and without recording the rawlog.
//
//   build/bench/bench_sim2d
#include <asf/framework/registry.h>
#include <asf/source.h>
#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace {

asf::framework::PluginHandle<asf::Source> makeCave(const std::map<std::string, std::string>& extra,
                                        const std::string& out_dir) {
  static auto info = asf::framework::Registry::loadFile(ASF_BENCH_PLUGIN_DIR "/source_sim2d.so");
  std::map<std::string, std::string> kv{
      {"map_image", ASF_BENCH_SOURCE_DIR "/datasets/cave/cave_filled.png"},
      {"resolution", "0.04"},
      {"pad_wall_px", "1"},
      {"start_x", "2"},
      {"start_y", "2"},
      {"laser_rays", "1081"},
      {"laser_fov_deg", "270"},
      {"laser_max_range", "30"},
      {"max_steps", "1000000000"},
      {"record", out_dir.empty() ? "false" : "true"}};
  for (const auto& [k, v] : extra) kv[k] = v;
  auto h = asf::framework::Registry::create<asf::Source>(info);
  h->setMinLoggingLevel(mrpt::system::LVL_ERROR);
  asf::PluginContext ctx;
  ctx.seed = 1;
  ctx.output_dir = out_dir;
  h->configure(asf::Params::fromSpecs("sim2d", info->descriptor->keys, info->descriptor->num_keys,
                                      kv),
               ctx);
  return h;
}

// Map-frame goals (start (2, 2) is the origin) around the open lower part of the cave.
const std::vector<asf::Goal> kGoals{{4, 0, 0.2}, {10, 0, 0.2}, {10, 3.5, 0.2}, {0, 3.5, 0.2},
                                    {0, 0, 0.2}};

void run(benchmark::State& state, const std::map<std::string, std::string>& extra,
         bool record) {
  const std::string dir =
      record ? (std::filesystem::temp_directory_path() / "asf_bench_sim2d").string() : "";
  if (record) std::filesystem::create_directories(dir);
  auto src = makeCave(extra, dir);
  mrpt::poses::CPose2D odo;
  std::size_t goal = 0;
  std::int64_t scans = 0;
  for (auto _ : state) {
    if (src->status() != asf::NavStatus::Moving) {
      asf::NavigationContext ctx;
      ctx.robot_estimate = odo;
      src->navigate(kGoals[goal++ % kGoals.size()], ctx);
    }
    auto f = src->next();
    odo = odo + f->odometry;
    scans += f->scan != nullptr;
    benchmark::DoNotOptimize(f);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["scans"] = static_cast<double>(scans);
}

void BM_Sim2dStep_Laser1081(benchmark::State& s) { run(s, {}, false); }
void BM_Sim2dStep_Laser1081_Range10m(benchmark::State& s) {
  run(s, {{"laser_max_range", "10"}}, false);
}
void BM_Sim2dStep_Laser1081_Recording(benchmark::State& s) { run(s, {}, true); }
// The tilted laser (181 rays over 180 degrees, 4 m, 20 degrees down) on top of the default
// run's horizontal laser (541 rays, 270 degrees, 10 m): what a step with both costs, against
// the same step without it.
void BM_Sim2dStep_Laser541_Range10m(benchmark::State& s) {
  run(s, {{"laser_rays", "541"}, {"laser_max_range", "10"}}, false);
}
void BM_Sim2dStep_Laser541_Range10m_Tilted(benchmark::State& s) {
  run(s, {{"laser_rays", "541"}, {"laser_max_range", "10"}, {"tilted_laser", "true"}}, false);
}
void BM_Sim2dStep_Laser10Hz_Steps100Hz(benchmark::State& s) {
  run(s, {{"dt", "0.01"}, {"laser_rate", "10"}, {"step_length", "0.005"}}, false);
}
void BM_Sim2dStep_MotionOnly(benchmark::State& s) {
  // Two rays, the cheapest laser the source allows: what the motion and noise cost.
  run(s, {{"laser_rays", "2"}}, false);
}

BENCHMARK(BM_Sim2dStep_Laser1081)->Unit(benchmark::kMicrosecond)->MinTime(2.0);
BENCHMARK(BM_Sim2dStep_Laser1081_Range10m)->Unit(benchmark::kMicrosecond)->MinTime(2.0);
BENCHMARK(BM_Sim2dStep_Laser1081_Recording)->Unit(benchmark::kMicrosecond)->MinTime(2.0);
BENCHMARK(BM_Sim2dStep_Laser541_Range10m)->Unit(benchmark::kMicrosecond)->MinTime(2.0);
BENCHMARK(BM_Sim2dStep_Laser541_Range10m_Tilted)->Unit(benchmark::kMicrosecond)->MinTime(2.0);
BENCHMARK(BM_Sim2dStep_Laser10Hz_Steps100Hz)->Unit(benchmark::kMicrosecond)->MinTime(2.0);
BENCHMARK(BM_Sim2dStep_MotionOnly)->Unit(benchmark::kMicrosecond)->MinTime(2.0);

}  // namespace

BENCHMARK_MAIN();
