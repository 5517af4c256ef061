// Graph families (asf/graph/families.h), `asf graph-gen` and `asf optimal-eval`: generator
// invariants, list round trips, and the evaluation's figures on graphs with known answers.
#include <asf/errors.h>
#include <asf/graph/families.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <set>

#include "test_util.h"

using asf_test::has;
namespace fs = std::filesystem;
namespace gr = asf::graph;

namespace {
fs::path tmp(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / "asf_test_optimal_eval";
  fs::create_directories(d);
  return d / name;
}
bool simple(const gr::Multigraph& g) {
  std::set<std::pair<int, int>> seen;
  for (const auto& e : g.edges)
    if (e.u == e.v || !seen.insert({std::min(e.u, e.v), std::max(e.u, e.v)}).second) return false;
  return true;
}
}  // namespace

TEST(GraphFamilies, GeneratorsHaveTheirDefiningProperties) {
  const auto grid = gr::gridGraph(3, 4);
  EXPECT_EQ(grid.n, 12);
  EXPECT_EQ(grid.m(), 3 * 3 + 2 * 4);  // horizontal + vertical
  EXPECT_TRUE(grid.connected());
  for (int n : {1, 2, 3, 10, 57}) {
    const auto t = gr::randomTree(n, 7 + n);
    EXPECT_EQ(t.n, n);
    EXPECT_EQ(t.m(), n - 1);
    EXPECT_EQ(n == 1 || t.connected(), true) << "a tree on " << n << " nodes";
    EXPECT_TRUE(simple(t));
  }
  const auto sw = gr::smallWorld(30, 4, 0.3, 5);
  EXPECT_EQ(sw.m(), 60) << "rewiring keeps the edge count n k / 2";
  EXPECT_TRUE(sw.connected());
  EXPECT_TRUE(simple(sw));
  const auto rc = gr::roomsAndCorridor(6, 3, 0.5, 1.0, 3);
  EXPECT_TRUE(rc.connected());
  EXPECT_LE(rc.n, 6 * 4);
  EXPECT_TRUE(has(asf_test::errorOf<asf::Error>([] { gr::smallWorld(10, 3, 0.1, 1); }),
                  "k must be even"));
}

TEST(GraphFamilies, ListsAreSeededCappedAndRoundTrip) {
  const auto a = gr::generateFamily("mixed", 40, 30, 11);
  const auto b = gr::generateFamily("mixed", 20, 30, 11);
  for (std::size_t i = 0; i < b.size(); ++i) {
    ASSERT_EQ(a[i].n, b[i].n) << "graph " << i << " depends only on seed + i";
    ASSERT_EQ(a[i].m(), b[i].m());
  }
  for (const auto& g : a) {
    EXPECT_GE(g.n, 4);
    EXPECT_LE(g.n, 30);
    EXPECT_TRUE(g.connected());
  }
  const fs::path f = tmp("roundtrip.txt");
  gr::writeGraphList(f.string(), a, "test list");
  const auto back = gr::readGraphList(f.string());
  ASSERT_EQ(back.size(), a.size());
  EXPECT_EQ(back[0].line, 2) << "after the comment line";
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(back[i].graph.m(), a[i].m());
    for (int j = 0; j < a[i].m(); ++j) {
      EXPECT_EQ(back[i].graph.edges[j].u, a[i].edges[j].u);
      EXPECT_EQ(back[i].graph.edges[j].v, a[i].edges[j].v);
    }
  }
  EXPECT_TRUE(has(asf_test::errorOf<asf::Error>([] { gr::generateFamily("mesh", 1, 10, 1); }),
                  "unknown graph family 'mesh'"));
}

TEST(OptimalEval, KnownAnswersAndTheDocumentedJson) {
  // Line 2: K4 (uniform weights are optimal for every criterion, so every route that covers
  // each edge equally is 100% efficient); line 3: a path (a tree: the postman walks every edge
  // twice, as efficient as uniform); line 4: disconnected.
  const fs::path f = tmp("known.txt");
  std::ofstream(f) << "# known answers\n"
                   << "4 6 1-2 1-3 1-4 2-3 2-4 3-4\n"
                   << "5 4 1-2 2-3 3-4 4-5\n"
                   << "4 2 1-2 3-4\n";
  const auto svg = tmp("eff.svg");
  const auto r = asf_test::runHost("optimal-eval " + f.string() + " --json -p " + svg.string(),
                                   false);
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["graphs"].size(), 3u);
  const auto& k4 = j["graphs"][0];
  EXPECT_EQ(k4["index"], 2);
  EXPECT_EQ(k4["connected"], true);
  for (const char* c : {"D", "A", "E"}) {
    // ||L||_p of K4 with uniform weights summing to 1: every eigenvalue is 4/6.
    EXPECT_NEAR(k4["optimum"][c].get<double>(), 4.0 / 6.0, 1e-6) << c;
    EXPECT_LE(k4["gap"][c].get<double>(), 1e-5) << c;
    EXPECT_EQ(k4["weights"][c].size(), 6u);
    EXPECT_NEAR(k4["efficiency"]["uniform"][c].get<double>(), 1.0, 1e-5) << c;
  }
  const auto& path = j["graphs"][1];
  for (const char* c : {"D", "A", "E"}) {
    EXPECT_NEAR(path["efficiency"]["cpp"][c].get<double>(),
                path["efficiency"]["uniform"][c].get<double>(), 1e-9)
        << "the postman walks each edge of a tree twice";
    EXPECT_LE(path["efficiency"]["uniform"][c].get<double>(), 1.0 + 1e-9);
  }
  // A path's D optimum puts equal weight on every edge (all spanning trees are the path).
  EXPECT_NEAR(path["efficiency"]["uniform"]["D"].get<double>(), 1.0, 1e-6);
  EXPECT_EQ(j["graphs"][2]["connected"], false);
  EXPECT_FALSE(j["graphs"][2].contains("optimum"));
  EXPECT_EQ(j["summary"]["connected"], 2);
  const double mean_e = j["summary"]["efficiency"]["uniform"]["E"]["mean"].get<double>();
  EXPECT_NEAR(mean_e,
              (k4["efficiency"]["uniform"]["E"].get<double>() +
               path["efficiency"]["uniform"]["E"].get<double>()) / 2, 1e-12)
      << "means over the connected graphs only";
  std::ifstream s(svg);
  std::string text((std::istreambuf_iterator<char>(s)), std::istreambuf_iterator<char>());
  EXPECT_TRUE(has(text, "<svg") && has(text, "E-criterion")) << "plot written";
}

TEST(OptimalEval, GraphGenFeedsOptimalEval) {
  const fs::path f = tmp("gen.txt");
  const auto g = asf_test::runHost(
      "graph-gen --family rooms --count 5 --max-nodes 20 --seed 3 -o " + f.string());
  ASSERT_EQ(g.code, 0) << g.out;
  EXPECT_TRUE(has(g.out, "5 rooms graphs")) << g.out;
  const auto r = asf_test::runHost("optimal-eval " + f.string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "5 connected graphs of 5")) << r.out;
  const auto bad = asf_test::runHost("graph-gen --max-nodes 2 -o " + f.string());
  EXPECT_EQ(bad.code, 2) << bad.out;
}
