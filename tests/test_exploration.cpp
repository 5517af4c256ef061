// The closed exploration loop on a small synthetic world: sim2d -> ICP graph SLAM -> DuDe
// -> topological graph -> policy, until the policy says done. Each policy must finish by its
// own stop rule with (nearly) the whole reachable area mapped.
#include <asf/config.h>
#include <asf/pipeline.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace fs = std::filesystem;

namespace {

fs::path tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("asf_test_exploration_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// 12 m x 6 m at 0.05 m/px: three rooms in a row joined by 1 m doors, a pillar in the
/// middle room. Written as a PGM.
fs::path writeWorld(const fs::path& dir) {
  const int W = 240, H = 120;
  std::vector<unsigned char> px(W * H, 255);
  auto wall = [&](int x0, int y0, int x1, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) px[y * W + x] = 0;
  };
  wall(0, 0, W, 3);
  wall(0, H - 3, W, H);
  wall(0, 0, 3, H);
  wall(W - 3, 0, W, H);
  wall(75, 0, 85, 50);  // 0.5 m walls; door rows 50..70 (1 m)
  wall(75, 70, 85, H);
  wall(155, 0, 165, 20);  // second wall, door near the bottom (rows 20..40)
  wall(155, 40, 165, H);
  wall(112, 50, 128, 66);  // pillar in the middle room
  const fs::path f = dir / "three_rooms.pgm";
  std::ofstream o(f, std::ios::binary);
  o << "P5\n" << W << " " << H << "\n255\n";
  o.write(reinterpret_cast<const char*>(px.data()), px.size());
  return f;
}

nlohmann::json explore(const std::string& policy, const fs::path& dir) {
  const fs::path world = writeWorld(dir);
  std::ostringstream ini;
  ini << "[pipeline]\nsource = sim2d\nfrontend = icp_graph\nbackend = sparse_lm\n"
         "segmenter = dude\npolicy = "
      << policy
      << "\nseed = 3\nmax_steps = 12000\nprogress_interval = 0\nverbosity = WARN\n"
         "[sim2d]\nmap_image = "
      << world.string()
      << "\nresolution = 0.05\nstart_x = 1.0\nstart_y = 1.0\nlaser_rays = 361\n"
         "laser_fov_deg = 270\nlaser_max_range = 8.0\nrobot_radius = 0.2\n"
         "[map]\nresolution = 0.05\n";
  asf::Registry reg;
  const auto cfg = asf::resolveConfig(asf::IniConfig::fromText(ini.str(), "exploration.ini"), reg);
  const fs::path out = dir / policy;
  asf::Pipeline p(cfg, out.string());
  const asf::RunSummary s = p.run();
  std::ifstream f(out / "summary.json");
  nlohmann::json j = nlohmann::json::parse(f);
  EXPECT_TRUE(fs::exists(out / "timeseries.csv"));
  EXPECT_TRUE(fs::exists(out / "report.html"));
  EXPECT_EQ(j["finished"], s.finished);
  return j;
}

TEST(Exploration, TigreTraversesEveryEdgeAndMapsTheWorld) {
  const fs::path dir = tempDir("tigre");
  const auto j = explore("tigre", dir);
  EXPECT_TRUE(j["finished"].get<bool>()) << j["stop_reason"];
  EXPECT_NE(j["stop_reason"].get<std::string>().find("every edge traversed"), std::string::npos)
      << j["stop_reason"];
  EXPECT_GE(j["coverage"].get<double>(), 0.97);
  EXPECT_GT(j["loop_closures"].get<int>(), 0);
  // Every region edge of the final graph has been crossed at least once.
  std::ifstream f(dir / "tigre" / "topology.json");
  const auto topo = nlohmann::json::parse(f);
  int region_edges = 0;
  for (const auto& e : topo["edges"]) {
    if (e["frontier"].get<bool>()) continue;
    ++region_edges;
    EXPECT_GE(e["traversals"].size(), 1u) << e.dump();
  }
  EXPECT_GE(region_edges, 1);
  fs::remove_all(dir);
}

TEST(Exploration, FrontierExplorerMapsTheWorld) {
  const fs::path dir = tempDir("frontier");
  const auto j = explore("frontier", dir);
  EXPECT_TRUE(j["finished"].get<bool>()) << j["stop_reason"];
  EXPECT_GE(j["coverage"].get<double>(), 0.97);
  fs::remove_all(dir);
}

TEST(Exploration, OfflinePostmanWalksTheTrueGraph) {
  const fs::path dir = tempDir("cpp");
  const auto j = explore("cpp_offline", dir);
  EXPECT_TRUE(j["finished"].get<bool>()) << j["stop_reason"];
  EXPECT_NE(j["stop_reason"].get<std::string>().find("Chinese postman walk done"),
            std::string::npos)
      << j["stop_reason"];
  EXPECT_GE(j["coverage"].get<double>(), 0.97);
  fs::remove_all(dir);
}

}  // namespace
