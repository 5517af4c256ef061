// `asf optimize` through the host binary, and the g2o reader's handling of what the command
// meets in the wild (FIX lines, edge-only files, malformed lines, bad information).
#include <asf/errors.h>
#include <asf/pose_graph.h>
#include <gtest/gtest.h>

#include "test_util.h"
#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

using asf_test::has;
namespace fs = std::filesystem;

namespace {

using Result = asf_test::HostResult;

/// Runs the host; `merge` folds stderr into the output, else stderr is dropped (JSON).
Result host(const std::string& args, bool merge = true) { return asf_test::runHost(args, merge); }

fs::path tmp(const std::string& name) { return fs::temp_directory_path() / ("asf_opt_" + name); }

fs::path writeText(const std::string& name, const std::string& text) {
  const fs::path f = tmp(name);
  std::ofstream(f) << text;
  return f;
}

/// A noisy loop of n poses with chords, written as g2o; returns the graph written.
asf::PoseGraph noisyLoop(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01;
  std::vector<mrpt::poses::CPose2D> truth;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * M_PI * i / n;
    truth.emplace_back(5 * std::cos(t), 5 * std::sin(t), t + M_PI / 2);
  }
  asf::PoseGraph g;
  auto edge = [&](int i, int j) {
    asf::PoseEdge e;
    e.from = i;
    e.to = j;
    const auto m = truth[j] - truth[i];
    e.mean = mrpt::poses::CPose2D(m.x() + 0.05 * n01(rng), m.y() + 0.05 * n01(rng),
                                  m.phi() + 0.02 * n01(rng));
    e.information = Eigen::Vector3d(400, 400, 2500).asDiagonal();
    return e;
  };
  std::vector<asf::PoseEdge> odo;
  for (int i = 0; i + 1 < n; ++i) odo.push_back(edge(i, i + 1));
  g.addNode(truth[0]);
  for (const auto& e : odo) g.addNode(g.nodes.back().pose + e.mean);
  for (const auto& e : odo) g.addEdge(e);
  g.addEdge(edge(n - 1, 0));
  for (int i = 0; i + 5 < n; i += 6) g.addEdge(edge(i + 5, i));
  return g;
}

nlohmann::json optimizeJson(const std::string& args) {
  const auto r = host("optimize " + args + " --json", false);
  EXPECT_EQ(r.code, 0) << r.out;
  try {
    return nlohmann::json::parse(r.out);
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not one JSON object: " << e.what() << "\n" << r.out;
    return nlohmann::json::object();
  }
}

}  // namespace

TEST(Optimize, JsonHasTheDocumentedKeys) {
  const asf::PoseGraph g = noisyLoop(40, 1);
  const fs::path f = tmp("loop.g2o");
  asf::writeG2o(g, f.string());
  auto j = optimizeJson(f.string() + " --backend sparse_lm");
  for (const char* k : {"nodes", "edges", "initial_chi2", "final_chi2", "iterations", "time_s",
                        "marginals_time_s"})
    EXPECT_TRUE(j.contains(k)) << k << " missing in " << j.dump();
  EXPECT_EQ(j["nodes"], 40);
  EXPECT_EQ(j["edges"], g.edges.size());
  EXPECT_NEAR(j["initial_chi2"].get<double>(), g.chi2(), 1e-9 * g.chi2());
  EXPECT_LT(j["final_chi2"].get<double>(), 0.5 * g.chi2());
  EXPECT_GE(j["iterations"].get<int>(), 1);
  EXPECT_GE(j["time_s"].get<double>(), 0.0);
  EXPECT_TRUE(j["marginals_time_s"].is_null());
  EXPECT_EQ(j["backend"], "sparse_lm");

  j = optimizeJson(f.string() + " --backend sparse_lm --marginals");
  ASSERT_TRUE(j["marginals_time_s"].is_number()) << j.dump();
  EXPECT_GE(j["marginals_time_s"].get<double>(), 0.0);
  fs::remove(f);
}

