// The pipeline end to end with the reference plugins: configuration errors, outputs of a
// finished run, an interrupted run, and a run whose plugin fails midway.
#include <asf/errors.h>
#include <asf/io/occupancy_io.h>
#include <asf/io/rawlog_io.h>
#include <asf/framework/pipeline.h>
#include <asf/pose_graph.h>
#include <asf/evaluation/trajectory_eval.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>

#include "test_util.h"

using asf_test::has;
namespace {
const auto errorOf = asf_test::errorOf<asf::Error>;
}
namespace fs = std::filesystem;

namespace {

const std::string kDefault = ASF_TEST_SOURCE_DIR "/configs/two_rooms_scripted.ini";

fs::path tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("asf_test_pipeline_" + name);
  fs::remove_all(d);
  return d;
}

nlohmann::json readJson(const fs::path& f) {
  std::ifstream in(f);
  return nlohmann::json::parse(in);
}

std::size_t lineCount(const fs::path& f) {
  std::ifstream in(f);
  std::size_t n = 0;
  std::string l;
  while (std::getline(in, l)) ++n;
  return n;
}

}  // namespace

TEST(PipelineConfig, DefaultConfigResolves) {
  asf::framework::Registry reg;
  const auto rc = asf::framework::resolveConfig(asf::IniConfig::fromFile(kDefault), reg);
  EXPECT_EQ(rc.slots.size(), 6u) << "one plugin per slot";
  EXPECT_TRUE(rc.warnings.empty());
  const std::string ini = rc.toIni();
  EXPECT_TRUE(has(ini, "[segment_world]"));
  EXPECT_TRUE(has(ini, "max_steps = 100000"));
  // The resolved text is itself a valid configuration that resolves to the same values.
  asf::framework::Registry reg2;
  const auto rc2 =
      asf::framework::resolveConfig(asf::IniConfig::fromText(ini, "resolved.ini"), reg2);
  auto texts = [](const asf::Params& p) {
    std::map<std::string, std::string> m;
    for (const auto& [k, v] : p.values()) m[k] = v.text;
    return m;
  };
  EXPECT_EQ(texts(rc2.pipeline), texts(rc.pipeline));
  EXPECT_EQ(texts(rc2.map), texts(rc.map));
  ASSERT_EQ(rc2.plugin_params.size(), rc.plugin_params.size());
  for (const auto& [name, p] : rc.plugin_params)
    EXPECT_EQ(texts(rc2.plugin_params.at(name)), texts(p)) << name;
}

TEST(PipelineConfig, ErrorsNameFileSectionKeyAndSuggest) {
  asf::framework::Registry reg;
  const auto ini = asf::IniConfig::fromText(
      "[pipeline]\nsource = segment_world\nfrontend = odometri\nbackend = dense_gn\n"
      "seed = -3\n[segment_wrld]\nx = 1\n[dense_gn]\nmax_iteratons = 3\n",
      "p.ini");
  const std::string msg = errorOf([&] { asf::framework::resolveConfig(ini, reg); });
  EXPECT_TRUE(has(msg, "p.ini:5: [pipeline] seed = '-3': out of range")) << msg;
  EXPECT_TRUE(has(msg,
                  "p.ini:3: [pipeline] frontend: unknown frontend plugin 'odometri'; "
                  "available frontend plugins: "))
      << msg;
  // The list names the available ones, in order: the one meant is among them.
  EXPECT_TRUE(
      std::regex_search(msg, std::regex("available frontend plugins: ([a-z_]+, )*odometry")))
      << msg;
  EXPECT_TRUE(has(msg, "p.ini:6: unknown section [segment_wrld] (did you mean [segment_world]?)"))
      << msg;
  EXPECT_TRUE(has(msg,
                  "p.ini:9: [dense_gn] unknown key 'max_iteratons' (did you mean "
                  "'max_iterations'?)"))
      << msg;
}

