// Plots (svg_plot), run reports (run_report) and `asf experiment` (experiment.h): SVG
// well-formedness and ticks, reports from synthetic run folders, the experiment INI's
// errors, summaries against hand-computed statistics, and real experiments end to end
// (parallel runs, resume, re-running one run, Ctrl-C).
#include <asf/errors.h>
#include <asf/studies/experiment.h>
#include <asf/evaluation/run_report.h>
#include <asf/evaluation/svg_plot.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <thread>

#include "process_launcher.h"
#include "test_util.h"

extern char** environ;

using asf_test::has;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

fs::path tempDir(const std::string& name) {
  return asf_test::freshTempDir("asf_test_experiment_" + name);
}

void write(const fs::path& p, const std::string& text) { asf_test::writeFile(p, text); }

std::string read(const fs::path& p) { return asf_test::readFile(p.string()); }

std::size_t count(const std::string& hay, const std::string& needle) {
  std::size_t n = 0;
  for (auto p = hay.find(needle); p != std::string::npos; p = hay.find(needle, p + 1)) ++n;
  return n;
}

/// Checks that every element is closed in order (an XML parser's first test); returns
/// "" or what is wrong.
std::string tagBalance(const std::string& doc) {
  std::vector<std::string> stack;
  std::size_t i = 0;
  while ((i = doc.find('<', i)) != std::string::npos) {
    const std::size_t end = doc.find('>', i);
    if (end == std::string::npos) return "unterminated tag at " + std::to_string(i);
    const std::string tag = doc.substr(i + 1, end - i - 1);
    i = end + 1;
    if (tag.empty()) return "empty tag";
    if (tag[0] == '!' || tag[0] == '?') continue;  // doctype, comments, declarations
    if (tag[0] == '/') {
      const std::string name = tag.substr(1);
      if (stack.empty() || stack.back() != name)
        return "</" + name + "> closes " + (stack.empty() ? "nothing" : "<" + stack.back() + ">");
      stack.pop_back();
      continue;
    }
    if (tag.back() == '/') continue;  // self-closing
    const std::string name = tag.substr(0, tag.find_first_of(" \t\n"));
    // HTML void elements have no closing tag.
    if (name == "meta" || name == "img" || name == "br" || name == "link") continue;
    stack.push_back(name);
  }
  return stack.empty() ? "" : "<" + stack.back() + "> never closed";
}

/// The text between <svg and </svg> of the n-th inline SVG.
std::vector<std::string> svgsOf(const std::string& html) {
  std::vector<std::string> out;
  for (auto p = html.find("<svg"); p != std::string::npos; p = html.find("<svg", p + 1)) {
    const auto e = html.find("</svg>", p);
    if (e == std::string::npos) break;
    out.push_back(html.substr(p, e + 6 - p));
  }
  return out;
}

bool hasNanOrInf(const std::string& s) {  // as a value, not inside a word ("information")
  static const std::regex value("(^|[^A-Za-z])(nan|inf)([^A-Za-z]|$)", std::regex::icase);
  return std::regex_search(s, value);
}

}  // namespace

// ---------------------------------------------------------------------------------- plots

TEST(SvgPlot, NiceTicksOnKnownRanges) {
  using asf::evaluation::plot::niceTicks;
  auto near = [](const std::vector<double>& got, const std::vector<double>& want) {
    if (got.size() != want.size()) return false;
    for (std::size_t i = 0; i < got.size(); ++i)
      if (std::fabs(got[i] - want[i]) > 1e-9) return false;
    return true;
  };
  EXPECT_TRUE(near(niceTicks(0, 1), {0, 0.2, 0.4, 0.6, 0.8, 1.0}));
  EXPECT_TRUE(near(niceTicks(0, 130.2), {0, 20, 40, 60, 80, 100, 120, 140}));
  EXPECT_TRUE(near(niceTicks(0.3, 0.97), {0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0}));
  EXPECT_TRUE(near(niceTicks(-3.2, 7.9), {-4, -2, 0, 2, 4, 6, 8}));
  EXPECT_TRUE(near(niceTicks(0, 0.0042), {0, 0.001, 0.002, 0.003, 0.004, 0.005}));
  EXPECT_TRUE(near(niceTicks(0, 0), {0, 0.2, 0.4, 0.6, 0.8, 1.0}));
  // One value: a range around it that contains it; nonsense input still gives ticks.
  const auto one = niceTicks(5, 5);
  ASSERT_GE(one.size(), 2u);
  EXPECT_LT(one.front(), 5);
  EXPECT_GT(one.back(), 5);
  const auto bad = niceTicks(NAN, INFINITY);
  ASSERT_GE(bad.size(), 2u);
  for (double t : bad) EXPECT_TRUE(std::isfinite(t));
}

