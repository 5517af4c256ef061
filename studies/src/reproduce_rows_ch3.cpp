// The rows of `asf reproduce` for chapter 3 (expected-uncertainty planning): Table 3.1, Figs.
// 3.1-3.5 and Table 3.2.
#include "reproduce_collector.h"

namespace asf::studies::reproduce {

namespace {

// ---- chapter 3 ---------------------------------------------------------------------------

// Table 3.1 of the thesis (error rate %, scenarios A-D x criteria).
const char* const kCriteria[] = {"expected_uncertainty", "mechanical_work", "sum_dopt", "shortest"};
const char* const kCriterionNames[] = {"expected uncertainty", "mechanical work",
                                       "sum of D-optimality", "distance"};
const double kTable31[4][4] = {
    {0, 0, 0, 15.1}, {0, 0, 0, 15.1}, {0, 12.1, 47.1, 28.5}, {0, 0, 44.1, 28.5}};

void table31(Collector& c, const std::string& log) {
  const std::string stage = "ch3_table_3_1_" + log;
  const json j = c.read(stage, "plan_eval.json");
  std::map<std::string, const json*> by_name;
  if (j.is_object())
    for (const auto& sc : j["scenarios"]) by_name[sc.value("name", "")] = &sc;
  std::string eu_all, baseline_cd;
  bool eu_zero = true, any_scenario = false;
  for (int k = 0; k < 4; ++k) {
    const std::string name(1, static_cast<char>('A' + k));
    const json* sc = by_name.count(name) ? by_name[name] : nullptr;
    for (int cr = 0; cr < 4; ++cr) {
      std::string asf, diff, note;
      if (sc) {
        const double rate = 100 * num(*sc, {"planners", kCriteria[cr], "error_rate"});
        const double errors = num(*sc, {"planners", kCriteria[cr], "errors"});
        asf = fmt(rate) + " % (" + fmt(errors, 0) + " of " + fmt(num(*sc, {"pairs"}), 0) + ")";
        diff = points(rate, kTable31[k][cr]);
        if (cr == 0) eu_zero = eu_zero && rate == 0;
        if (k >= 2 && cr > 0 && cr < 3 && rate > 0)
          baseline_cd += name + " " + kCriterionNames[cr] + " " + fmt(rate) + " %; ";
      }
      if (cr == 0 && sc) any_scenario = true;
      c.row(stage, "Table 3.1",
            log + ", scenario " + name + " (zone " + (k < 2 ? "1" : "2") + ", ×" +
                (k % 2 ? "100" : "10") + "), " + kCriterionNames[cr],
            fmt(kTable31[k][cr]) + " %", asf, diff, note);
    }
  }
  c.row(stage, "Table 3.1", log + ": expected uncertainty errs 0 % in every scenario",
        "yes (0 % in A-D)", any_scenario ? (eu_zero ? "yes" : "no") : "",
        any_scenario ? (eu_zero ? "agrees" : "differs") : "");
  if (baseline_cd.size() > 2) baseline_cd.resize(baseline_cd.size() - 2);  // the last "; "
  c.row(stage, "Table 3.1", log + ": a baseline (work, sum of D-opt) errs in C or D",
        "yes (work 12.1 % in C; sum of D-opt 47.1 % / 44.1 % in C / D)",
        any_scenario ? (baseline_cd.empty() ? "no" : "yes: " + baseline_cd) : "",
        any_scenario ? (baseline_cd.empty() ? "differs" : "agrees") : "");
}

/// Figs. 3.4 (the scenarios: the zones on the map) and 3.5 (an error example: a baseline's
/// path through the zone where expected uncertainty goes around) from plan-eval's pictures.
void figs34and35(Collector& c, const std::string& log) {
  const std::string stage = "ch3_table_3_1_" + log;
  const json j = c.read(stage, "plan_eval.json");
  std::string example, example_file;
  bool any = false;
  if (j.is_object())
    for (const auto& sc : j["scenarios"]) {
      any = true;
      const std::string name = sc.value("name", "");
      const json fig = sc.value("figures", json());
      if (!fig.is_object()) continue;
      if (name == "A" || name == "C") {
        const std::string zone = name == "A" ? "1" : "2";
        c.row(stage, "Fig. 3.4",
              log + ": zone " + zone +
                  (zone == "1" ? " (a wing most paths can avoid)" : " (hard to avoid)"),
              "blue square on the map (figure; no value)",
              fmt(num(sc, {"zone_nodes"}), 0) + " nodes, " + fmt(num(sc, {"scans_removed"}), 0) +
                  " scans ignored; the shortest path crosses it in " +
                  fmt(num(sc, {"planners", "shortest", "errors"}), 0) + " of " +
                  fmt(num(sc, {"pairs"}), 0) + " pairs",
              "compare the pictures");
        if (fig.contains("scenario"))  // else plan-eval could not write it ("error")
          c.figure("Fig. 3.4",
                   log + ", zone " + zone + " (scenarios " + name + ", " +
                       static_cast<char>(name[0] + 1) + ")",
                   stage + "/" + fig.value("scenario", ""));
      }
      const json ex = fig.value("error_example", json());
      if (example.empty() && ex.is_object()) {
        const bool mw = ex.value("baseline", "") == "mechanical_work";
        example = "scenario " + name + ", node " + fmt(num(ex, {"start"}), 0) + " to " +
                  fmt(num(ex, {"goal"}), 0) + ": " +
                  (mw ? "mechanical work" : "sum of D-optimality") + " (" +
                  fmt(num(ex, {"baseline_nodes"}), 0) +
                  " nodes) crosses the zone, expected uncertainty (" +
                  fmt(num(ex, {"expected_uncertainty_nodes"}), 0) + " nodes) goes around";
        example_file = stage + "/" + ex.value("file", "");
      }
    }
  const bool found = !example.empty();
  c.row(stage, "Fig. 3.5",
        log + ": a baseline's path crosses the zone where expected uncertainty goes around",
        "yes: mechanical work returns to certain nodes through the zone (Fig. 3.5a), expected "
        "uncertainty avoids it (b)",
        any ? (found ? example : "no such pair: no baseline erred in A-D") : "",
        any ? (found ? "agrees" : "differs") : "",
        found ? "" : "see Table 3.1's note: why the baselines err only where they do");
  if (found) c.figure("Fig. 3.5", log + ": " + example, example_file);
}

/// Figs. 3.1-3.2 (illustrations of Algorithm 1) checked on Table 3.2's chosen path: the
/// merged hypotheses grow linearly, and their E[C] equals the enumeration of every sequence.
void figs31and32(Collector& c) {
  const std::string stage = "ch3_table_3_2";
  const json j = c.read(stage, "table_3_2_cov_1.json");
  const json h = j.is_object() ? j.value("hypotheses", json()) : json();
  const bool ok = h.is_object();
  const double m = num(h, {"steps"}), hyp = num(h, {"hypotheses"});
  c.row(stage, "Figs. 3.1-3.2", "hypotheses kept along a path of m steps",
        "m + 1 (one per step of the last relocalization), not 2^m",
        ok ? "aces, node 201 to 128: " + fmt(m, 0) + " steps, " + fmt(hyp, 0) + " hypotheses, " +
                 fmt(num(h, {"evaluations"}), 0) + " probability evaluations (2^" + fmt(m, 0) +
                 " = " + sci(num(h, {"sequences"})) + " sequences)"
           : "",
        ok ? (hyp == m + 1 ? "agrees" : "differs") : "");
  const double diff = num(h, {"relative_difference"}), from = num(h, {"checked_from_step"});
  c.row(stage, "Figs. 3.1-3.2", "E[C] of the merged hypotheses equals every sequence enumerated",
        "yes (the merge is exact)",
        ok ? "steps " + fmt(from + 1, 0) + "-" + fmt(from + num(h, {"checked_steps"}), 0) + " (" +
                 sci(num(h, {"checked_sequences"})) + " sequences; E[C] a mixture at " +
                 fmt(num(h, {"checked_mixed_prefixes"}), 0) +
                 " of its prefixes): largest relative difference " + sci(diff)
           : "",
        ok ? (diff < 1e-9 ? "agrees" : "differs") : "",
        "the window of the path where E[C] is most often a mixture of hypotheses");
}

void fig33(Collector& c) {
  const std::string stage = "ch3_fig_3_3";
  const json j = c.read(stage, "recognition.json");
  std::map<int, double> p;
  if (j.is_object())
    for (const auto& sc : j["scatter"]) p[sc.value("node", -1)] = sc.value("p", NAN);
  const bool both = p.count(141) && p.count(153);
  c.row(stage, "Fig. 3.3", "place recognition in a corridor (aces node 141)",
        "ICP errors spread along the corridor (figure; no value)",
        p.count(141) ? "p = " + fmt(p[141], 2) : "", "not comparable: the thesis gives no number");
  c.row(stage, "Fig. 3.3", "place recognition at a corner (aces node 153)",
        "errors concentrated: recognition succeeds (figure; no value)",
        p.count(153) ? "p = " + fmt(p[153], 2) : "", "not comparable: the thesis gives no number");
  c.row(stage, "Fig. 3.3", "a corner is recognised more reliably than a corridor",
        "yes (the figure's point)", both ? (p[153] > p[141] ? "yes" : "no") : "",
        both ? (p[153] > p[141] ? "agrees" : "differs") : "");
  c.figure("Fig. 3.3", "Monte Carlo ICP at aces node 141 (corridor)", stage + "/scatter_141.svg");
  c.figure("Fig. 3.3", "Monte Carlo ICP at aces node 153 (corner)", stage + "/scatter_153.svg");
}

void table32(Collector& c) {
  const std::string stage = "ch3_table_3_2";
  const json j = c.read(stage, "table_3_2_cov_1.json");
  const json g = j.is_object() ? j["comparison"].value("graph", json()) : json();
  const json u = j.is_object() ? j["comparison"].value("unexplored", json()) : json();
  const bool ok = g.is_object() && u.is_object();
  auto v = [&](const json& x, const char* k) { return ok ? x.value(k, NAN) : NAN; };
  const double dg = v(g, "distance"), du = v(u, "distance"), eg = v(g, "expected_uncertainty"),
               eu = v(u, "expected_uncertainty"), cg = v(g, "cost"), cu = v(u, "cost");
  const std::string S = "Table 3.2";
  c.row(stage, S, "graph SLAM path: distance", "31.7 m", ok ? fmt(dg) + " m" : "",
        ok ? ratio(dg, 31.7) : "");
  c.row(stage, S, "path through the unexplored: distance", "15.0 m", ok ? fmt(du) + " m" : "",
        ok ? ratio(du, 15.0) : "");
  c.row(stage, S, "distance saved by the unexplored path", "52 %",
        ok ? fmt(100 * (1 - du / dg), 0) + " %" : "", ok ? points(100 * (1 - du / dg), 52) : "");
  c.row(stage, S, "graph SLAM path: expected uncertainty", "2.97",
        ok ? sci(eg) + " (det E[C])" : "", ok ? "scales differ" : "",
        "the thesis does not say which scalar of E[C] it reports");
  c.row(stage, S, "path through the unexplored: expected uncertainty", "3.11",
        ok ? sci(eu) + " (det E[C])" : "", ok ? "scales differ" : "");
  c.row(stage, S, "uncertainty added by the unexplored path", "+4.7 %",
        ok ? "+" + fmt(100 * (eu / eg - 1), 0) + " %" : "", ok ? ratio(eu / eg, 1.047) : "");
  c.row(stage, S, "cost (distance × expected uncertainty): graph / unexplored", "94.15 / 46.65",
        ok ? sci(cg) + " / " + sci(cu) : "",
        ok ? (cu < cg ? "same ordering" : "reversed ordering") : "");
  std::string turn;
  for (const char* scale : {"0.1", "0.01"}) {
    const json js = c.read(stage, std::string("table_3_2_cov_") + scale + ".json");
    if (js.is_object() && js["comparison"]["unexplored"].is_object())
      turn += std::string("×") + scale + ": " +
              (js["comparison"]["unexplored"].value("path", json()) == js["path"] ? "unexplored"
                                                                                  : "graph") +
              "; ";
  }
  if (turn.size() > 2) turn.resize(turn.size() - 2);
  const bool unexplored = ok && u.value("path", json()) == j["path"];
  c.row(stage, S, "path chosen", "through the unexplored",
        ok ? (unexplored ? "through the unexplored" : "graph SLAM") : "",
        ok ? (unexplored ? "agrees" : "differs") : "",
        "chosen with the virtual edges' odometry covariance scaled " +
            (turn.empty() ? std::string("-") : turn));
  c.figure(S, "Table 3.2 / Fig. 3.6: the chosen path (odometry covariance ×1)",
           stage + "/table_3_2_cov_1.png");
  c.figure(S, "the same with the virtual edges' covariance ×0.01",
           stage + "/table_3_2_cov_0.01.png");
}

}  // namespace

void chapter3(Collector& c) {
  const Settings& s = c.s_;
  const std::string pairs = std::to_string(s.pairs);
  c.section("Table 3.1",
            "The thesis ran ch. 3.5.1 on Rawseeds, whose laser streams are not available here; asf "
            "runs it "
            "on two real CARMEN logs (intel, aces), converted with synthetic odometry (seed 1) and "
            "mapped by "
            "asf's graph SLAM (configs/slam_<log>.ini). In a zone every scan is ignored and the "
            "links are "
            "the log's wheel odometry with covariance ×10 (A, C) or ×100 (B, D); p_recognition "
            "comes from "
            "Monte Carlo ICP on each node's own scan (" +
                std::to_string(s.recognition_samples) + " samples). A seeded subset of " + pairs +
                " start/goal pairs per zone (scripts/chapter-3.sh runs 300). The zones and why the "
                "baselines "
                "err only where they do: configs/plan_eval_<log>.ini and "
                "docs/benchmarks/planning.md.");
  c.section("Fig. 3.3",
            "asf recognition on the ACES run, " + std::to_string(s.figure_samples) +
                " samples at a corridor node and a corner node (the thesis used Rawseeds).");
  c.section(
      "Table 3.2",
      "The ACES run stopped after 292 frames, when the robot first stands in the rotunda; virtual "
      "edges "
      "from the generalized Voronoi graph of its map; asf plan --voronoi from node 201 to node 128 "
      "(cost = distance × det E[C], eq. 3.25).");
  figs31and32(c);
  fig33(c);
  table31(c, "intel");
  table31(c, "aces");
  figs34and35(c, "intel");
  figs34and35(c, "aces");
  table32(c);
}

}  // namespace asf::studies::reproduce