TEST(PipelineConfig, MissingSlotsAndWrongKinds) {
  asf::framework::Registry reg;
  std::string msg = errorOf(
      [&] { asf::framework::resolveConfig(asf::IniConfig::fromText("[map]\n", "p.ini"), reg); });
  EXPECT_TRUE(has(msg, "p.ini: no [pipeline] section")) << msg;
  EXPECT_TRUE(has(msg, "missing required key 'source'")) << msg;
  msg = errorOf([&] {
    asf::framework::resolveConfig(
        asf::IniConfig::fromText("[pipeline]\nsource = dense_gn\nfrontend = odometry\n", "p.ini"),
        reg);
  });
  EXPECT_TRUE(has(msg, "p.ini:2: [pipeline] source: plugin 'dense_gn'")) << msg;
  EXPECT_TRUE(has(msg, "is a backend, not a source")) << msg;
}

TEST(PipelineConfig, SectionOfAnUnusedPluginIsValidatedAndWarned) {
  asf::framework::Registry reg;
  const auto ini = asf::IniConfig::fromText(
      "[pipeline]\nsource = segment_world\nfrontend = odometry\n[shortest]\n", "p.ini");
  const auto rc = asf::framework::resolveConfig(ini, reg);
  ASSERT_EQ(rc.warnings.size(), 1u);
  EXPECT_TRUE(
      has(rc.warnings[0], "configures plugin 'shortest', which this pipeline does not use"));
}

// The source's recording is whole when the run says it finished, while the pipeline (and so
// the source) still lives: 137 frames, not a multiple of the writer's 50 per flush.
TEST(Pipeline, TheSourcesRecordingIsWholeWhenTheRunEnds) {
  const auto ini = asf::IniConfig::fromText(
      "[pipeline]\nsource = sim2d\nfrontend = odometry\nbackend = dense_gn\n"
      "segmenter = dude\nplanner = shortest\npolicy = waypoints\nseed = 1\nmax_steps = 137\n"
      "progress_interval = 0\nverbosity = WARN\n[waypoints]\nwaypoints = 3 0; 3 3; 0 3\n",
      "record.ini");
  asf::framework::Registry reg;
  const fs::path out = tempDir("recording");
  asf::framework::Pipeline p(asf::framework::resolveConfig(ini, reg), out.string());
  const asf::framework::RunSummary s = p.run();
  ASSERT_EQ(s.steps, 137) << s.stop_reason;
  asf::io::RawlogReader rec((out / "sim2d.rawlog").string());
  long recorded = 0;
  while (rec.next()) ++recorded;
  EXPECT_EQ(recorded, s.steps) << "the recording was not closed when the run ended";
  EXPECT_EQ(readJson(out / "progress.json")["status"], "stopped: " + s.stop_reason);
  std::ifstream gt(out / "sim2d.gt.txt");
  EXPECT_EQ(std::count(std::istreambuf_iterator<char>(gt), {}, '\n'), s.steps + 1)
      << "a header and one pose per frame";
}

