// asf plan-eval (thesis Table 3.1 protocol) end to end: on a synthetic building -- a ring
// of corridors with a short cut through a feature-void zone -- the expected-uncertainty
// planner avoids the zone where the shortest path crosses it; config errors name the key;
// and, when ../shared is here, a subset of the protocol on the Intel CARMEN log's SLAM graph.
#include <asf/errors.h>
#include <asf/planning/expected_uncertainty.h>
#include <asf/io/rawlog_io.h>
#include <asf/sensor_frame.h>
#include <gtest/gtest.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "plan_eval_figure.h"
#include "test_util.h"

namespace {

namespace fs = std::filesystem;

fs::path tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("asf_test_plan_eval_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// A 12 m x 6 m ring of corridors (nodes every metre, ids 0..35 in driving order, closed
/// by a loop closure 35 -> 0) and a middle corridor from (0, 3) to (12, 3) (ids 36..46),
/// precise scan-matching edges everywhere, two loop closures inside the future zone.
void writeBuilding(const fs::path& g2o) {
  std::vector<std::pair<double, double>> xy;
  for (int x = 0; x < 12; ++x) xy.emplace_back(x, 0);  // 0..11   south
  for (int y = 0; y < 6; ++y) xy.emplace_back(12, y);  // 12..17  east
  for (int x = 12; x > 0; --x) xy.emplace_back(x, 6);  // 18..29  north
  for (int y = 6; y > 0; --y) xy.emplace_back(0, y);   // 30..35  west
  for (int x = 1; x < 12; ++x) xy.emplace_back(x, 3);  // 36..46  middle
  std::ofstream f(g2o);
  for (std::size_t i = 0; i < xy.size(); ++i)
    f << "VERTEX_SE2 " << i << " " << xy[i].first << " " << xy[i].second << " 0\n";
  auto edge = [&](int a, int b) {
    const double ixy = 1 / (0.01 * 0.01), iphi = 1 / (0.005 * 0.005);
    f << "EDGE_SE2 " << a << " " << b << " " << xy[b].first - xy[a].first << " "
      << xy[b].second - xy[a].second << " 0 " << ixy << " 0 0 " << ixy << " 0 " << iphi << "\n";
  };
  for (int i = 0; i < 35; ++i) edge(i, i + 1);
  edge(35, 0);
  const int west_mid = 33, east_mid = 15;  // (0, 3) and (12, 3)
  edge(west_mid, 36);
  for (int i = 36; i < 46; ++i) edge(i, i + 1);
  edge(46, east_mid);
  edge(40, 42);  // loop closures inside the zone: dropped by the protocol
  edge(41, 43);
}

std::string writeConfig(const fs::path& dir, const std::string& extra = "") {
  const fs::path ini = dir / "plan_eval.ini";
  std::ofstream(ini) << "[plan_eval]\n"
                        "graph = building.g2o\n"
                        "zones = 4 2 8 4\n"
                        "factors = 10 100\n"
                        "pair_grid = 2\n"
                        "seed = 3\n"
                        "progress_every = 10\n"
                        "zone_covariance = odometry\n"
                     << extra
                     << "[expected_uncertainty]\n"
                        "merge_radius = 0.5\n"
                        "max_seconds = 0\n"
                        "[mechanical_work]\n"
                        "merge_radius = 0.5\n"
                        "[sum_dopt]\n"
                        "merge_radius = 0.5\n";
  return ini.string();
}

std::string readText(const fs::path& f) {
  std::ifstream in(f);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t i = s.find(what); i != std::string::npos; i = s.find(what, i + 1)) ++n;
  return n;
}

TEST(PlanEval, ExpectedUncertaintyAvoidsTheZoneShortestCrossesIt) {
  const fs::path dir = tempDir("building");
  writeBuilding(dir / "building.g2o");
  const std::string ini = writeConfig(dir);
  const auto r = asf_test::runHost("plan-eval " + ini + " --out " + (dir / "out").string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(asf_test::has(r.out, "[A] 10/")) << "progress lines expected\n" << r.out;
  ASSERT_TRUE(fs::exists(dir / "out" / "plan_eval.md"));
  std::ifstream jf(dir / "out" / "plan_eval.json");
  const auto j = nlohmann::json::parse(jf);
  ASSERT_EQ(j["scenarios"].size(), 2u);
  for (const auto& s : j["scenarios"]) {
    const std::string what = "scenario " + s["name"].get<std::string>();
    EXPECT_EQ(s["zone_nodes"].get<int>(), 5) << what;  // x = 4..8 on the middle corridor
    EXPECT_EQ(s["dropped_loop_closures"].get<int>(), 2) << what;
    const std::size_t pairs = s["pairs"].get<std::size_t>();
    EXPECT_GT(pairs, 50u) << what;
    EXPECT_EQ(s["pairs_without_avoiding_candidate"].get<int>(), 0) << what;
    const auto& pl = s["planners"];
    for (const char* name : {"expected_uncertainty", "mechanical_work", "sum_dopt", "shortest"}) {
      EXPECT_EQ(pl[name]["found"].get<std::size_t>(), pairs) << what << " " << name;
      EXPECT_EQ(pl[name]["not_found"].get<int>(), 0) << what << " " << name;
    }
    const double eu = pl["expected_uncertainty"]["error_rate"].get<double>();
    const double shortest = pl["shortest"]["error_rate"].get<double>();
    // West-east pairs take the short cut when only distance counts (the pairs are all
    // pairs of a 2 m grid of the ring, most of them on one side of the zone).
    EXPECT_GT(shortest, 0.05) << what;
    EXPECT_GE(pl["shortest"]["errors"].get<int>(), 8) << what;
    EXPECT_EQ(eu, 0.0) << what << ": expected_uncertainty crossed the zone";
    // Every pair's record agrees with the tally.
    std::size_t crossed = 0;
    for (const auto& p : s["pair_results"]) crossed += p["shortest"]["crosses"].get<bool>();
    EXPECT_EQ(crossed, pl["shortest"]["errors"].get<std::size_t>()) << what;
    // Every chosen path runs from the pair's start to its goal, and "crosses" is what its
    // nodes say (zone nodes: 39..43).
    for (const auto& p : s["pair_results"])
      for (const char* name : {"expected_uncertainty", "mechanical_work", "sum_dopt", "shortest"}) {
        const auto path = p[name]["path"].get<std::vector<int>>();
        ASSERT_FALSE(path.empty()) << what << " " << name;
        EXPECT_EQ(path.front(), p["start"].get<int>()) << what << " " << name;
        EXPECT_EQ(path.back(), p["goal"].get<int>()) << what << " " << name;
        EXPECT_EQ(path.size(), p[name]["nodes"].get<std::size_t>()) << what << " " << name;
        const bool in =
            std::any_of(path.begin(), path.end(), [](int v) { return v >= 39 && v <= 43; });
        EXPECT_EQ(in, p[name]["crosses"].get<bool>()) << what << " " << name;
      }
    // Fig. 3.4: the scenario drawn, every node once, the zone as a rectangle. No baseline
    // erred, so there is no Fig. 3.5 example.
    const std::string svg = readText(dir / "out" / s["figures"]["scenario"].get<std::string>());
    EXPECT_EQ(count(svg, "<circle"), 47u) << what;
    EXPECT_EQ(count(svg, "fill=\"#2c6fdc\"/>"), 5u) << what << ": the zone's nodes in blue";
    EXPECT_TRUE(s["figures"]["error_example"].is_null()) << what;
    // Zone nodes are not starts or goals.
    for (const auto& p : s["pair_results"])
      for (const char* k : {"start", "goal"}) {
        const int v = p[k].get<int>();
        EXPECT_FALSE(v >= 39 && v <= 43) << what << ": " << k << " " << v << " is in the zone";
      }
  }
  // The thesis' zone model instead of wheel odometry: scaled own covariances.
  const auto r2 = asf_test::runHost("plan-eval " + ini + " --out " + (dir / "out2").string() +
                                    " --set plan_eval.zone_covariance=scaled --set "
                                    "plan_eval.max_pairs=20 --set plan_eval.factors=100");
  ASSERT_EQ(r2.code, 0) << r2.out;
  std::ifstream jf2(dir / "out2" / "plan_eval.json");
  const auto j2 = nlohmann::json::parse(jf2);
  ASSERT_EQ(j2["scenarios"].size(), 1u);
  EXPECT_EQ(j2["scenarios"][0]["pairs"].get<int>(), 20);

  // A picture that cannot be written (its name taken by a folder) is reported; the results
  // are still written.
  fs::create_directories(dir / "out3" / "scenario_A.svg");
  const auto r3 = asf_test::runHost("plan-eval " + ini + " --out " + (dir / "out3").string() +
                                    " --set plan_eval.max_pairs=5 --set plan_eval.factors=10");
  ASSERT_EQ(r3.code, 0) << r3.out;
  EXPECT_TRUE(asf_test::has(r3.out, "[A] figures not written: ")) << r3.out;
  std::ifstream jf3(dir / "out3" / "plan_eval.json");
  const auto j3 = nlohmann::json::parse(jf3);
  EXPECT_TRUE(
      asf_test::has(j3["scenarios"][0]["figures"]["error"].get<std::string>(), "is a directory"));
}

// Fig. 3.5's example: the first pair where the baseline crosses and expected uncertainty does
// not; its picture draws both paths over the graph, S and G at the first path's ends.
TEST(PlanEvalFigure, ErrorExampleIsTheFirstPairWhereOnlyTheBaselineCrosses) {
  using nlohmann::json;
  auto pair = [](int start, bool eu_crosses, bool mw_crosses) {
    return json{
        {"start", start},
        {"goal", 5},
        {"expected_uncertainty", {{"crosses", eu_crosses}, {"nodes", 3}, {"path", {start, 4, 5}}}},
        {"mechanical_work", {{"crosses", mw_crosses}, {"nodes", 3}, {"path", {start, 2, 5}}}}};
  };
  const json pairs = json::array(
      {pair(0, false, false), pair(1, true, true), pair(3, false, true), pair(0, false, true)});
  EXPECT_EQ(asf::studies::errorExample(pairs, "mechanical_work")["start"].get<int>(), 3);
  EXPECT_TRUE(asf::studies::errorExample(pairs, "sum_dopt").is_null());
  EXPECT_TRUE(
      asf::studies::errorExample(json::array({pair(1, true, true)}), "mechanical_work").is_null());

  asf::PoseGraph g;
  for (int i = 0; i < 6; ++i) {
    asf::PoseNode n;
    n.pose = mrpt::poses::CPose2D(i, i % 2, 0);
    g.nodes.push_back(n);
  }
  const asf::planning::Zone zone{1.5, -1, 2.5, 2};  // holds node 2 only
  json scen{{"name", "C"}, {"zone_index", 2}, {"factor", 10.0}, {"pair_results", pairs}};
  const fs::path dir = tempDir("figure");
  const json rec = asf::studies::writeScenarioFigures(g, zone, scen, dir.string());
  EXPECT_EQ(rec["scenario"].get<std::string>(), "scenario_C.svg");
  ASSERT_TRUE(rec["error_example"].is_object());
  EXPECT_EQ(rec["error_example"]["start"].get<int>(), 3);
  EXPECT_EQ(rec["error_example"]["baseline"].get<std::string>(), "mechanical_work");
  const std::string svg = readText(dir / "error_example_C.svg");
  EXPECT_EQ(count(svg, "<polyline"), 2u);
  EXPECT_EQ(count(svg, ">S</text>") + count(svg, ">G</text>"), 2u);
  EXPECT_EQ(count(svg, "fill=\"#2c6fdc\"/>"), 1u) << "node 2 alone is in the zone";
  EXPECT_TRUE(svg.find("node 3 to node 5") != std::string::npos);
  // A path through a node the graph does not have is an input error.
  EXPECT_THROW(asf::studies::scenarioSvg(g, zone, {{"bad", "red", {0, 9}}}, "t"), asf::InputError);
}

TEST(PlanEval, ConfigErrorsNameTheKeyOrSection) {
  const fs::path dir = tempDir("errors");
  writeBuilding(dir / "building.g2o");
  auto r = asf_test::runHost("plan-eval " + writeConfig(dir, "zone = 1 2 3 4\n"));
  EXPECT_NE(r.code, 0);
  EXPECT_TRUE(asf_test::has(r.out, "unknown key 'zone'") && asf_test::has(r.out, "zones")) << r.out;
  r = asf_test::runHost("plan-eval " + writeConfig(dir) + " --set expected_uncertainity.k_paths=3");
  EXPECT_NE(r.code, 0);
  EXPECT_TRUE(asf_test::has(r.out, "[expected_uncertainity]") &&
              asf_test::has(r.out, "did you mean [expected_uncertainty]"))
      << r.out;
  r = asf_test::runHost("plan-eval " + writeConfig(dir) + " --set expected_uncertainty.kpaths=3");
  EXPECT_NE(r.code, 0);
  EXPECT_TRUE(asf_test::has(r.out, "kpaths") && asf_test::has(r.out, "k_paths")) << r.out;
  r = asf_test::runHost("plan-eval " + writeConfig(dir) + " --set plan_eval.zones=1,2,3");
  EXPECT_NE(r.code, 0);
  EXPECT_TRUE(asf_test::has(r.out, "zones") && asf_test::has(r.out, "four numbers")) << r.out;
  r = asf_test::runHost("plan-eval " + writeConfig(dir) + " --set plan_eval.zones=50,50,60,60");
  EXPECT_NE(r.code, 0);
  EXPECT_TRUE(asf_test::has(r.out, "holds no node")) << r.out;
  // The thesis' zone needs the run's log for its wheel odometry.
  r = asf_test::runHost("plan-eval " + writeConfig(dir) +
                        " --set plan_eval.zone_covariance=wheel_odometry");
  EXPECT_NE(r.code, 0);
  EXPECT_TRUE(asf_test::has(r.out, "zone_covariance") && asf_test::has(r.out, "rawlog")) << r.out;
}

/// The building's run: keyframes.txt (node i at t = 10 + i) and its log, one frame per node,
/// odometry 1 m ahead, a 181-ray scan of the corridor walls 1 m to each side (nodes
/// `without_scan` get none).
void writeBuildingRun(const fs::path& dir, const std::vector<int>& without_scan = {}) {
  std::ofstream kf(dir / "keyframes.txt");
  asf::io::RawlogWriter w((dir / "building.rawlog").string());
  for (int i = 0; i < 47; ++i) {
    kf << 10 + i << " 0 0 0\n";
    asf::SensorFrame f;
    f.timestamp = 10 + i;
    f.odometry = mrpt::poses::CPose2D(1, 0, 0);
    f.odometry_cov = Eigen::Vector3d(1e-4, 1e-4, 1e-5).asDiagonal();
    if (std::find(without_scan.begin(), without_scan.end(), i) == without_scan.end()) {
      auto s = std::make_shared<mrpt::obs::CObservation2DRangeScan>();
      s->aperture = static_cast<float>(M_PI);
      s->maxRange = 8;
      s->resizeScan(181);
      for (std::size_t k = 0; k < 181; ++k) {
        const double a = -M_PI / 2 + M_PI * static_cast<double>(k) / 180;
        const double r = std::min(8.0, 1.0 / std::max(1e-3, std::abs(std::sin(a))));
        s->setScanRange(k, static_cast<float>(r));
        s->setScanRangeValidity(k, r < 8);
      }
      f.scan = s;
    }
    w.write(f);
  }
}

TEST(PlanEval, WithTheRunsLogTheZonesScansAreIgnoredAndRecognitionIsMonteCarlo) {
  const fs::path dir = tempDir("with_log");
  writeBuilding(dir / "building.g2o");
  writeBuildingRun(dir);
  const std::string ini = writeConfig(dir,
                                      "rawlog = building.rawlog\nrecognition_samples = 4\n"
                                      "max_pairs = 6\n");
  auto r = asf_test::runHost("plan-eval " + ini + " --out " + (dir / "out").string() +
                             " --set plan_eval.zone_covariance=wheel_odometry" +
                             " --set plan_eval.factors=100");
  ASSERT_EQ(r.code, 0) << r.out;
  std::ifstream jf(dir / "out" / "plan_eval.json");
  const auto j = nlohmann::json::parse(jf);
  ASSERT_EQ(j["scenarios"].size(), 1u);
  const auto& s = j["scenarios"][0];
  EXPECT_EQ(s["zone_nodes"].get<int>(), 5);
  EXPECT_EQ(s["scans_removed"].get<int>(), 5);
  EXPECT_EQ(s["scaled_edges"].get<int>(), 6);  // 38-39 ... 43-44: consecutive, touching
  EXPECT_EQ(s["dropped_loop_closures"].get<int>(), 2);
  ASSERT_FALSE(s["recognition"].is_null());
  EXPECT_EQ(s["recognition"]["nodes"].get<int>(), 42);
  // The planners' recognition file: the zone at 0, every other node a Monte Carlo value.
  std::ifstream rf(dir / "out" / "recognition_A.txt");
  std::string line;
  int rows = 0;
  while (std::getline(rf, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream is(line);
    int v;
    double p;
    is >> v >> p;
    ++rows;
    if (v >= 39 && v <= 43) {
      EXPECT_EQ(p, 0.0) << "zone node " << v;
    }
    EXPECT_TRUE(p >= 0 && p <= 1) << line;
  }
  EXPECT_EQ(rows, 47);
  // A log whose zone frames have no scans: nothing to ignore, a clear error.
  writeBuildingRun(dir, {39, 40, 41, 42, 43});
  r = asf_test::runHost("plan-eval " + ini + " --out " + (dir / "out2").string() +
                        " --set plan_eval.zone_covariance=wheel_odometry");
  EXPECT_NE(r.code, 0);
  EXPECT_TRUE(asf_test::has(r.out, "zones") && asf_test::has(r.out, "has a scan in")) << r.out;
  // Another run's keyframes: the log has no frame at their times.
  std::ofstream(dir / "keyframes.txt") << "0.5 0 0 0\n";
  r = asf_test::runHost("plan-eval " + ini + " --out " + (dir / "out3").string() +
                        " --set plan_eval.zone_covariance=wheel_odometry");
  EXPECT_NE(r.code, 0);
  EXPECT_TRUE(asf_test::has(r.out, "keyframes.txt") && asf_test::has(r.out, "47 nodes")) << r.out;
}

TEST(Recognition, CommandWritesEveryNodesProbabilityAndTheScatterAsked) {
  const fs::path dir = tempDir("recognition");
  writeBuilding(dir / "building.g2o");
  writeBuildingRun(dir, {40});
  const std::string base = "recognition " + (dir / "building.g2o").string() + " -r " +
                           (dir / "building.rawlog").string() + " -n 4 -j 2 -o ";
  auto r = asf_test::runHost(base + (dir / "out").string() + " -s 3 -s 45");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(asf_test::has(r.out, "46 nodes with a scan")) << r.out;
  const auto back = asf::planning::readRecognitionProbabilities((dir / "out/recognition.txt").string());
  ASSERT_EQ(back.size(), 47u);
  EXPECT_EQ(back.at(40), 0.0) << "no scan, no recognition";
  for (const char* f : {"scatter_3.svg", "scatter_45.svg", "recognition.json"})
    EXPECT_TRUE(fs::exists(dir / "out" / f)) << f;
  r = asf_test::runHost(base + (dir / "out2").string() + " -s 47");
  EXPECT_NE(r.code, 0);
  EXPECT_TRUE(asf_test::has(r.out, "--scatter 47") && asf_test::has(r.out, "0..46")) << r.out;
}

/// The protocol on the real log, on a few pairs: the Intel CARMEN log converted, its graph
/// SLAM run, then plan-eval with configs/plan_eval_intel.ini pointed at that graph.
TEST(PlanEval, IntelSubsetRuns) {
  const fs::path log = fs::path(ASF_TEST_SHARED_DIR) / "datasets/carmen/intel-corrected.log.gz";
  if (!fs::exists(log)) GTEST_SKIP() << "../shared is not available here (" << log << ")";
  const fs::path dir = tempDir("intel");
  const std::string src = ASF_TEST_SOURCE_DIR;
  auto r = asf_test::runHost("carmen2rawlog -q -i " + log.string() + " -o " +
                             (dir / "intel.rawlog.gz").string() + " --gt " +
                             (dir / "intel.gt.txt").string() + " --synth-odometry --seed 1");
  ASSERT_EQ(r.code, 0) << r.out;
  r = asf_test::runHost("run " + src + "/configs/slam_intel.ini --out " + (dir / "slam").string() +
                        " --set rawlog.file=" + (dir / "intel.rawlog.gz").string() +
                        " --set rawlog.ground_truth=" + (dir / "intel.gt.txt").string());
  ASSERT_EQ(r.code, 0) << r.out.substr(r.out.size() > 3000 ? r.out.size() - 3000 : 0);
  r = asf_test::runHost("plan-eval " + src + "/configs/plan_eval_intel.ini --out " +
                        (dir / "eval").string() +
                        " --set plan_eval.graph=" + (dir / "slam" / "graph.g2o").string() +
                        " --set plan_eval.rawlog=" + (dir / "intel.rawlog.gz").string() +
                        " --set plan_eval.max_pairs=6 --set plan_eval.factors=100"
                        " --set plan_eval.recognition_samples=4");
  ASSERT_EQ(r.code, 0) << r.out;
  std::ifstream jf(dir / "eval" / "plan_eval.json");
  const auto j = nlohmann::json::parse(jf);
  ASSERT_EQ(j["scenarios"].size(), 2u);
  for (const auto& s : j["scenarios"]) {
    EXPECT_EQ(s["pairs"].get<int>(), 6);
    EXPECT_GT(s["zone_nodes"].get<int>(), 0);
    EXPECT_EQ(s["planners"]["expected_uncertainty"]["not_found"].get<int>(), 0);
    EXPECT_EQ(s["scans_removed"], s["zone_nodes"]) << "every keyframe of the log has a scan";
    EXPECT_FALSE(s["recognition"].is_null());
  }
}

}  // namespace