TEST(SvgPlot, LinesBandsGapsAndLegend) {
  asf::evaluation::plot::Figure f;
  f.title = "Coverage <vs> distance";
  f.x_label = "distance (m)";
  f.y_label = "coverage (%)";
  asf::evaluation::plot::Series a =
      asf::evaluation::plot::series("tigre & co", {0, 1, 2, 3, 4, 5}, {0, 10, NAN, 30, 40, 50});
  a.y_low = {0, 5, NAN, 25, 35, 45};
  a.y_high = {0, 15, NAN, 35, 45, 55};
  asf::evaluation::plot::Series b =
      asf::evaluation::plot::series("nearest_frontier", {0, 2.5, 5}, {0, 20, INFINITY});
  b.dashed = true;
  f.series = {a, b};
  const std::string s = asf::evaluation::plot::svg(f);
  EXPECT_EQ(s.rfind("<svg", 0), 0u) << s.substr(0, 80);
  EXPECT_TRUE(has(s, "xmlns=\"http://www.w3.org/2000/svg\""));
  EXPECT_EQ(tagBalance(s), "") << s;
  EXPECT_FALSE(hasNanOrInf(s)) << s;
  EXPECT_TRUE(has(s, "tigre &amp; co")) << "labels are escaped";
  EXPECT_TRUE(has(s, "nearest_frontier"));
  EXPECT_TRUE(has(s, "Coverage &lt;vs&gt; distance"));
  EXPECT_TRUE(has(s, "distance (m)"));
  EXPECT_TRUE(has(s, "stroke-dasharray"));
  // The NaN splits series a into two pieces (two moveto), and its band into two polygons.
  const auto p = s.find("<path");
  ASSERT_NE(p, std::string::npos);
  const std::string first_path = s.substr(p, s.find("/>", p) - p);
  EXPECT_EQ(count(first_path, "M"), 2u) << first_path;
  EXPECT_EQ(count(s, "<polygon"), 2u);
  // The y axis reaches the band's top (55) with nice ticks: 0..60.
  EXPECT_TRUE(has(s, ">60</text>")) << s;
  EXPECT_TRUE(has(s, ">0</text>"));
}

TEST(SvgPlot, NoDataIsStillAValidSvg) {
  asf::evaluation::plot::Figure f;
  f.title = "Empty";
  EXPECT_TRUE(has(asf::evaluation::plot::svg(f), "no data"));
  f.series = {asf::evaluation::plot::series("only gaps", {NAN, 1}, {1, NAN})};
  const std::string s = asf::evaluation::plot::svg(f);
  EXPECT_TRUE(has(s, "no data"));
  EXPECT_TRUE(has(s, "only gaps"));
  EXPECT_EQ(tagBalance(s), "") << s;
  EXPECT_FALSE(hasNanOrInf(s)) << s;

  const fs::path d = tempDir("svg");
  asf::evaluation::plot::writeSvg(f, (d / "x.svg").string());
  EXPECT_EQ(read(d / "x.svg"), s);
  const std::string err = asf_test::errorOf<asf::Error>(
      [&] { asf::evaluation::plot::writeSvg(f, (d / "no_such_dir" / "x.svg").string()); });
  EXPECT_TRUE(has(err, "no_such_dir/x.svg")) << err;
}

// ------------------------------------------------------------------------------ run report

namespace {

// "Many hands make light work." and its base64 (RFC 4648 style, a length divisible by 3).
const char* kFakePng = "Many hands make light work.";
const char* kFakePngBase64 = "TWFueSBoYW5kcyBtYWtlIGxpZ2h0IHdvcmsu";

const char* kTimeseriesHeader =
    "step,time_s,distance_m,coverage,explored_area_m2,pose_error_m,loop_closures,nodes,edges,"
    "regions,decisions,frontend_ms,backend_ms,map_ms,segment_ms,policy_ms,map_information_bits\n";

}  // namespace

TEST(RunReport, EmbedsImagesAndDrawsPlots) {
  const fs::path d = tempDir("report");
  write(d / "summary.json",
        R"({"policy": "tigre", "seed": 3, "distance_m": 130.25, "coverage": 0.991,
            "mean_pose_error_m": 0.12, "final_pose_error_m": null, "finished": true,
            "stop_reason": "policy done", "plugins": {"source": "sim2d"}})");
  write(d / "timeseries.csv", std::string(kTimeseriesHeader) +
                                  "1,0,0,0.1,1,0,0,1,0,1,1,1,2,3,4,5\n"
                                  "2,1,10,0.5,5,0.2,0,2,1,1,1,1,2,3,4,5\n"
                                  "3,2,20,,9,,1,3,2,2,2,1,2,3,4,5\n"
                                  "4,3,30,0.991,12,0.4,1,4,3,2,3,1,2,3,4,5\n");
  write(d / "map.png", kFakePng);
  write(d / "decisions.csv",
        "step,time_s,previous_status,decision,goal_x,goal_y,reason\n"
        "1,0,idle,goto,1.5,2,nearest frontier\n"
        "5,2,arrived,goto,0.5,1,the next room\n"
        "9,4,arrived,done,,,no frontier left\n");
  fs::create_directories(d / "timeline");  // decision 1 has no picture (no map yet)
  write(d / "timeline/0002.png", kFakePng);
  write(d / "timeline/0003.png", kFakePng);
  const std::string path = asf::evaluation::writeRunReport(d.string());
  EXPECT_EQ(path, (d / "report.html").string());
  const std::string html = read(path);
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_EQ(tagBalance(html), "");
  EXPECT_TRUE(has(html, std::string("data:image/png;base64,") + kFakePngBase64));
  EXPECT_TRUE(has(html, "regions.png: missing")) << "the missing image is noted";
  const auto svgs = svgsOf(html);
  ASSERT_EQ(svgs.size(), 4u) << "coverage, pose error, error/distance, compute time";
  for (const auto& s : svgs) {
    EXPECT_FALSE(has(s, "no data")) << s;
    EXPECT_FALSE(hasNanOrInf(s)) << s;
  }
  EXPECT_TRUE(has(html, "Coverage"));
  EXPECT_TRUE(has(html, "Pose error per distance"));
  for (const char* stage : {"frontend", "backend", "map", "segment", "policy"})
    EXPECT_TRUE(has(svgs[3], ">" + std::string(stage) + "</text>")) << stage;
  EXPECT_TRUE(has(html, "99.100 %")) << "coverage shown in percent";
  EXPECT_TRUE(has(html, "130.250"));
  EXPECT_TRUE(has(html, "unknown")) << "null final pose error";
  EXPECT_TRUE(has(html, "no frontier left"));
  EXPECT_TRUE(has(html, "(1.5, 2)"));
  EXPECT_TRUE(has(html, "source: sim2d"));
  EXPECT_FALSE(fs::exists(d / "report.html.tmp"));
  // The timeline: both pictures, a slider over them, each decision's caption.
  EXPECT_TRUE(has(html, "<h2>Timeline</h2>")) << html;
  EXPECT_TRUE(has(html, "type=\"range\" min=\"0\" max=\"1\"")) << html;
  const std::string url = std::string("data:image/png;base64,") + kFakePngBase64;
  EXPECT_NE(html.find(url, html.find(url, html.find("<h2>Timeline</h2>")) + 1), std::string::npos)
      << "the two frames";
  EXPECT_TRUE(has(html, "decision 2 of 3 · step 5 · t = 2 s · goto (0.5, 1) · the next room"))
      << html;
  EXPECT_TRUE(has(html, "decision 3 of 3 · step 9 · t = 4 s · done · no frontier left")) << html;
}