TEST(Pipeline, DefaultRunFinishesAndWritesEveryOutput) {
  asf::framework::Registry reg;
  auto ini = asf::IniConfig::fromFile(kDefault);
  ini.set("pipeline", "progress_interval", "0");
  const auto rc = asf::framework::resolveConfig(ini, reg);
  const fs::path out = tempDir("default");
  asf::framework::Pipeline p(rc, out.string());
  const asf::framework::RunSummary s = p.run();
  EXPECT_TRUE(s.finished) << s.stop_reason;
  EXPECT_TRUE(has(s.stop_reason, "policy done")) << s.stop_reason;
  EXPECT_GT(s.distance_m, 15.0) << "the route is about 20 m long";
  EXPECT_GT(s.nodes, 20u);
  EXPECT_GE(s.regions, 1u);
  EXPECT_GE(s.final_pose_error_m, 0.0);
  EXPECT_LT(s.final_pose_error_m, 1.0) << "2% odometry noise over ~20 m";
  for (const auto& f : asf::framework::Pipeline::outputFiles())
    EXPECT_TRUE(fs::exists(out / f)) << f << " missing";
  EXPECT_EQ(lineCount(out / "trajectory.csv"), static_cast<std::size_t>(s.steps) + 1);
  const auto j = readJson(out / "summary.json");
  EXPECT_EQ(j["steps"], s.steps);
  EXPECT_EQ(j["finished"], true);
  const auto progress = readJson(out / "progress.json");
  EXPECT_EQ(progress["status"], "finished");
  EXPECT_GT(progress["step"].get<long>(), 0);
  // "finished" only once every output is in place: progress.json is the last file written.
  for (const auto& e : fs::directory_iterator(out))
    if (e.path().filename() != "run.log")  // the log goes on (the path home is logged after)
      EXPECT_LE(fs::last_write_time(e.path()), fs::last_write_time(out / "progress.json"))
          << e.path().filename() << " written after progress.json said finished";
  EXPECT_EQ(j["plugins"]["policy"], "waypoints");
  const auto g = asf::readG2o((out / "graph.g2o").string());
  EXPECT_EQ(g.nodes.size(), s.nodes);
  // The ATE covers every keyframe (each has ground truth here); keyframes.txt holds them.
  EXPECT_EQ(s.ate_poses, s.nodes);
  EXPECT_GT(s.ate_rmse_m, 0.0);
  EXPECT_LE(s.ate_rmse_m, s.ate_max_m);
  EXPECT_LT(s.ate_max_m, 1.0);
  EXPECT_EQ(j["ate_rmse_m"], s.ate_rmse_m);
  // The RPE of consecutive keyframes: local errors, below the largest absolute one here.
  EXPECT_GT(s.rpe_trans_rmse_m, 0.0);
  EXPECT_LT(s.rpe_trans_rmse_m, s.ate_max_m);
  EXPECT_EQ(j["rpe_trans_rmse_m"], s.rpe_trans_rmse_m);
  const auto kf = asf::evaluation::readTrajectory((out / "keyframes.txt").string());
  ASSERT_EQ(kf.size(), s.nodes);
  for (std::size_t i = 0; i < kf.size(); ++i)
    EXPECT_NEAR(kf[i].pose.x(), g.nodes[i].pose.x(), 1e-5) << "keyframe " << i;
  const auto topo = readJson(out / "topology.json");
  EXPECT_GE(topo["nodes"].size(), 2u) << "regions + the unexplored node";
  // The bare grid in its frame: every keyframe stands on a free cell of map.yaml.
  const asf::GridMap occ = asf::io::readOccupancyMap((out / "map.yaml").string());
  ASSERT_TRUE(occ.grid);
  for (const auto& n : g.nodes)
    EXPECT_GT(occ.grid->getPos(n.pose.x(), n.pose.y()), 0.5)
        << "node at (" << n.pose.x() << ", " << n.pose.y() << ") not on a free cell";

  // Same seed, same run: deterministic to the last digit.
  const fs::path out2 = tempDir("default2");
  asf::framework::Registry reg2;
  asf::framework::Pipeline p2(asf::framework::resolveConfig(ini, reg2), out2.string());
  const asf::framework::RunSummary s2 = p2.run();
  EXPECT_EQ(s2.steps, s.steps);
  EXPECT_EQ(s2.final_pose_error_m, s.final_pose_error_m);
  std::ifstream a(out / "trajectory.csv"), b(out2 / "trajectory.csv");
  EXPECT_TRUE(
      std::equal(std::istreambuf_iterator<char>(a), {}, std::istreambuf_iterator<char>(b), {}));
  fs::remove_all(out);
  fs::remove_all(out2);
}

TEST(Pipeline, InterruptedRunLeavesValidOutputs) {
  asf::framework::Registry reg;
  auto ini = asf::IniConfig::fromFile(kDefault);
  ini.set("pipeline", "progress_interval", "0");
  const fs::path out = tempDir("interrupted");
  asf::framework::Pipeline p(asf::framework::resolveConfig(ini, reg), out.string());
  std::atomic<bool> stop{true};
  const asf::framework::RunSummary s = p.run(&stop);
  EXPECT_EQ(s.stop_reason, "interrupted");
  EXPECT_FALSE(s.finished);
  const auto j = readJson(out / "summary.json");
  EXPECT_EQ(j["stop_reason"], "interrupted");
  EXPECT_TRUE(fs::exists(out / "graph.g2o"));
  EXPECT_GE(lineCount(out / "timeseries.csv"), 2u) << "header and the final row";
  EXPECT_TRUE(fs::exists(out / "report.html"));
  fs::remove_all(out);
}