TEST(Optimize, TextOutputAndTheOptimizedFile) {
  asf::PoseGraph g = noisyLoop(30, 2);
  g.fixed = {7};
  const fs::path f = tmp("fixed.g2o"), out = tmp("fixed_out.g2o");
  asf::writeG2o(g, f.string());
  fs::remove(out);
  const auto r = host("optimize " + f.string() + " -b sparse_lm --marginals -o " + out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "30 nodes, " + std::to_string(g.edges.size()) + " edges, 1 fixed"))
      << r.out;
  EXPECT_TRUE(has(r.out, "sparse_lm: chi2 ")) << r.out;
  EXPECT_TRUE(has(r.out, "marginals: all 30 node covariances in")) << r.out;
  EXPECT_TRUE(has(r.out, "wrote " + out.string())) << r.out;
  const asf::PoseGraph o = asf::readG2o(out.string());
  ASSERT_EQ(o.size(), 30u);
  EXPECT_EQ(o.fixed, std::vector<asf::NodeId>{7});
  EXPECT_EQ(o.nodes[7].pose.x(), g.nodes[7].pose.x());
  EXPECT_EQ(o.nodes[0].pose.y(), g.nodes[0].pose.y());
  EXPECT_LT(o.chi2(), 0.5 * g.chi2());
  const auto j = optimizeJson(f.string());  // sparse_lm is the default back-end
  EXPECT_NEAR(j["final_chi2"].get<double>(), o.chi2(), 1e-9 * o.chi2());
  fs::remove(f);
  fs::remove(out);
}

TEST(Optimize, EveryBackEndKeepsTheContract) {
  const asf::PoseGraph g = noisyLoop(36, 3);
  const fs::path f = tmp("backends.g2o");
  asf::writeG2o(g, f.string());
  std::map<std::string, double> final_chi2;
  for (const char* b : {"sparse_lm", "dense_gn", "mrpt_levmarq"}) {
    SCOPED_TRACE(b);
    const auto j = optimizeJson(f.string() + " --backend " + std::string(b) + " --marginals");
    EXPECT_EQ(j["backend"], b);
    EXPECT_LE(j["final_chi2"].get<double>(), j["initial_chi2"].get<double>());
    EXPECT_TRUE(j["marginals_time_s"].is_number());
    final_chi2[b] = j["final_chi2"].get<double>();
  }
  EXPECT_NEAR(final_chi2["sparse_lm"], final_chi2["dense_gn"], 1e-6 * final_chi2["dense_gn"]);
  fs::remove(f);
}

TEST(Optimize, SetReachesTheBackEndAndIsValidated) {
  const asf::PoseGraph g = noisyLoop(30, 4);
  const fs::path f = tmp("set.g2o");
  asf::writeG2o(g, f.string());
  auto j = optimizeJson(f.string() + " --set max_iterations=1 --set sparse_lm.method=gn");
  EXPECT_EQ(j["iterations"], 1);
  j = optimizeJson(f.string() + " -b dense_gn --set dense_gn.max_iterations=2");
  EXPECT_LE(j["iterations"].get<int>(), 2);

  auto r = host("optimize " + f.string() + " --set max_iteration=3");
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.out, "did you mean 'max_iterations'")) << r.out;
  r = host("optimize " + f.string() + " --set method=newton");
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.out, "method")) << r.out;
  r = host("optimize " + f.string() + " --set dense_gn.max_iterations=2");
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.out, "the back-end is 'sparse_lm'")) << r.out;
  r = host("optimize " + f.string() + " --set verbosity");
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.out, "expected key=value")) << r.out;
  // Per-step log lines go to stderr: stdout stays one JSON object.
  r = host("optimize " + f.string() + " --json --set verbosity=2", false);
  EXPECT_EQ(r.code, 0);
  EXPECT_NO_THROW(nlohmann::json::parse(r.out)) << r.out;
  r = host("optimize " + f.string() + " --set verbosity=2");
  EXPECT_TRUE(has(r.out, "[sparse_lm] sparse_lm: iteration 1: chi2")) << r.out;
  fs::remove(f);
}

