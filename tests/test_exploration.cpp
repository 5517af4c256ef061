// The closed exploration loop on a small synthetic world: sim2d -> ICP graph SLAM -> DuDe
// -> topological graph -> policy, until the policy says done. Each policy must finish by its
// own stop rule with (nearly) the whole reachable area mapped.
#include <asf/config.h>
#include <asf/errors.h>
#include <asf/framework/pipeline.h>
#include <asf/evaluation/run_report.h>
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "test_util.h"

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

nlohmann::json runConfig(const asf::IniConfig& ini, const fs::path& out) {
  asf::framework::Registry reg;
  const auto cfg = asf::framework::resolveConfig(ini, reg);
  asf::framework::Pipeline p(cfg, out.string());
  const asf::framework::RunSummary s = p.run();
  std::ifstream f(out / "summary.json");
  nlohmann::json j = nlohmann::json::parse(f);
  EXPECT_TRUE(fs::exists(out / "timeseries.csv"));
  EXPECT_TRUE(fs::exists(out / "report.html"));
  EXPECT_EQ(j["finished"], s.finished);
  return j;
}

/// `pipeline_keys`: more [pipeline] lines ("key = value\n").
nlohmann::json explore(const std::string& policy, const fs::path& dir,
                       const std::string& pipeline_keys = "", long max_steps = 12000) {
  const fs::path world = writeWorld(dir);
  std::ostringstream ini;
  ini << "[pipeline]\nsource = sim2d\nfrontend = icp_graph\nbackend = sparse_lm\n"
         "segmenter = dude\npolicy = "
      << policy << "\nseed = 3\nmax_steps = " << max_steps
      << "\nprogress_interval = 0\nverbosity = WARN\n"
      << pipeline_keys << "[sim2d]\nmap_image = " << world.string()
      << "\nresolution = 0.05\nstart_x = 1.0\nstart_y = 1.0\nlaser_rays = 361\n"
         "laser_fov_deg = 270\nlaser_max_range = 8.0\nrobot_radius = 0.2\n"
         "[map]\nresolution = 0.05\n";
  return runConfig(asf::IniConfig::fromText(ini.str(), "exploration.ini"), dir / policy);
}

/// Coverage milestones in summary.json: the distance and time of the first timeseries row at
/// or above each share (recomputed from timeseries.csv), null for a share never reached.
void expectMilestonesOfTheTimeseries(const nlohmann::json& j, const fs::path& run) {
  const auto ts = asf::evaluation::report::readCsvColumns((run / "timeseries.csv").string());
  const std::vector<double>& cov = ts.at("coverage");
  int reached = 0;
  double last_d = -1;
  for (const int pct : {25, 50, 75, 90, 99}) {
    const auto& d = j["distance_to_coverage_" + std::to_string(pct) + "_m"];
    const auto& t = j["time_to_coverage_" + std::to_string(pct) + "_s"];
    std::size_t row = 0;
    while (row < cov.size() && !(cov[row] >= pct / 100.0)) ++row;
    if (row == cov.size()) {
      EXPECT_TRUE(d.is_null() && t.is_null()) << pct << " % never reached";
      continue;
    }
    ++reached;
    EXPECT_NEAR(d.get<double>(), ts.at("distance_m")[row], 1e-4) << pct << " %";
    EXPECT_NEAR(t.get<double>(), ts.at("time_s")[row], 1e-4) << pct << " %";
    EXPECT_GE(d.get<double>(), last_d) << pct << " %: milestones in order";
    last_d = d.get<double>();
  }
  EXPECT_GE(reached, 4) << "coverage >= 0.97 passes 25, 50, 75 and 90 %";
  EXPECT_LT(last_d, j["distance_m"].get<double>()) << "before the end of the run";
  // The map's information in every row, growing as the world gets mapped; the entropy over
  // the final grid is its cells minus that, and ends as summary.json's.
  const std::vector<double>& info = ts.at("map_information_bits");
  ASSERT_FALSE(info.empty());
  for (double v : info) ASSERT_TRUE(std::isfinite(v) && v >= 0);
  EXPECT_GT(info.back(), 2 * info.front());
  const double cells = j["map_cells"].get<double>();
  EXPECT_NEAR(j["map_entropy_bits"].get<double>(), cells - j["map_information_bits"].get<double>(),
              1e-6);
  EXPECT_LT(j["map_entropy_bits"].get<double>(), cells - info.front())
      << "less entropy at the end than after the first scan";
}