TEST(RunReport, MapEntropyOverTheFinalGrid) {
  // 1000 cells; the map says 0, 200 then 600 bits: entropy 1.0, 0.8, 0.4 kbit. Without
  // map_cells (a run from before the column) there is no such plot.
  const fs::path d = tempDir("report_entropy");
  write(d / "summary.json", R"({"policy": "tigre", "distance_m": 20, "map_cells": 1000})");
  write(d / "timeseries.csv", std::string(kTimeseriesHeader) +
                                  "1,0,0,0.1,1,0,0,1,0,1,1,1,2,3,4,5,0\n"
                                  "2,1,10,0.5,5,0.2,0,2,1,1,1,1,2,3,4,5,200\n"
                                  "3,2,20,0.9,9,0.3,1,3,2,2,2,1,2,3,4,5,600\n");
  std::string html = read(asf::evaluation::writeRunReport(d.string()));
  auto svgs = svgsOf(html);
  ASSERT_EQ(svgs.size(), 5u);
  EXPECT_TRUE(has(svgs[3], "Map entropy over the final grid")) << svgs[3];
  EXPECT_TRUE(has(svgs[3], "entropy (kbit)"));
  EXPECT_FALSE(hasNanOrInf(svgs[3])) << svgs[3];
  write(d / "summary.json", R"({"policy": "tigre", "distance_m": 20})");
  html = read(asf::evaluation::writeRunReport(d.string()));
  EXPECT_EQ(svgsOf(html).size(), 4u);
}

TEST(RunReport, TimelineOfALongRunIsThinnedEvenly) {
  // 400 decisions, a picture each: 150 of them embedded, the first and the last among them,
  // each captioned with its own decision.
  const fs::path d = tempDir("report_long_timeline");
  fs::create_directories(d / "timeline");
  std::string csv = "step,time_s,previous_status,decision,goal_x,goal_y,reason\n";
  for (int n = 1; n <= 400; ++n) {
    csv += std::to_string(10 * n) + "," + std::to_string(n) + ",arrived,goto,1,2,goal " +
           std::to_string(n) + "\n";
    char name[32];
    std::snprintf(name, sizeof name, "timeline/%04d.png", n);
    write(d / name, kFakePng);
  }
  write(d / "decisions.csv", csv);
  const std::string html = read(asf::evaluation::writeRunReport(d.string()));
  EXPECT_TRUE(has(html, "type=\"range\" min=\"0\" max=\"149\"")) << "150 pictures";
  EXPECT_TRUE(has(html, "decision 1 of 400 · step 10 · t = 1 s · goto (1, 2) · goal 1\""));
  EXPECT_TRUE(has(html, "decision 400 of 400 · step 4000 · t = 400 s · goto (1, 2) · goal 400"));
  EXPECT_FALSE(has(html, "decision 2 of 400")) << "thinned";
  EXPECT_EQ(tagBalance(html), "");
}

TEST(RunReport, MissingFilesAreNotedNotFatal) {
  const fs::path d = tempDir("report_empty");
  const std::string html = read(asf::evaluation::writeRunReport(d.string()));
  EXPECT_EQ(tagBalance(html), "");
  for (const char* f : {"summary.json: missing", "timeseries.csv: missing", "map.png: missing",
                        "decisions.csv: missing"})
    EXPECT_TRUE(has(html, f)) << f;

  // Broken files too: invalid JSON, a CSV without the columns, an interrupted run.
  write(d / "summary.json", "{\"distance_m\": 3,");
  write(d / "timeseries.csv", "a,b\n1,2\n");
  const std::string html2 = read(asf::evaluation::writeRunReport(d.string()));
  EXPECT_TRUE(has(html2, "summary.json: invalid JSON"));
  EXPECT_TRUE(has(html2, "no distance_m column"));

  const std::string err = asf_test::errorOf<asf::Error>(
      [&] { asf::evaluation::writeRunReport((d / "no" / "such" / "dir").string()); });
  EXPECT_TRUE(has(err, "report.html")) << err;
}

// --------------------------------------------------------------------- experiment config

