// The stages of `asf reproduce`: which asf commands rerun each table and figure of the
// thesis' chapters 3-6, on which data, with which sample sizes. The same commands as
// scripts/chapter-3.sh, table-4-1.sh and chapter-5-weights.sh and the chapter-6 experiment,
// with fewer start/goal pairs (the full sweep takes 100 min) and, under --quick, smoke-run
// sizes.
#include <asf/errors.h>
#include <asf/studies/reproduce.h>
#include <asf/text.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

namespace asf::studies::reproduce {

namespace fs = std::filesystem;
using Argv = std::vector<std::string>;

const char* const kThesisCaveOverrides =
    "dude.variant=thesis; dude.change_rule=reference; dude.rebuild_full_fraction=0; "
    "tigre.ties=random; tigre.relocate=false; tigre.next_goal=centre; tigre.robot_radius=0.325; "
    "frontier.robot_radius=0.325";

std::string Settings::fingerprint() const {
  std::ostringstream f;
  f << (quick ? "quick" : "full") << " pairs=" << pairs << " recognition=" << recognition_samples
    << " figure_samples=" << figure_samples << " replications=" << replications
    << " max_distance=" << max_distance << " shared=" << shared;
  return f.str();
}

namespace {

Command cmd(Argv argv, std::string stdout_file = "") {
  return {[argv] { return argv; }, std::move(stdout_file)};
}

/// What the cave runs depend on: where they stop.
std::string caveRunSettings(const Settings& s) {
  return "max_distance=" + formatSignificant(s.max_distance, 6) + " overrides=" +
         kThesisCaveOverrides;
}

/// The line of the thesis' graph list (optexp/graphs.txt) that Figs. 5.11-5.13 draw: the
/// thesis does not say which graphs it drew, so each is the first graph with the structure
/// its caption describes (as scripts/chapter-5-weights.sh picks them).
std::size_t pickGraphLine(const std::string& file, const std::string& rule) {
  std::ifstream in(file);
  if (!in) throw InputError(file + ": cannot read");
  std::string line;
  for (std::size_t no = 1; std::getline(in, line); ++no) {
    std::istringstream ls(line);
    std::size_t n = 0, m = 0;
    if (line.empty() || line[0] == '#' || !(ls >> n >> m)) continue;
    std::map<std::size_t, std::vector<std::size_t>> adj;
    std::string e;
    while (ls >> e) {
      const auto dash = e.find('-');
      if (dash == std::string::npos)
        throw InputError(file + ":" + std::to_string(no) + ": bad edge '" + e + "'");
      const std::size_t a = std::stoul(e.substr(0, dash)), b = std::stoul(e.substr(dash + 1));
      adj[a].push_back(b);
      adj[b].push_back(a);
    }
    std::set<std::size_t> seen{1};
    std::vector<std::size_t> stack{1};
    while (!stack.empty()) {
      const std::size_t v = stack.back();
      stack.pop_back();
      for (std::size_t w : adj[v])
        if (seen.insert(w).second) stack.push_back(w);
    }
    if (seen.size() != n) continue;
    const long cycles = static_cast<long>(m) - static_cast<long>(n) + 1;
    if ((rule == "tree" && cycles == 0 && n >= 20) ||
        (rule == "one_loop" && cycles == 1 && n >= 15) ||
        (rule == "cycles" && cycles >= 3 && n <= 30) ||
        (rule == "small_cycles" && cycles >= 2 && n <= 10))
      return no;
  }
  throw InputError(file + ": no graph is a '" + rule + "'");
}

/// Converting a CARMEN log and its graph SLAM run (configs/slam_<log>.ini).
Stage slamStage(const Settings& s, const std::string& log) {
  const std::string dir = s.out + "/ch3_" + log;
  const std::string src = s.shared + "/datasets/carmen/" + log + "-corrected.log.gz";
  Stage st{"ch3_" + log, "graph SLAM on the " + log + " log", {}, {src}, {}, 1};
  st.commands.push_back(
      cmd({"asf", "carmen2rawlog", "-q", "-i", src, "-o", dir + "/" + log + ".rawlog.gz", "--gt",
           dir + "/" + log + ".gt.txt", "--synth-odometry", "--seed", "1"},
          "convert.txt"));
  st.commands.push_back(
      cmd({"asf", "run", s.configs + "/slam_" + log + ".ini", "--out", dir + "/slam", "--set",
           "rawlog.file=" + dir + "/" + log + ".rawlog.gz", "--set",
           "rawlog.ground_truth=" + dir + "/" + log + ".gt.txt", "--set",
           "pipeline.progress_interval=0"},
          "slam.txt"));
  return st;
}

Stage table31Stage(const Settings& s, const std::string& log) {
  const std::string run = s.out + "/ch3_" + log;
  Stage st{"ch3_table_3_1_" + log, "Table 3.1 on " + log, {"ch3_" + log}, {}, {}, 1};
  // outputs=2: plan-eval records every chosen path and draws Figs. 3.4 and 3.5.
  st.settings = "pairs=" + std::to_string(s.pairs) +
                " recognition=" + std::to_string(s.recognition_samples) + " outputs=2";
  st.commands.push_back(
      cmd({"asf", "plan-eval", s.configs + "/plan_eval_" + log + ".ini", "--out",
           s.out + "/" + st.id, "--set", "plan_eval.graph=" + run + "/slam/graph.g2o", "--set",
           "plan_eval.rawlog=" + run + "/" + log + ".rawlog.gz", "--set",
           "plan_eval.max_pairs=" + std::to_string(s.pairs), "--set",
           "plan_eval.recognition_samples=" + std::to_string(s.recognition_samples), "--set",
           "plan_eval.threads=1"},
          "plan_eval.txt"));
  return st;
}

/// Table 3.2: the ACES run stopped when the robot first stands in the rotunda, the GVG's
/// virtual edges through the arm it saw but did not drive (see scripts/chapter-3.sh).
Stage table32Stage(const Settings& s) {
  const std::string aces = s.out + "/ch3_aces", dir = s.out + "/ch3_table_3_2";
  Stage st{"ch3_table_3_2", "Table 3.2 on aces, partially explored", {"ch3_aces"}, {}, {}, 1};
  st.settings = "outputs=2";  // asf plan --json records the hypotheses check (Figs. 3.1-3.2)
  st.commands.push_back(
      cmd({"asf", "run", s.configs + "/slam_aces.ini", "--out", dir + "/partial", "--set",
           "rawlog.file=" + aces + "/aces.rawlog.gz", "--set",
           "rawlog.ground_truth=" + aces + "/aces.gt.txt", "--set", "rawlog.max_frames=292",
           "--set", "map.widen_beams=true", "--set", "pipeline.progress_interval=0"},
          "partial.txt"));
  for (const char* scale : {"1", "0.1", "0.01"}) {
    st.commands.push_back({[dir, scale] {
                             const std::string summary = dir + "/partial/summary.json";
                             std::ifstream in(summary);
                             if (!in) throw InputError(summary + ": cannot read");
                             const auto j = nlohmann::json::parse(in);
                             const double step =
                                 j.at("distance_m").get<double>() / j.at("steps").get<double>();
                             return Argv{"asf",
                                         "plan",
                                         "--graph",
                                         dir + "/partial/graph.g2o",
                                         "--map",
                                         dir + "/partial/map.yaml",
                                         "--voronoi",
                                         "--start",
                                         "201",
                                         "--goal",
                                         "128",
                                         "--planner",
                                         "expected_uncertainty",
                                         "--set",
                                         "max_seconds=0",
                                         "--set",
                                         "voronoi_odometry_step=" + formatSignificant(step, 6),
                                         "--set",
                                         std::string("voronoi_cov_scale=") + scale,
                                         "--image",
                                         dir + "/table_3_2_cov_" + scale + ".png",
                                         "--json"};
                           },
                           std::string("table_3_2_cov_") + scale + ".json"});
  }
  return st;
}

Stage fig33Stage(const Settings& s) {
  Stage st{"ch3_fig_3_3", "Fig. 3.3 on aces", {"ch3_aces"}, {}, {}, 1};
  st.settings = "samples=" + std::to_string(s.figure_samples);
  st.commands.push_back(
      cmd({"asf", "recognition", s.out + "/ch3_aces/slam/graph.g2o", "-r",
           s.out + "/ch3_aces/aces.rawlog.gz", "-n", std::to_string(s.figure_samples), "-s", "141",
           "-s", "153", "-j", "1", "-o", s.out + "/" + st.id},
          "recognition.txt"));
  return st;
}

Stage table41Stage(const Settings& s) {
  const std::string d = s.shared + "/datasets/roomseg", dir = s.out + "/ch4_table_4_1";
  Stage st{"ch4_table_4_1",
           "Table 4.1, Figs. 4.1-4.2 (room segmentation benchmark)",
           {},
           {d + "/plain", d + "/gt", d + "/furnished"},
           {},
           1};
  // The reference DuDe's own outputs, when this copy of the data has them: the thesis variant
  // compared with them region by region (issue 48).
  std::error_code ec;
  const bool reference = fs::is_directory(d + "/reference_dude", ec);
  st.settings = std::string("outputs=2 reference=") + (reference ? "1" : "0");  // outputs: Fig. 4.3
  auto eval = [&](const std::string& label, const std::string& seg, Argv extra) {
    Argv a{"asf",          "segment-eval",
           "--plain",      d + "/plain",
           "--gt",         d + "/gt",
           "--furnished",  d + "/furnished",
           "--resolution", "0.05",
           "--segmenter",  seg,
           "--json",       dir + "/" + label + ".json"};
    a.insert(a.end(), extra.begin(), extra.end());
    st.commands.push_back(cmd(a, label + ".txt"));
  };
  const Argv inc{"--incremental", "--exploration", "raster_disks", "--incremental-on", "both"};
  Argv thesis{"--set", "variant=thesis"}, rooms{"--set", "variant=rooms"};
  thesis.insert(thesis.end(), inc.begin(), inc.end());
  rooms.insert(rooms.end(), inc.begin(), inc.end());
  thesis.insert(thesis.end(), {"--images", dir + "/images"});  // Fig. 4.3
  if (reference) thesis.insert(thesis.end(), {"--reference", d + "/reference_dude"});
  eval("dude_thesis", "dude", thesis);
  eval("dude_rooms", "dude", rooms);
  eval("voronoi", "voronoi", {});
  st.commands.push_back(cmd(
      {"asf", "segment-report", dir + "/dude_thesis.json", dir + "/dude_rooms.json",
       dir + "/voronoi.json", "-l", "dude thesis", "-l", "dude rooms", "-l", "voronoi", "-o", dir},
      "segment_report.txt"));
  return st;
}

Stage table51Stage(const Settings& s) {
  const std::string g = s.shared + "/datasets/optexp/graphs.txt";
  Stage st{"ch5_table_5_1", "Table 5.1 on the thesis' 174 graphs", {}, {g}, {}, 1};
  st.commands.push_back(
      cmd({"asf", "optimal-eval", g, "--json", "-p", s.out + "/" + st.id + "/efficiency.svg"},
          "optimal_eval.json"));
  return st;
}

Stage figs511Stage(const Settings& s) {
  const std::string g = s.shared + "/datasets/optexp/graphs.txt", dir = s.out + "/ch5_figs_5_11_13";
  Stage st{"ch5_figs_5_11_13", "Figs. 5.11-5.13 (optimal weights drawn)", {}, {g}, {}, 1};
  int fig = 11;
  for (const char* rule : {"tree", "one_loop", "cycles"}) {
    const std::string stem = dir + "/fig_5_" + std::to_string(fig++);
    st.commands.push_back({[g, rule, stem] {
                             return Argv{"asf",
                                         "optimal",
                                         g,
                                         "--index",
                                         std::to_string(pickGraphLine(g, rule)),
                                         "--criteria",
                                         "E,A,D",
                                         "--draw",
                                         stem + ".svg",
                                         "--json"};
                           },
                           fs::path(stem).filename().string() + ".json"});
  }
  return st;
}

/// Figs. 5.6-5.10: the information rate of the best walks of d traversals (exhaustive) on
/// K4 (figs. 5.6-5.8) and on a small generic graph of the thesis' list (figs. 5.9-5.10).
Stage walksStage(const Settings& s) {
  const std::string g = s.shared + "/datasets/optexp/graphs.txt", dir = s.out + "/ch5_walks";
  Stage st{"ch5_walks", "Figs. 5.6-5.10 (walks on K4 and a generic graph)", {}, {g}, {}, 1};
  st.commands.push_back({[dir] {
                           const std::string k4 = dir + "/k4.txt";
                           std::ofstream f(k4);
                           f << "# K4 (thesis fig. 5.5)\n4 6 1-2 1-3 1-4 2-3 2-4 3-4\n";
                           if (!f) throw Error(k4 + ": cannot write");
                           return Argv{"asf",
                                       "optimal",
                                       k4,
                                       "--index",
                                       "2",
                                       "--walks",
                                       "12",
                                       "--walk-kind",
                                       "walk",
                                       "--criteria",
                                       "T,D,A,E",
                                       "-p",
                                       dir + "/fig_5_6_8.svg",
                                       "--json"};
                         },
                         "k4.json"});
  st.commands.push_back({[g, dir] {
                           return Argv{"asf",
                                       "optimal",
                                       g,
                                       "--index",
                                       std::to_string(pickGraphLine(g, "small_cycles")),
                                       "--walks",
                                       "14",
                                       "--walk-kind",
                                       "walk",
                                       "--criteria",
                                       "T,D,A,E",
                                       "-p",
                                       dir + "/fig_5_9_10.svg",
                                       "--json"};
                         },
                         "generic.json"});
  return st;
}

/// Theorem 5.2.1 / eq. 5.54 on two real pose graphs and the Fig. 6.1 TIGRE run.
Stage theoremStage(const Settings& s) {
  const std::string g2o = s.shared + "/datasets/g2o";
  Stage st{"ch5_theorem",
           "Theorem 5.2.1 on intel, MIT and a cave run",
           {"ch6_fig_6_1"},
           {g2o + "/intel.g2o", g2o + "/MIT.g2o"},
           {},
           1};
  st.settings = caveRunSettings(s);  // the Fig. 6.1 run is one of its graphs
  // intel has 1728 poses: D only (sparse); the dense spectra of the others fit.
  st.commands.push_back(
      cmd({"asf", "optimal", g2o + "/intel.g2o", "--criteria", "D", "--theorem", "--json"},
          "theorem_intel.json"));
  st.commands.push_back(
      cmd({"asf", "optimal", g2o + "/MIT.g2o", "--criteria", "T,D,A,E", "--theorem", "--json"},
          "theorem_MIT.json"));
  st.commands.push_back(cmd({"asf", "optimal", s.out + "/ch6_fig_6_1/run", "--criteria", "T,D,A,E",
                             "--theorem", "--json"},
                            "theorem_cave_run.json"));
  return st;
}

/// The cave with the author's robot (configs/cave_thesis.ini): one stage per policy (so the
/// long TIGRE runs share the cores with the rest), each an `asf experiment` of its own INI
/// into its stage folder (two experiments never write one summary), then one that links the
/// four into ch6_experiment/runs/ and summarizes them together.
const char* const kPolicies[] = {"tigre", "frontier", "cpp_offline", "tsp_offline"};

std::string writeExperimentIni(const Settings& s, const std::string& file,
                               const std::string& policies) {
  std::ofstream f(file);
  f << "; written by asf reproduce\n[experiment]\npipeline = " << s.configs << "/cave_thesis.ini"
    << "\npolicies = " << policies << "\nreplications = " << s.replications << "\nfirst_seed = 1\n"
    << "overrides = " << kThesisCaveOverrides << "; pipeline.progress_interval=0"
    << (s.max_distance > 0 ? "; pipeline.max_distance=" + formatSignificant(s.max_distance, 6) : "")
    << "\n";
  if (!f) throw Error(file + ": cannot write");
  return file;
}

Stage policyStage(const Settings& s, const std::string& policy) {
  const std::string dir = s.out + "/ch6_" + policy;
  Stage st{"ch6_" + policy, "the cave with the author's robot: " + policy, {}, {}, {}, 1};
  st.settings = "replications=" + std::to_string(s.replications) + " " + caveRunSettings(s);
  st.commands.push_back({[s, dir, policy] {
                           fs::create_directories(dir);
                           const std::string ini = writeExperimentIni(
                               s, dir + "/experiment_" + policy + ".ini", policy);
                           return Argv{"asf", "experiment", ini, "-j", "1", "-o", dir + "/runs"};
                         },
                         "experiment.txt"});
  return st;
}

Stage experimentStage(const Settings& s) {
  const std::string dir = s.out + "/ch6_experiment";
  Stage st{"ch6_experiment", "Figs. 6.2-6.4: the four policies summarized", {}, {}, {}, 1};
  st.settings = "replications=" + std::to_string(s.replications) + " " + caveRunSettings(s);
  for (const char* p : kPolicies) st.after.push_back(std::string("ch6_") + p);
  st.commands.push_back(
      {[s, dir] {
         const std::string ini = writeExperimentIni(s, dir + "/experiment.ini",
                                                    "tigre, frontier, cpp_offline, tsp_offline");
         fs::create_directories(dir + "/runs");
         for (const char* p : kPolicies) {
           const fs::path link = dir + "/runs/" + p;
           fs::remove_all(link);
           fs::create_directory_symlink(fs::path("../..") / ("ch6_" + std::string(p)) / "runs" / p,
                                        link);
         }
         return Argv{"asf", "experiment", ini, "--summarize-only", "-o", dir + "/runs"};
       },
       "summary.txt"});
  return st;
}

Stage fig61Stage(const Settings& s) {
  Stage st{"ch6_fig_6_1", "Fig. 6.1: snapshots of one TIGRE run", {}, {}, {}, 1};
  st.settings = caveRunSettings(s);
  Argv a{
      "asf",
      "run",
      s.configs + "/cave_thesis.ini",
      "--out",
      s.out + "/" + st.id + "/run",
      "--set",
      "pipeline.progress_interval=0",
      "--set",
      std::string("pipeline.snapshot_distances=") + (s.max_distance > 0 ? "10,20,30" : "15,40,90")};
  // The overrides of the experiments, one --set each: the same TIGRE as Figs. 6.2-6.4.
  for (const std::string& kv : splitTrimmed(kThesisCaveOverrides, ';')) a.insert(a.end(), {"--set", kv});
  if (s.max_distance > 0)
    a.insert(a.end(), {"--set", "pipeline.max_distance=" + formatSignificant(s.max_distance, 6)});
  st.commands.push_back(cmd(a, "run.txt"));
  return st;
}

}  // namespace

std::vector<Stage> plan(const Settings& s) {
  // Longest first: the scheduler starts ready stages in this order.
  return {policyStage(s, "tigre"),
          slamStage(s, "aces"),
          table31Stage(s, "aces"),
          policyStage(s, "frontier"),
          policyStage(s, "cpp_offline"),
          policyStage(s, "tsp_offline"),
          experimentStage(s),
          slamStage(s, "intel"),
          table31Stage(s, "intel"),
          fig61Stage(s),
          fig33Stage(s),
          table32Stage(s),
          table41Stage(s),
          table51Stage(s),
          figs511Stage(s),
          walksStage(s),
          theoremStage(s)};
}

std::string stageSettings(const Settings& s, const Stage& st) {
  return "data=" + s.shared + (st.settings.empty() ? "" : " " + st.settings);
}

std::string recordedSettings(const Settings& s, const Stage& st) {
  std::ifstream in(s.out + "/" + st.id + "/done.json");
  if (!in) return "";
  try {
    return nlohmann::json::parse(in).value("settings", "");
  } catch (const std::exception&) {
    return "";
  }
}

}  // namespace asf::studies::reproduce