TEST(Optimize, ErrorsAndUsage) {
  auto r = host("optimize");
  EXPECT_EQ(r.code, 2) << r.out;
  r = host("optimize --help");
  EXPECT_EQ(r.code, 0);
  EXPECT_TRUE(has(r.out, "--marginals")) << r.out;
  EXPECT_TRUE(has(host("--help").out, "optimize"));
  r = host("optimize /nonexistent/x.g2o");
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.out, "/nonexistent/x.g2o: cannot open")) << r.out;

  const fs::path f = writeText("ok.g2o", "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n"
                                         "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n");
  r = host("optimize " + f.string() + " --backend nosuch");
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.out, "nosuch")) << r.out;
  EXPECT_TRUE(has(r.out, "sparse_lm")) << r.out;  // the available back-ends are listed
  r = host("optimize " + f.string() + " --backend waypoints");  // a policy, not a back-end
  EXPECT_EQ(r.code, 1) << r.out;

  const fs::path bad = writeText("bad.g2o", "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n"
                                            "EDGE_SE2 0 1 1 0\n");
  r = host("optimize " + bad.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.out, bad.string() + ":3: malformed EDGE_SE2")) << r.out;
  const fs::path npd = writeText("npd.g2o", "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n"
                                            "EDGE_SE2 0 1 1 0 0 1 2 0 1 0 1\n");
  r = host("optimize " + npd.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.out, npd.string() + ":3: information matrix of edge 0 -> 1 is not positive "
                                        "definite")) << r.out;
  // A back-end's refusal names the file too (found by the mutation sweep: a coordinate of
  // 1e308 made the chi2 infinite and the message was "sparse_lm: ..." alone).
  const fs::path huge = writeText("huge.g2o", "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1e308 0 0\n"
                                              "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n");
  for (const char* backend : {"sparse_lm", "dense_gn"}) {
    r = host("optimize " + huge.string() + " --backend " + backend);
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_TRUE(has(r.out, huge.string() + ": " + backend + ": ")) << r.out;
  }
  for (const auto& p : {f, bad, npd, huge}) fs::remove(p);
}

TEST(Optimize, EdgeOnlyFilesStartFromTheOdometryChain) {
  asf::PoseGraph g = noisyLoop(24, 5);
  std::string text;
  for (const auto& e : g.edges) {
    const auto& I = e.information;
    text += "EDGE_SE2 " + std::to_string(e.from) + " " + std::to_string(e.to) + " " +
            std::to_string(e.mean.x()) + " " + std::to_string(e.mean.y()) + " " +
            std::to_string(e.mean.phi()) + " " + std::to_string(I(0, 0)) + " 0 0 " +
            std::to_string(I(1, 1)) + " 0 " + std::to_string(I(2, 2)) + "\n";
  }
  const fs::path f = writeText("edges_only.g2o", text);
  const asf::PoseGraph read = asf::readG2o(f.string());
  ASSERT_EQ(read.size(), 24u);
  EXPECT_NEAR(read.chi2(), g.chi2(), 1e-3 * g.chi2());  // same chain, printed to 6 digits
  const auto j = optimizeJson(f.string());
  EXPECT_EQ(j["nodes"], 24);
  EXPECT_LT(j["final_chi2"].get<double>(), j["initial_chi2"].get<double>());
  fs::remove(f);
}

TEST(Optimize, SharedIntelReachesTheReferenceChi2) {
  const std::string f = ASF_TEST_SHARED_DIR "/datasets/g2o/intel.g2o";
  if (!fs::exists(f)) GTEST_SKIP() << "needs " << f;
  const auto j = optimizeJson(f + " --backend sparse_lm --marginals");
  EXPECT_EQ(j["nodes"], 1728);
  EXPECT_EQ(j["edges"], 2512);
  EXPECT_LE(j["final_chi2"].get<double>(), 45.005 * 1.001);
}

// ---- the g2o reader on what the command meets ---------------------------------------

namespace {
const auto inputErrorOf = asf_test::errorOf<asf::InputError>;
}