TEST(ExperimentConfig, ReadsKeysAndResolvesPaths) {
  const fs::path d = tempDir("config");
  write(d / "pipe.ini", "[pipeline]\n");
  write(d / "exp.ini",
        "; comparison\n[experiment]\npipeline = pipe.ini\npolicies = a, b ,c\n"
        "replications = 3\nout = res\noverrides = map.resolution=0.1; pipeline.max_steps=5\n");
  const asf::studies::ExperimentConfig c =
      asf::studies::readExperimentConfig((d / "exp.ini").string());
  EXPECT_EQ(c.pipeline_ini, (d / "pipe.ini").string());
  EXPECT_EQ(c.policies, (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_EQ(c.replications, 3);
  EXPECT_EQ(c.first_seed, 1);
  EXPECT_EQ(c.jobs, 0);
  EXPECT_EQ(c.out_dir, (d / "res").string()) << "relative to the INI";
  EXPECT_EQ(c.overrides, (std::vector<std::string>{"map.resolution=0.1", "pipeline.max_steps=5"}));

  write(d / "exp2.ini", "[experiment]\npipeline = pipe.ini\npolicies = a\n");
  const asf::studies::ExperimentConfig c2 =
      asf::studies::readExperimentConfig((d / "exp2.ini").string());
  EXPECT_EQ(c2.replications, 10);
  EXPECT_EQ(c2.out_dir, "results/exp2");
  std::size_t n = 0;
  asf::studies::experimentKeys(n);
  EXPECT_EQ(n, 7u);
}

TEST(ExperimentConfig, ErrorsNameFileLineAndKey) {
  const fs::path d = tempDir("config_errors");
  write(d / "pipe.ini", "[pipeline]\n");
  auto err = [&](const std::string& text) {
    write(d / "exp.ini", text);
    return asf_test::errorOf<asf::ConfigError>(
        [&] { asf::studies::readExperimentConfig((d / "exp.ini").string()); });
  };
  const std::string f = (d / "exp.ini").string();
  std::string e = err("[experiment]\npipeline = pipe.ini\npolicies = a\nreplicatons = 3\n");
  EXPECT_TRUE(has(e, f + ":4: [experiment] unknown key 'replicatons' (did you mean "
                         "'replications'?)"))
      << e;
  e = err("[experiment]\npolicies = a\n");
  EXPECT_TRUE(has(e, "missing required key 'pipeline'")) << e;
  e = err("[experiment]\npipeline = nope.ini\npolicies = a\n");
  EXPECT_TRUE(has(e, f + ":2: [experiment] pipeline")) << e;
  EXPECT_TRUE(has(e, "no such file")) << e;
  e = err("[experiment]\npipeline = pipe.ini\npolicies = a\n\nreplications = 0\n");
  EXPECT_TRUE(has(e, f + ":5: [experiment] replications")) << e;
  e = err("[experiment]\npipeline = pipe.ini\npolicies = a, ,a\n");
  EXPECT_TRUE(has(e, f + ":3: [experiment] policies")) << e;
  EXPECT_TRUE(has(e, "'a' appears twice")) << e;
  e = err("[experiment]\npipeline = pipe.ini\npolicies = a\noverrides = map.resolution\n");
  EXPECT_TRUE(has(e, f + ":4: [experiment] overrides")) << e;
  EXPECT_TRUE(has(e, "'map.resolution' is not section.key=value")) << e;
  e = err("[experiment]\npipeline = pipe.ini\npolicies = a\n[experimnt]\njobs = 2\n");
  EXPECT_TRUE(has(e, f + ":4: unknown section [experimnt]")) << e;
  EXPECT_TRUE(has(e, "did you mean [experiment]")) << e;
}

// ------------------------------------------------------------------------------ summaries

TEST(ExperimentSummary, StatisticsCurvesAndStatusesFromRunFolders) {
  const fs::path d = tempDir("summary");
  write(d / "pipe.ini", "[pipeline]\n");
  asf::studies::ExperimentConfig cfg;
  cfg.pipeline_ini = (d / "pipe.ini").string();
  cfg.policies = {"alpha", "beta"};
  cfg.replications = 4;
  cfg.first_seed = 7;
  cfg.out_dir = (d / "out").string();
  auto run = [&](const std::string& p, int seed, double dist, const char* cov,
                 const std::string& stop) {
    write(d / "out" / p / ("seed_" + std::to_string(seed)) / "summary.json",
          "{\"distance_m\": " + std::to_string(dist) + ", \"coverage\": " + cov +
              ", \"mean_pose_error_m\": 0.5, \"ate_rmse_m\": " + std::to_string(dist / 1000) +
              ", \"loop_closures\": 2, \"wall_time_s\": 1.5, "
              "\"stop_reason\": \"" +
              stop + "\"}");
  };
  // alpha: 10, 20, 60 finished; one interrupted (ignored). beta: one finished, one error,
  // one invalid file, one missing.
  run("alpha", 7, 10, "0.5", "policy done");
  run("alpha", 8, 20, "null", "distance budget spent");
  run("alpha", 9, 60, "0.9", "policy done");
  run("alpha", 10, 1000, "0.1", "interrupted");
  run("beta", 7, 5, "0.25", "policy done");
  run("beta", 8, 5, "0.25", "error: the planner failed");
  write(d / "out/beta/seed_9/summary.json", "{ not json");
  // Curves: alpha seed 7 and 9 have time series, the others none.
  write(d / "out/alpha/seed_7/timeseries.csv", std::string(kTimeseriesHeader) +
                                                   "1,0,0,0,0,0,0,1,0,1,1,0,0,0,0,0,0\n"
                                                   "2,1,10,0.5,0,1,0,1,0,1,1,0,0,0,0,0,500\n");
  write(d / "out/alpha/seed_9/timeseries.csv", std::string(kTimeseriesHeader) +
                                                   "1,0,0,0,0,0,0,1,0,1,1,0,0,0,0,0,0\n"
                                                   "2,1,60,0.9,0,3,0,1,0,1,1,0,0,0,0,0,900\n");
  write(d / "out/alpha/seed_7/map.png", kFakePng);

  const std::string md = asf::studies::summarizeExperiment(cfg);
  const json j = json::parse(read(d / "out/summary.json"));
  const json& a = j["policies"]["alpha"];
  EXPECT_EQ(a["finished"], 3);
  EXPECT_EQ(a["total"], 4);
  EXPECT_DOUBLE_EQ(a["distance_m"]["mean"].get<double>(), 30.0);
  // Sample std of 10, 20, 60: sqrt(((20)^2 + 10^2 + 30^2) / 2) = sqrt(700).
  EXPECT_NEAR(a["distance_m"]["std"].get<double>(), std::sqrt(700.0), 1e-9);
  EXPECT_EQ(a["distance_m"]["n"], 3);
  EXPECT_DOUBLE_EQ(a["coverage"]["mean"].get<double>(), 0.7) << "null coverage skipped";
  EXPECT_EQ(a["coverage"]["n"], 2);
  EXPECT_NEAR(a["ate_rmse_m"]["mean"].get<double>(), 0.030, 1e-12) << "keyframe ATE column";
  EXPECT_EQ(a["ate_rmse_m"]["n"], 3);
  EXPECT_TRUE(a["final_pose_error_m"]["mean"].is_null());
  EXPECT_EQ(a["final_pose_error_m"]["n"], 0);
  const json& b = j["policies"]["beta"];
  EXPECT_EQ(b["finished"], 1);
  EXPECT_DOUBLE_EQ(b["distance_m"]["mean"].get<double>(), 5.0);
  EXPECT_DOUBLE_EQ(b["distance_m"]["std"].get<double>(), 0.0);

  ASSERT_EQ(j["runs"].size(), 8u);
  std::map<std::string, std::string> status;
  for (const auto& r : j["runs"])
    status[r["policy"].get<std::string>() + std::to_string(r["seed"].get<int>())] =
        r["status"].get<std::string>();
  EXPECT_EQ(status["alpha7"], "finished");
  EXPECT_EQ(status["alpha10"], "interrupted");
  EXPECT_EQ(status["beta8"], "error: the planner failed");
  EXPECT_TRUE(has(status["beta9"], "invalid summary.json")) << status["beta9"];
  EXPECT_EQ(status["beta10"], "missing summary.json");

  // Markdown: a row per policy with mean ± std, and the runs that do not count.
  EXPECT_TRUE(has(md, "| alpha | 3/4 | 30.00 ± 26.46 | 70.0 ± 28.3 (n=2) |")) << md;
  EXPECT_TRUE(has(md, "| beta | 1/4 | 5.00 ± 0.00 |")) << md;
  // The coverage milestones and the RPE beside the ATE (issue 23's standard metrics).
  EXPECT_TRUE(has(md, "| coverage (%) | distance to 90 % (m) | distance to 99 % (m) |")) << md;
  EXPECT_TRUE(has(md, "| keyframe ATE (m) | keyframe RPE (m) |")) << md;
  EXPECT_TRUE(has(md, "- beta seed 10: missing summary.json")) << md;
  EXPECT_EQ(read(d / "out/summary.md"), md);
  const std::string csv = read(d / "out/summary.csv");
  EXPECT_TRUE(has(csv, "policy,finished,total,distance_m_mean,distance_m_std,distance_m_n"));
  EXPECT_TRUE(has(csv, "alpha,3,4,30,26.45751311,3,0.7,")) << csv;

  // Curves: alpha's mean over its two time series; coverage of the shorter run is held
  // after it ended, so at 60 m the mean is (50 + 90) / 2 = 70 %.
  const std::string cov = read(d / "out/coverage_vs_distance.svg");
  EXPECT_EQ(tagBalance(cov), "");
  EXPECT_FALSE(hasNanOrInf(cov));
  EXPECT_TRUE(has(cov, "alpha (2 runs)")) << cov;
  EXPECT_TRUE(has(cov, "beta (0 runs)")) << cov;
  EXPECT_TRUE(has(cov, "<polygon")) << "the std band";
  const std::string epd = read(d / "out/error_per_distance_vs_distance.svg");
  EXPECT_EQ(tagBalance(epd), "");
  EXPECT_TRUE(has(epd, "alpha (2 runs)"));
  EXPECT_FALSE(hasNanOrInf(epd));
  const std::string info = read(d / "out/map_information_vs_distance.svg");
  EXPECT_EQ(tagBalance(info), "");
  EXPECT_TRUE(has(info, "alpha (2 runs)")) << info;
  EXPECT_FALSE(hasNanOrInf(info));

  const std::string html = read(d / "out/report.html");
  EXPECT_EQ(tagBalance(html), "");
  EXPECT_EQ(svgsOf(html).size(), 3u) << "coverage, error per distance, map information";
  EXPECT_TRUE(has(html, std::string("base64,") + kFakePngBase64)) << "alpha's first map";
  EXPECT_TRUE(has(html, "beta: no run has a map.png"));
  EXPECT_TRUE(has(html, "missing summary.json"));
  EXPECT_TRUE(has(html, "2 finished run(s) without a usable timeseries.csv")) << "alpha 8, beta 7";
}

// ----------------------------------------------------------------------- end to end (host)

namespace {

/// A short waypoints route in the two-rooms world: a run takes well under a second.
void writePipeline(const fs::path& dir, const std::string& waypoints = "1 0; 1 1; 0 0",
                   const std::string& extra = "") {
  write(dir / "pipe.ini",
        "[pipeline]\nsource = segment_world\nfrontend = odometry\nsegmenter = free_components\n"
        "policy = waypoints\nseed = 1\n\n[segment_world]\nworld = two_rooms\nstart_x = 1.0\n"
        "start_y = 1.0\n\n[waypoints]\nwaypoints = " +
            waypoints + "\ntolerance = 0.25\n" + extra);
}

json readJson(const fs::path& p) { return json::parse(read(p)); }

}  // namespace

namespace {

/// A ProcessRunner without processes: a run "lasts" a number of polls, then writes the
/// summary.json its policy is scripted to write and exits as scripted. Records the
/// arguments, the most runs alive at once and the interrupts.
class ScriptedLauncher : public asf::studies::ProcessRunner {
 public:
  struct Script {
    int polls = 2;
    std::string stop_reason = "policy done: test";  ///< empty: no summary.json
    Exit exit;
  };
  std::map<std::string, Script> by_policy;
  std::vector<std::vector<std::string>> started;
  std::size_t max_alive = 0, interrupts = 0;
  bool refuse_start = false;

  long start(const std::vector<std::string>& argv, const Redirect& io,
             std::string& error) override {
    if (refuse_start) {
      error = "test: cannot start";
      return -1;
    }
    EXPECT_EQ(argv.at(0), "asf");  // the host's own binary
    EXPECT_TRUE(io.err.empty());   // stderr with stdout, in run.log
    const std::vector<std::string> args(argv.begin() + 1, argv.end());
    std::ofstream(io.out) << "scripted run\n";
    Alive a;
    a.dir = args.at(3);
    a.policy = args.at(5).substr(std::string("pipeline.policy=").size());
    a.polls_left = by_policy[a.policy].polls;
    alive_[next_] = a;
    started.push_back(args);
    max_alive = std::max(max_alive, alive_.size());
    return next_++;
  }
  std::optional<Exit> poll(long h) override {
    Alive& a = alive_.at(h);
    if (a.polls_left-- > 0) return std::nullopt;
    const Script& sc = by_policy[a.policy];
    if (!sc.stop_reason.empty())
      std::ofstream(fs::path(a.dir) / "summary.json")
          << json{{"stop_reason", sc.stop_reason}, {"distance_m", 2.5}}.dump();
    alive_.erase(h);
    return sc.exit;
  }
  void interrupt(long) override { ++interrupts; }
  void kill(long) override {}
  int run(const std::vector<std::string>&, std::string& output) override {
    output = "scripted: runs only asf run";
    return -1;
  }

 private:
  struct Alive {
    std::string dir, policy;
    int polls_left = 0;
  };
  std::map<long, Alive> alive_;
  long next_ = 7;
};

}  // namespace

TEST(ExperimentScheduler, JobsLimitSkipsExitCodesAndArguments) {
  const fs::path d = tempDir("scheduler");
  write(d / "pipe.ini", "[pipeline]\n");
  write(d / "exp.ini",
        "[experiment]\npipeline = pipe.ini\npolicies = good, crash, broken\nreplications = 2\n"
        "first_seed = 5\njobs = 2\nout = out\noverrides = map.resolution=0.1\n");
  const asf::studies::ExperimentConfig cfg =
      asf::studies::readExperimentConfig((d / "exp.ini").string());
  // good seed 5 finished in an earlier invocation: skipped, not started again.
  write(d / "out/good/seed_5/summary.json", R"({"stop_reason": "source ended"})");
  ScriptedLauncher L;
  L.by_policy["crash"].exit = {asf::studies::ProcessRunner::Exit::How::Signaled, 11, ""};
  L.by_policy["crash"].stop_reason = "";
  L.by_policy["broken"].exit = {asf::studies::ProcessRunner::Exit::How::Exited, 1, ""};
  L.by_policy["broken"].stop_reason = "error: scripted";
  std::vector<std::string> lines;
  const auto runs =
      asf::studies::runExperiment(cfg, L, [&](const std::string& l) { lines.push_back(l); });
  std::string all;
  for (const auto& l : lines) all += l + "\n";
  ASSERT_EQ(runs.size(), 6u);
  EXPECT_EQ(L.started.size(), 5u) << all;
  EXPECT_EQ(L.max_alive, 2u) << "jobs = 2";
  EXPECT_EQ(L.interrupts, 0u);
  // Seeds outer, policies inner.
  EXPECT_EQ(runs[0].policy, "good");
  EXPECT_EQ(runs[1].policy, "crash");
  EXPECT_EQ(runs[3].seed, 6);
  EXPECT_TRUE(runs[0].skipped);
  EXPECT_FALSE(runs[3].skipped);
  EXPECT_EQ(runs[3].exit_code, 0);
  EXPECT_EQ(runs[1].exit_code, 128 + 11);
  EXPECT_EQ(runs[2].exit_code, 1);
  EXPECT_TRUE(has(all, "[1/6] good seed 5: already finished, skipped")) << all;
  EXPECT_TRUE(has(all, "crash seed 5: killed by signal 11")) << all;
  EXPECT_TRUE(has(all, "broken seed 5: failed (exit 1, error: scripted)")) << all;
  EXPECT_TRUE(has(all, "good seed 6: finished in")) << all;
  EXPECT_TRUE(has(all, "[6/6] ")) << all;
  const std::vector<std::string> expected{
      "run",   cfg.pipeline_ini,        "--out", (fs::path(cfg.out_dir) / "crash/seed_5").string(),
      "--set", "pipeline.policy=crash", "--set", "pipeline.seed=5",
      "--set", "map.resolution=0.1",    "-v",    "WARN"};
  EXPECT_EQ(L.started[0], expected);
  const json j = readJson(d / "out/summary.json");
  EXPECT_EQ(j["policies"]["good"]["finished"], 2);
  EXPECT_EQ(j["policies"]["crash"]["finished"], 0);
  EXPECT_EQ(j["policies"]["broken"]["finished"], 0);
}

TEST(ExperimentScheduler, StopInterruptsRunningRunsAndStartsNoMore) {
  const fs::path d = tempDir("scheduler_stop");
  write(d / "pipe.ini", "[pipeline]\n");
  write(d / "exp.ini",
        "[experiment]\npipeline = pipe.ini\npolicies = slow\nreplications = 4\njobs = 2\n"
        "out = out\n");
  const asf::studies::ExperimentConfig cfg =
      asf::studies::readExperimentConfig((d / "exp.ini").string());
  ScriptedLauncher L;
  L.by_policy["slow"].polls = 3;
  L.by_policy["slow"].stop_reason = "interrupted";
  L.by_policy["slow"].exit = {asf::studies::ProcessRunner::Exit::How::Exited, 130, ""};
  std::atomic<bool> stop{false};
  std::vector<std::string> lines;
  const auto runs = asf::studies::runExperiment(
      cfg, L,
      [&](const std::string& l) {
        lines.push_back(l);
        if (has(l, "started slow seed 2")) stop = true;  // Ctrl-C once two runs are going
      },
      &stop);
  EXPECT_EQ(L.started.size(), 2u) << "no run starts after the stop";
  EXPECT_EQ(L.interrupts, 2u) << "each running run is interrupted once";
  EXPECT_EQ(runs[0].exit_code, 130);
  EXPECT_EQ(runs[2].exit_code, 0) << "never started";
  EXPECT_TRUE(fs::exists(d / "out/summary.md")) << "what exists is summarized";

  L.refuse_start = true;
  stop = false;
  const auto failed = asf::studies::runExperiment(cfg, L, nullptr, &stop);
  EXPECT_EQ(failed[0].exit_code, 127) << "a run that cannot start";
}

TEST(ExperimentHost, RunsInParallelSummarizesAndResumes) {
  const fs::path d = tempDir("e2e");
  writePipeline(d);
  write(d / "exp.ini",
        "[experiment]\npipeline = pipe.ini\npolicies = waypoints\nreplications = 2\n"
        "first_seed = 5\njobs = 2\nout = out\noverrides = segment_world.speed=0.6\n");
  auto r = asf_test::runHost("experiment " + (d / "exp.ini").string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(count(r.out, "started waypoints seed"), 2u) << r.out;
  EXPECT_TRUE(has(r.out, "[2/2] waypoints seed")) << r.out;
  EXPECT_TRUE(has(r.out, ": finished in ")) << r.out;
  EXPECT_TRUE(has(r.out, "| policy | finished |")) << r.out;
  EXPECT_TRUE(has(r.out, "| waypoints | 2/2 |")) << r.out;
  EXPECT_TRUE(has(r.out, "report in " + (d / "out/report.html").string())) << r.out;

  const fs::path s5 = d / "out/waypoints/seed_5", s6 = d / "out/waypoints/seed_6";
  for (const auto& s : {s5, s6}) {
    ASSERT_TRUE(fs::exists(s / "summary.json")) << s;
    EXPECT_TRUE(fs::exists(s / "run.log"));
    // The run got the experiment's policy, seed and overrides.
    const std::string ini = read(s / "config.ini");
    EXPECT_TRUE(has(ini, "speed = 0.6")) << ini;
  }
  EXPECT_TRUE(has(read(s5 / "config.ini"), "seed = 5"));
  EXPECT_TRUE(has(read(s6 / "config.ini"), "seed = 6"));

  // The summary's numbers are the means of the runs' own summary.json values.
  const json j = readJson(d / "out/summary.json");
  const json a = readJson(s5 / "summary.json"), b = readJson(s6 / "summary.json");
  for (const char* k : {"distance_m", "mean_pose_error_m", "final_pose_error_m", "wall_time_s",
                        "loop_closures", "decision_ms_mean"}) {
    if (!a.contains(k) || !a[k].is_number() || !b[k].is_number()) continue;
    const double want = (a[k].get<double>() + b[k].get<double>()) / 2;
    EXPECT_NEAR(j["policies"]["waypoints"][k]["mean"].get<double>(), want,
                1e-12 * std::max(1.0, std::fabs(want)))
        << k;
    EXPECT_EQ(j["policies"]["waypoints"][k]["n"], 2) << k;
  }
  EXPECT_EQ(j["policies"]["waypoints"]["finished"], 2);
  ASSERT_EQ(j["runs"].size(), 2u);
  for (const char* f :
       {"summary.md", "summary.csv", "coverage_vs_distance.svg",
        "error_per_distance_vs_distance.svg", "map_information_vs_distance.svg", "report.html"})
    EXPECT_TRUE(fs::exists(d / "out" / f)) << f;

  // Again: nothing to run.
  const auto t5 = fs::last_write_time(s5 / "summary.json");
  const auto t6 = fs::last_write_time(s6 / "summary.json");
  r = asf_test::runHost("experiment " + (d / "exp.ini").string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(count(r.out, "already finished, skipped"), 2u) << r.out;
  EXPECT_FALSE(has(r.out, "started")) << r.out;
  EXPECT_EQ(fs::last_write_time(s5 / "summary.json"), t5);
  EXPECT_EQ(fs::last_write_time(s6 / "summary.json"), t6);

  // Without one run's summary.json only that run runs again.
  fs::remove(s6 / "summary.json");
  r = asf_test::runHost("experiment " + (d / "exp.ini").string() + " --jobs 1");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(count(r.out, "started"), 1u) << r.out;
  EXPECT_TRUE(has(r.out, "started waypoints seed 6")) << r.out;
  EXPECT_TRUE(has(r.out, "waypoints seed 5: already finished, skipped")) << r.out;
  EXPECT_EQ(fs::last_write_time(s5 / "summary.json"), t5);
  EXPECT_TRUE(fs::exists(s6 / "summary.json"));

  // An interrupted run counts as unfinished and runs again.
  json interrupted = readJson(s5 / "summary.json");
  interrupted["stop_reason"] = "interrupted";
  write(s5 / "summary.json", interrupted.dump());
  EXPECT_FALSE(asf::studies::runFinished(s5.string()));
  r = asf_test::runHost("experiment " + (d / "exp.ini").string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "started waypoints seed 5")) << r.out;
  EXPECT_TRUE(asf::studies::runFinished(s5.string()));

  // --summarize-only runs nothing and prints the table of what exists.
  r = asf_test::runHost("experiment " + (d / "exp.ini").string() + " --summarize-only");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_FALSE(has(r.out, "started"));
  EXPECT_TRUE(has(r.out, "| waypoints | 2/2 |")) << r.out;
}

TEST(ExperimentHost, BadPolicyOrOverrideFailsBeforeAnyRun) {
  const fs::path d = tempDir("e2e_bad");
  writePipeline(d);
  write(d / "exp.ini",
        "[experiment]\npipeline = pipe.ini\npolicies = waypoints, no_such_policy\n"
        "replications = 1\nout = out\n");
  auto r = asf_test::runHost("experiment " + (d / "exp.ini").string());
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_TRUE(has(r.out, "no_such_policy")) << r.out;
  EXPECT_FALSE(fs::exists(d / "out/waypoints")) << "nothing ran";

  write(d / "exp.ini",
        "[experiment]\npipeline = pipe.ini\npolicies = waypoints\nreplications = 1\nout = out\n"
        "overrides = segment_world.sped=1\n");
  r = asf_test::runHost("experiment " + (d / "exp.ini").string());
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_TRUE(has(r.out, "unknown key 'sped'")) << r.out;
  EXPECT_TRUE(has(r.out, "did you mean 'speed'")) << r.out;

  r = asf_test::runHost("experiment " + (d / "exp.ini").string() + " --jobs -1");
  EXPECT_NE(r.code, 0) << r.out;
}

TEST(ExperimentHost, FailedRunIsReportedAndNotCounted) {
  const fs::path d = tempDir("e2e_fail");
  writePipeline(d);
  write(d / "exp.ini",
        "[experiment]\npipeline = pipe.ini\npolicies = waypoints\nreplications = 1\nout = out\n");
  // The asf binary as the experiment's child, with an argument it rejects: a failed run.
  asf::studies::ExperimentConfig cfg = asf::studies::readExperimentConfig((d / "exp.ini").string());
  cfg.overrides = {"pipeline.no_such_key=1"};
  std::vector<std::string> lines;
  asf::app::ProcessLauncher launcher(ASF_TEST_BINARY_DIR "/bin/asf");
  const auto runs =
      asf::studies::runExperiment(cfg, launcher, [&](const std::string& l) { lines.push_back(l); });
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].exit_code, 1);
  std::string all;
  for (const auto& l : lines) all += l + "\n";
  EXPECT_TRUE(has(all, "[1/1] waypoints seed 1: failed (exit 1")) << all;
  EXPECT_TRUE(has(all, "no_such_key")) << "the log's last line is quoted: " << all;
  const json j = readJson(d / "out/summary.json");
  EXPECT_EQ(j["policies"]["waypoints"]["finished"], 0);
  EXPECT_TRUE(j["policies"]["waypoints"]["distance_m"]["mean"].is_null());
}

TEST(ExperimentHost, CtrlCStopsRunsAndStillSummarizes) {
  const fs::path d = tempDir("e2e_sigint");
  // A long route (back and forth many times), so the runs are still going when SIGINT comes.
  std::string route;
  for (int i = 0; i < 400; ++i) route += i % 2 ? "0 0; " : "2.5 0.5; ";
  route += "0 0";
  writePipeline(d, route);
  write(d / "exp.ini",
        "[experiment]\npipeline = pipe.ini\npolicies = waypoints\nreplications = 3\njobs = 2\n"
        "out = out\n");
  const std::string log = (d / "experiment.log").string();
  const pid_t pid = asf_test::spawnHost({"experiment", (d / "exp.ini").string()}, log);
  ASSERT_GT(pid, 0);
  // Wait until both parallel runs have started and written some steps.
  const auto t0 = std::chrono::steady_clock::now();
  auto started = [&] {
    // Steps written: both runs are past installing their SIGINT handler.
    std::error_code ec;
    for (const char* s :
         {"out/waypoints/seed_1/trajectory.csv", "out/waypoints/seed_2/trajectory.csv"}) {
      const auto size = fs::file_size(d / s, ec);
      if (ec || size < 2000) return false;
    }
    return true;
  };
  while (!started() && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_TRUE(started()) << read(log);
  kill(pid, SIGINT);
  int st = 0;
  ASSERT_EQ(waitpid(pid, &st, 0), pid);
  const std::string out = read(log);
  ASSERT_TRUE(WIFEXITED(st)) << out;
  if (fs::exists(d / "out/waypoints/seed_1/summary.json") &&
      asf::studies::runFinished((d / "out/waypoints/seed_1").string()) &&
      asf::studies::runFinished((d / "out/waypoints/seed_2").string()))
    GTEST_SKIP() << "both runs finished before the interrupt (machine too fast for the route)";
  EXPECT_EQ(WEXITSTATUS(st), 130) << out;
  EXPECT_TRUE(has(out, "interrupted")) << out;
  EXPECT_FALSE(fs::exists(d / "out/waypoints/seed_3")) << "no run starts after Ctrl-C";
  // The children wrote their outputs, and the experiment summarized them.
  const json j = readJson(d / "out/summary.json");
  int interrupted = 0;
  for (const auto& r : j["runs"]) interrupted += r.value("status", "") == "interrupted";
  EXPECT_GE(interrupted, 1) << j.dump(1);
  EXPECT_TRUE(fs::exists(d / "out/report.html"));
  EXPECT_TRUE(has(out, "| waypoints |")) << out;
}
