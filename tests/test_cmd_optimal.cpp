// asf optimal on a topological graph (topology.json) and its exhaustive walk search
// (--walks, --plot): the figures 5.6-5.10 command.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "test_util.h"

namespace fs = std::filesystem;
using asf_test::has;
using asf_test::runHost;

namespace {

fs::path tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("asf_test_cmd_optimal_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

TEST(AsfOptimalCommand, ExhaustiveWalksMeetTheRelaxedOptimumOnACycle) {
  // A 4-cycle with a chord 1-3. The E-optimal weights are the cycle's, 1/4 each (the chord
  // gets none); the closed walk round the cycle (d = 4) has exactly those weights, so the best
  // E rate over walks of 4 traversals equals the relaxed optimum, 0.5 (eigenvalues of the
  // cycle's Laplacian / 4: 0.5, 1, 0.5).
  const fs::path d = tempDir("walks");
  std::ofstream(d / "g.txt") << "4 5 1-2 2-3 3-4 4-1 1-3\n";
  const auto r = runHost("optimal " + (d / "g.txt").string() +
                             " --criteria E --walks 5 --json -p " + (d / "w.svg").string(),
                         false);
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["optimum"]["E"].get<double>(), 0.5, 1e-6);
  const auto& x = j["exhaustive"];
  ASSERT_EQ(x["d"].size(), 5u);
  EXPECT_EQ(x["rate"]["E"][0].get<double>(), 0.0) << "one edge leaves the graph disconnected";
  EXPECT_NEAR(x["rate"]["E"][3].get<double>(), 0.5, 1e-9);
  for (const auto& v : x["rate"]["E"])
    EXPECT_LE(v.get<double>(), 0.5 + 1e-9) << "never above the optimum";
  std::ifstream svg(d / "w.svg");
  const std::string text((std::istreambuf_iterator<char>(svg)), std::istreambuf_iterator<char>());
  EXPECT_TRUE(has(text, "<svg"));
  // --plot needs --walks; --start must name a node.
  const auto bad = runHost("optimal " + (d / "g.txt").string() + " -p " + (d / "x.svg").string());
  EXPECT_EQ(bad.code, 1);
  EXPECT_TRUE(has(bad.out, "--walks")) << bad.out;
  const auto bad_start = runHost("optimal " + (d / "g.txt").string() + " --walks 3 --start 9");
  EXPECT_EQ(bad_start.code, 1);
  EXPECT_TRUE(has(bad_start.out, "--start 9: nodes are 1..4")) << bad_start.out;
  fs::remove_all(d);
}

// A large graph says on stderr which criterion it is solving and how long it took (issue 20,
// item 7: a 3600-node graph ran for minutes without a word); a small one stays quiet.
TEST(AsfOptimalCommand, LargeGraphsShowProgressPerCriterion) {
  const fs::path d = tempDir("progress");
  {
    std::ofstream f(d / "path.txt");
    f << "520 519";
    for (int i = 1; i < 520; ++i) f << " " << i << "-" << i + 1;
    f << "\n";
  }
  const auto r = runHost("optimal " + (d / "path.txt").string() + " --criteria D --json");
  ASSERT_EQ(r.code, 0) << r.out.substr(0, 400);
  EXPECT_TRUE(has(r.out, "asf optimal: D-optimal weights of 520 nodes, 519 edges"))
      << r.out.substr(0, 400);
  EXPECT_TRUE(has(r.out, "asf optimal: D done: ")) << r.out.substr(0, 400);
  // Within a criterion: one line per iteration with --progress-interval 0 (issue 20, item 7:
  // a 3600-node criterion ran for minutes without a word), bounds that enclose the optimum.
  const auto it = runHost("optimal " + (d / "path.txt").string() +
                          " --criteria D,E --progress-interval 0 --json");
  ASSERT_EQ(it.code, 0) << it.out.substr(0, 400);
  EXPECT_TRUE(has(it.out, "asf optimal: D: iteration 0, optimum in [")) << it.out.substr(0, 600);
  EXPECT_TRUE(has(it.out, "asf optimal: E: iteration 1, optimum in [")) << it.out.substr(0, 600);
  const auto quiet = runHost("optimal " + (d / "path.txt").string() +
                             " --criteria D,E --progress-interval 1e9 --json");
  EXPECT_FALSE(has(quiet.out, ": iteration ")) << quiet.out.substr(0, 600);
  EXPECT_TRUE(has(quiet.out, "asf optimal: E done: ")) << quiet.out.substr(0, 600);
  EXPECT_NE(runHost("optimal " + (d / "path.txt").string() + " --progress-interval -1").code, 0);
  std::ofstream(d / "small.txt") << "4 5 1-2 2-3 3-4 4-1 1-3\n";
  const auto s = runHost("optimal " + (d / "small.txt").string() + " --criteria D");
  ASSERT_EQ(s.code, 0) << s.out;
  EXPECT_FALSE(has(s.out, "asf optimal: D-optimal weights")) << s.out;
  fs::remove_all(d);
}

TEST(AsfOptimalCommand, ReadsATopologicalGraph) {
  // Three regions in a row plus a frontier edge: the frontier and the unexplored node are
  // not part of the graph (a path of 3 nodes, 2 edges: D-optimal weights 1/2 each).
  const fs::path d = tempDir("topology");
  std::ofstream(d / "topology.json") << R"({"nodes": [{"region": 4}, {"region": 7}, {"region": 9},
    {"region": -1}], "edges": [{"a": 4, "b": 7, "frontier": false}, {"a": 7, "b": 9,
    "frontier": false}, {"a": 9, "b": -1, "frontier": true}]})";
  const auto r =
      runHost("optimal " + (d / "topology.json").string() + " --criteria D --json", false);
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["n"], 3);
  EXPECT_EQ(j["m"], 2);
  EXPECT_TRUE(j["connected"].get<bool>());
  EXPECT_NEAR(j["weights"]["D"][0].get<double>(), 0.5, 1e-6);
  std::ofstream(d / "bad.json") << R"({"nodes": [{"region": 1}], "edges": [{"a": 1, "b": 5}]})";
  const auto bad = runHost("optimal " + (d / "bad.json").string());
  EXPECT_EQ(bad.code, 1);
  EXPECT_TRUE(has(bad.out, "names a region that is not a node")) << bad.out;
  // A node without its region, a region that is text: errors naming the file, not a bare
  // json.exception (issue 20, item 7).
  for (const char* text : {R"({"nodes": [{"centroid": [0, 0]}], "edges": []})",
                           R"({"nodes": [{"region": "one"}], "edges": []})",
                           R"({"nodes": [{"region": 1}], "edges": [{"a": 1}]})"}) {
    std::ofstream(d / "field.json") << text;
    const auto r2 = runHost("optimal " + (d / "field.json").string());
    EXPECT_EQ(r2.code, 1) << text << "\n" << r2.out;
    EXPECT_TRUE(has(r2.out, (d / "field.json").string() + ": not a topology.json as asf writes it"))
        << text << "\n"
        << r2.out;
    EXPECT_FALSE(has(r2.out, "unexpected error")) << r2.out;
  }
  // A region listed twice (before, its centroid was kept twice: positions and nodes then
  // disagreed in count).
  std::ofstream(d / "twice.json")
      << R"({"nodes": [{"region": 1, "centroid": [0, 0]}, {"region": 1, "centroid": [1, 0]}],
             "edges": []})";
  const auto twice = runHost("optimal " + (d / "twice.json").string() + " --draw " +
                             (d / "twice.svg").string());
  EXPECT_EQ(twice.code, 1) << twice.out;
  EXPECT_TRUE(has(twice.out, (d / "twice.json").string() + ": region 1 is listed twice"))
      << twice.out;
  fs::remove_all(d);
}

}  // namespace