// A SLAM run optimizes once more at its end: with optimize_every beyond the run's length the
// back-end runs only then, and the graph written (with its loop closures) is at a minimum that
// `asf optimize` cannot lower. Uses MRPT's SENA log (Debian package mrpt-common).
TEST(Optimize, SlamRunEndsWithTheGraphOptimized) {
  const std::string sena =
      "/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";
  if (!fs::exists(sena)) GTEST_SKIP() << "needs " << sena << " (Debian package mrpt-common)";
  const fs::path out = tmp("slam_sena");
  fs::remove_all(out);
  const auto run = host(std::string("run ") + ASF_TEST_SOURCE_DIR +
                        "/configs/slam_sena.ini --set pipeline.optimize_every=1000000 "
                        "--set pipeline.progress_interval=0 -o " + out.string());
  ASSERT_EQ(run.code, 0) << run.out;
  std::ifstream sf(out / "summary.json");
  const auto sum = nlohmann::json::parse(sf);
  const auto g = asf::readG2o((out / "graph.g2o").string());
  ASSERT_GT(g.size(), 50u);
  ASSERT_GT(g.edges.size(), g.size()) << "loop closures (edges beyond the chain) expected";
  const auto opt = host("optimize " + (out / "graph.g2o").string() + " --json", false);
  ASSERT_EQ(opt.code, 0) << opt.out;
  const auto j = nlohmann::json::parse(opt.out);
  const double written = j["initial_chi2"].get<double>();
  EXPECT_NEAR(written, sum["final_chi2"].get<double>(), 1e-3 * written + 1e-6);
  EXPECT_GT(j["final_chi2"].get<double>(), 0.999 * written)
      << "the run's graph was not optimized at its end";
}

TEST(G2oFormat, FixLinesAreCheckedAndKept) {
  const auto g = asf::parseG2o("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_SE2 2 2 0 0\n"
                               "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\nEDGE_SE2 1 2 1 0 0 1 0 0 1 0 1\n"
                               "FIX 1 2 # two of them\n");
  EXPECT_EQ(g.fixed, (std::vector<asf::NodeId>{1, 2}));
  EXPECT_TRUE(has(inputErrorOf([] { asf::parseG2o("VERTEX_SE2 0 0 0 0\nFIX\n", "f.g2o"); }),
                  "f.g2o:2: malformed FIX (expected: FIX id [id ...])"));
  EXPECT_TRUE(has(inputErrorOf([] { asf::parseG2o("VERTEX_SE2 0 0 0 0\nFIX zero\n", "f.g2o"); }),
                  "f.g2o:2: malformed FIX: 'zero' is not a vertex id"));
  EXPECT_TRUE(has(inputErrorOf([] { asf::parseG2o("VERTEX_SE2 0 0 0 0\nFIX 4\n", "f.g2o"); }),
                  "f.g2o:2: FIX names undefined vertex 4"));
}

TEST(G2oFormat, TrailingValuesAndNonFiniteNumbersAreErrorsComments) {
  EXPECT_TRUE(has(inputErrorOf([] { asf::parseG2o("VERTEX_SE2 0 0 0 0 7\n", "f.g2o"); }),
                  "f.g2o:1: malformed VERTEX_SE2: unexpected '7' after its values"));
  EXPECT_TRUE(has(inputErrorOf([] {
                    asf::parseG2o("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n"
                                  "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1 0.5\n",
                                  "f.g2o");
                  }),
                  "f.g2o:3: malformed EDGE_SE2: unexpected '0.5' after its values"));
  EXPECT_TRUE(has(inputErrorOf([] {
                    asf::parseG2o("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1e999 0 0\n", "f.g2o");
                  }),
                  "f.g2o:2:"));
  // Comments after the values and CRLF line ends are fine.
  const auto g = asf::parseG2o("# header\r\nVERTEX_SE2 0 0 0 0 # origin\r\nVERTEX_SE2 1 1 0 0\r\n"
                               "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\r\n");
  EXPECT_EQ(g.size(), 2u);
  EXPECT_EQ(g.edges.size(), 1u);
}

TEST(G2oFormat, EdgeOnlyFileWithAGapInTheChainIsAnError) {
  EXPECT_TRUE(has(inputErrorOf([] {
                    asf::parseG2o("EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\nEDGE_SE2 2 3 1 0 0 1 0 0 1 0 1\n",
                                  "f.g2o");
                  }),
                  "no VERTEX lines and no odometry edge 1 -> 2"));
}