TEST(Exploration, TigreTraversesEveryEdgeAndMapsTheWorld) {
  const fs::path dir = tempDir("tigre");
  const auto j = explore("tigre", dir);
  EXPECT_TRUE(j["finished"].get<bool>()) << j["stop_reason"];
  EXPECT_NE(j["stop_reason"].get<std::string>().find("every edge traversed"), std::string::npos)
      << j["stop_reason"];
  EXPECT_GE(j["coverage"].get<double>(), 0.97);
  expectMilestonesOfTheTimeseries(j, dir / "tigre");
  // A timeline picture per decision once there is a map (not at the first, before any scan).
  int frames = 0;
  for (const auto& e : fs::directory_iterator(dir / "tigre" / "timeline"))
    frames += e.path().extension() == ".png";
  EXPECT_GE(frames, j["decisions"].get<int>() - 1);
  EXPECT_LE(frames, j["decisions"].get<int>());
  std::ifstream report(dir / "tigre" / "report.html");
  const std::string html((std::istreambuf_iterator<char>(report)),
                         std::istreambuf_iterator<char>());
  EXPECT_NE(html.find("<h2>Timeline</h2>"), std::string::npos);
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

struct Point {
  double x, y;
};
/// The true position (gt_x, gt_y) of trajectory.csv's first and last rows.
std::pair<Point, Point> firstAndLastTruth(const fs::path& run) {
  const auto t = asf::evaluation::report::readCsvColumns((run / "trajectory.csv").string());
  return {{t.at("gt_x").front(), t.at("gt_y").front()}, {t.at("gt_x").back(), t.at("gt_y").back()}};
}

TEST(Exploration, ReturnHomeEndsTheRunAtTheStart) {
  const fs::path dir = tempDir("home");
  const auto j = explore("tigre", dir, "return_home = true\n");
  EXPECT_TRUE(j["finished"].get<bool>()) << j["stop_reason"];
  const std::string why = j["stop_reason"];
  EXPECT_NE(why.find("every edge traversed"), std::string::npos) << why;
  EXPECT_NE(why.find("; back at the start ("), std::string::npos) << why;
  const auto [first, last] = firstAndLastTruth(dir / "tigre");
  // Within the goal tolerance (0.3 m) of the estimated start, plus the estimate's error.
  EXPECT_LT(std::hypot(last.x - first.x, last.y - first.y), 0.5)
      << "ended at (" << last.x << ", " << last.y << "), started at (" << first.x << ", " << first.y
      << ")";
  EXPECT_GE(j["coverage"].get<double>(), 0.97);
  fs::remove_all(dir);
}

TEST(Exploration, ProgressTimeoutStopsARunThatMapsNothingNew) {
  // 40 m^2 of new area within every 3 m: more than a robot can see in this world after its
  // first views, so the run stops early, saying why, not finished.
  const fs::path dir = tempDir("timeout");
  const auto j = explore("tigre", dir, "progress_timeout_m = 3\nprogress_min_area = 40\n");
  EXPECT_FALSE(j["finished"].get<bool>());
  const std::string why = j["stop_reason"];
  EXPECT_NE(why.find("no progress: the explored area grew by less than 40 m^2 over the last 3 m"),
            std::string::npos)
      << why;
  EXPECT_GE(j["distance_m"].get<double>(), 3.0);
  EXPECT_LT(j["coverage"].get<double>(), 0.97) << "stopped before the world was mapped";
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

TEST(Exploration, DOptFrontierExplorerMapsTheWorld) {
  const fs::path dir = tempDir("dopt");
  const auto j = explore("dopt_frontier", dir);
  EXPECT_TRUE(j["finished"].get<bool>()) << j["stop_reason"];
  EXPECT_GE(j["coverage"].get<double>(), 0.97);
  fs::remove_all(dir);
}

// ---- asf run --resume ([pipeline] resume, [sim2d] resume_from) ---------------------------

std::vector<std::string> lines(const fs::path& f) {
  std::ifstream in(f);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

/// The first `n` fields of a CSV line.
std::string firstFields(const std::string& line, int n) {
  std::size_t pos = 0;
  for (int k = 0; k < n && pos != std::string::npos; ++k) pos = line.find(',', pos + 1);
  return line.substr(0, pos);
}

/// The run in `interrupted` continued into `out`, as `asf run --resume` sets it up.
nlohmann::json resume(const fs::path& interrupted, const fs::path& out,
                      const std::string& max_steps = "12000") {
  asf::IniConfig ini = asf::IniConfig::fromFile((interrupted / "config.ini").string());
  ini.set("pipeline", "resume", interrupted.string(), "test");
  ini.set("sim2d", "resume_from", interrupted.string(), "test");
  ini.set("pipeline", "max_steps", max_steps, "test");
  return runConfig(ini, out);
}

TEST(Exploration, ResumedRunReplaysTheInterruptedOneThenFinishesTheExploration) {
  const fs::path dir = tempDir("resume");
  const auto whole = explore("tigre", dir);
  ASSERT_TRUE(whole["finished"].get<bool>());
  const long half = whole["steps"].get<long>() / 2;
  fs::rename(dir / "tigre", dir / "whole");
  const auto cut = explore("tigre", dir, "", half);
  ASSERT_FALSE(cut["finished"].get<bool>());
  const fs::path first = dir / "tigre";
  const auto j = resume(first, dir / "resumed");

  // The interrupted run again, to the digit: its steps, its decisions, its estimates.
  ASSERT_TRUE(j.contains("resumed")) << j.dump();
  EXPECT_EQ(j["resumed"]["after_steps"].get<long>(), half);
  const auto recorded = lines(first / "decisions.csv");
  EXPECT_EQ(j["resumed"]["replayed_decisions"].get<int>(), static_cast<int>(recorded.size()) - 1);
  EXPECT_EQ(j["resumed"]["replayed_decisions_differing"].get<int>(), 0);
  const auto retaken = lines(dir / "resumed" / "decisions.csv");
  ASSERT_GT(retaken.size(), recorded.size());
  for (std::size_t i = 0; i < recorded.size(); ++i)
    EXPECT_EQ(firstFields(retaken[i], 6), firstFields(recorded[i], 6)) << "decision row " << i;
  const auto before = lines(first / "trajectory.csv"),
             after = lines(dir / "resumed" / "trajectory.csv");
  ASSERT_EQ(before.size(), static_cast<std::size_t>(half) + 1);
  for (std::size_t i = 0; i < before.size(); ++i)  // step, time, estimate x, y, phi
    ASSERT_EQ(firstFields(after[i], 5), firstFields(before[i], 5)) << "trajectory row " << i;
  // Its recording continues the interrupted one's.
  const auto gt0 = lines(first / "sim2d.gt.txt"), gt1 = lines(dir / "resumed" / "sim2d.gt.txt");
  ASSERT_EQ(gt1.size(), j["steps"].get<std::size_t>() + 1);  // a header line, a line per step
  EXPECT_TRUE(std::equal(gt0.begin(), gt0.end(), gt1.begin()));

  // Then the exploration goes on to the end, as the uninterrupted one did (other noise after
  // the interruption: another path, of a similar length).
  EXPECT_TRUE(j["finished"].get<bool>()) << j["stop_reason"];
  EXPECT_NE(j["stop_reason"].get<std::string>().find("every edge traversed"), std::string::npos);
  EXPECT_GT(j["steps"].get<long>(), half);
  EXPECT_GE(j["coverage"].get<double>(), 0.97);
  EXPECT_NEAR(j["distance_m"].get<double>(), whole["distance_m"].get<double>(),
              0.3 * whole["distance_m"].get<double>());

  // A log cut by a kill (its last record half written): the frames before the cut are the
  // run's; the decisions after them are not replayed.
  const fs::path killed = dir / "killed";
  fs::copy(first, killed, fs::copy_options::recursive);
  fs::resize_file(killed / "sim2d.rawlog", fs::file_size(killed / "sim2d.rawlog") * 6 / 10 + 7);
  const auto k = resume(killed, dir / "resumed_killed");
  EXPECT_GT(k["resumed"]["after_steps"].get<long>(), half / 2);
  EXPECT_LT(k["resumed"]["after_steps"].get<long>(), half);
  EXPECT_LT(k["resumed"]["replayed_decisions"].get<int>(), static_cast<int>(recorded.size()) - 1);
  EXPECT_EQ(k["resumed"]["replayed_decisions_differing"].get<int>(), 0);
  EXPECT_TRUE(k["finished"].get<bool>()) << k["stop_reason"];
  fs::remove_all(dir);
}

TEST(Exploration, ResumeErrorsNameTheKeyOrTheFile) {
  const fs::path dir = tempDir("resume_errors");
  explore("frontier", dir, "", 300);
  const fs::path run = dir / "frontier";
  asf::IniConfig ini = asf::IniConfig::fromFile((run / "config.ini").string());
  // The source must continue the same recording.
  ini.set("pipeline", "resume", run.string(), "test");
  std::string msg = asf_test::errorOf<asf::Error>([&] { runConfig(ini, dir / "a"); });
  EXPECT_NE(msg.find("sim2d.resume_from = the same folder"), std::string::npos) << msg;
  // Never into the folder it reads.
  ini.set("sim2d", "resume_from", run.string(), "test");
  msg = asf_test::errorOf<asf::Error>([&] { runConfig(ini, run); });
  EXPECT_NE(msg.find("resume_from"), std::string::npos) << msg;
  EXPECT_NE(msg.find("own output folder"), std::string::npos) << msg;
  EXPECT_TRUE(fs::exists(run / "sim2d.rawlog")) << "the interrupted run keeps its files";
  EXPECT_GT(fs::file_size(run / "sim2d.rawlog"), 0u);
  // Stopped while replaying (Ctrl-C): an interrupted run, its files written.
  {
    asf::framework::Registry reg;
    asf::framework::Pipeline p(asf::framework::resolveConfig(ini, reg), (dir / "stopped").string());
    const std::atomic<bool> stop{true};
    const asf::framework::RunSummary s = p.run(&stop);
    EXPECT_EQ(s.stop_reason, "interrupted");
    EXPECT_FALSE(s.finished);
    EXPECT_TRUE(fs::exists(dir / "stopped" / "summary.json"));
  }
  // Its decisions are needed.
  fs::remove(run / "decisions.csv");
  msg = asf_test::errorOf<asf::Error>([&] { runConfig(ini, dir / "b"); });
  EXPECT_NE(msg.find("decisions.csv"), std::string::npos) << msg;
  fs::remove_all(dir);
}

}  // namespace