TEST(Pipeline, PolicyThatNeverMovesTheRobotIsStopped) {
  // A looping route whose only waypoint is where the robot stands: every goal is reached at
  // once and the policy would go on forever; the host stops it.
  asf::framework::Registry reg;
  auto ini = asf::IniConfig::fromFile(kDefault);
  ini.set("pipeline", "progress_interval", "0");
  ini.set("pipeline", "max_idle_decisions", "20");
  ini.set("waypoints", "waypoints", "0 0");
  ini.set("waypoints", "loop", "true");
  const fs::path out = tempDir("idle");
  asf::framework::Pipeline p(asf::framework::resolveConfig(ini, reg), out.string());
  const asf::framework::RunSummary s = p.run();
  EXPECT_FALSE(s.finished);
  EXPECT_TRUE(has(s.stop_reason, "no progress: the policy's last 20 decisions")) << s.stop_reason;
  EXPECT_EQ(s.decisions, 20);
  fs::remove_all(out);
}

TEST(Pipeline, PolicySeesThePipelinesPlanner) {
  // [pipeline] planner is a service for the policy (ExplorationState::planner): the test
  // policy asks it for the path from the newest node home at each decision and writes the
  // answer into the decision's reason; without a planner it is told there is none.
  for (const std::string planner : {"shortest", ""}) {
    asf::framework::Registry reg;
    auto ini = asf::IniConfig::fromFile(kDefault);
    ini.set("pipeline", "policy", "test_policy");
    ini.set("pipeline", "planner", planner);
    ini.set("pipeline", "plugin_path", ASF_TEST_BINARY_DIR "/tests/plugins/good");
    ini.set("pipeline", "progress_interval", "0");
    ini.set("test_policy", "fail_after", "4");
    ini.set("test_policy", "plan_home", "true");
    const fs::path out = tempDir("policy_planner");
    asf::framework::Pipeline p(asf::framework::resolveConfig(ini, reg), out.string());
    errorOf([&] { p.run(); });  // the test policy throws after its 4 decisions
    std::ifstream in(out / "decisions.csv");
    const std::string csv((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (planner.empty()) {
      EXPECT_TRUE(has(csv, "planner: none")) << csv;
      EXPECT_FALSE(has(csv, "planner: path")) << csv;
    } else {
      EXPECT_FALSE(has(csv, "planner: none")) << csv;
      const std::regex path("planner: path of ([0-9]+) nodes from node ([0-9]+) to node 0");
      std::smatch m;
      ASSERT_TRUE(std::regex_search(csv, m, path)) << csv;
      EXPECT_GE(std::stoi(m[1]), 2);
      EXPECT_GE(std::stoi(m[2]), 1);
    }
    fs::remove_all(out);
  }
}

TEST(Pipeline, PluginFailureMidRunKeepsWhatWasProduced) {
  // The test policy shuttles for 3 goals and throws on its 4th decision; the run must
  // report the error and still leave the steps driven so far on disk.
  asf::framework::Registry reg;
  auto ini = asf::IniConfig::fromFile(kDefault);
  ini.set("pipeline", "policy", "test_policy");
  ini.set("pipeline", "plugin_path", ASF_TEST_BINARY_DIR "/tests/plugins/good");
  ini.set("pipeline", "progress_interval", "0");
  ini.set("test_policy", "fail_after", "3");
  const fs::path out = tempDir("failure");
  asf::framework::Pipeline p(asf::framework::resolveConfig(ini, reg), out.string());
  const std::string msg = errorOf([&] { p.run(); });
  EXPECT_TRUE(has(msg, "test policy fails on purpose")) << msg;
  const auto j = readJson(out / "summary.json");
  EXPECT_TRUE(has(j["stop_reason"].get<std::string>(), "error: test policy fails on purpose"));
  EXPECT_GT(lineCount(out / "trajectory.csv"), 10u) << "the steps before the failure";
  EXPECT_EQ(j["decisions"], 3) << "the throwing decision is not counted";
  EXPECT_TRUE(fs::exists(out / "config.ini"));
  fs::remove_all(out);
}
