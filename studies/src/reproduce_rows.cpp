// The rows of `asf reproduce`: each thesis value (with where the thesis gives it) beside the
// value asf measured, read back from the stages' outputs. Chapter 6 (TIGRE on the cave) here;
// chapters 3-5 in reproduce_rows_ch3.cpp and reproduce_rows_ch45.cpp.
#include <algorithm>

#include "reproduce_collector.h"

namespace asf::studies::reproduce {

namespace {

// ---- chapter 6 ---------------------------------------------------------------------------

const char* const kPolicies[] = {"tigre", "cpp_offline", "tsp_offline", "frontier"};
const char* const kPolicyNames[] = {"TIGRE", "CPP (offline)", "TSP (offline)", "frontier"};
// The author's spreadsheets (../shared/docs/thesis-notes.md, ch. 6): distance, mean pose
// error, loop closures.
const double kDistance[] = {129.2, 133.7, 76.2, 99.7};
const double kError[] = {0.32, 0.24, 0.69, 0.59};
const double kLoops[] = {51, 35, 1, 17};

std::string ordering(const double v[4]) {
  std::vector<int> o{0, 1, 2, 3};
  std::sort(o.begin(), o.end(), [&](int a, int b) { return v[a] < v[b]; });
  std::string s;
  for (int i = 0; i < 4; ++i) s += (i ? " < " : "") + std::string(kPolicyNames[o[i]]);
  return s;
}

void policiesOnTheCave(Collector& c) {
  const std::string stage = "ch6_experiment";
  const json j = c.read(stage, "runs/summary.json");
  double dist[4], err[4];
  bool all = j.is_object();
  for (int p = 0; p < 4; ++p) {
    const json pj = j.is_object() ? j["policies"].value(kPolicies[p], json()) : json();
    auto stat = [&](const char* k, int digits) -> std::pair<std::string, double> {
      const double m = num(pj, {k, "mean"}), sd = num(pj, {k, "std"});
      if (!std::isfinite(m)) return {"", NAN};
      return {pm(m, sd, digits) + " (" + fmt(num(pj, {"finished"}), 0) + "/" +
                  fmt(num(pj, {"total"}), 0) + " runs finished)",
              m};
    };
    const auto [d, dm] = stat("distance_m", 1);
    const auto [e, em] = stat("mean_pose_error_m", 3);
    const auto [l, lm] = stat("loop_closures", 0);
    dist[p] = dm;
    err[p] = em;
    all = all && std::isfinite(dm) && std::isfinite(em);
    const std::string who = kPolicyNames[p];
    c.row(stage, "Figs. 6.2-6.4", who + ": distance [m]", fmt(kDistance[p]), d,
          d.empty() ? "" : ratio(dm, kDistance[p]));
    c.row(stage, "Figs. 6.2-6.4", who + ": mean pose error [m]", fmt(kError[p], 2), e,
          e.empty() ? "" : ratio(em, kError[p]));
    c.row(stage, "Figs. 6.2-6.4", who + ": loop closures", fmt(kLoops[p], 0), l,
          l.empty() ? "" : ratio(lm, kLoops[p]),
          "asf counts every accepted loop-closure edge; the thesis' count is not defined further");
    c.figure("Figs. 6.2-6.4", "Fig. 6.2, " + who + ": final map, seed 1",
             stage + "/runs/" + kPolicies[p] + "/seed_1/map.png");
    c.figure("Figs. 6.2-6.4", "Fig. 6.2, " + who + ": final regions, seed 1",
             stage + "/runs/" + kPolicies[p] + "/seed_1/regions.png");
  }
  const std::string od = all ? ordering(dist) : "", oe = all ? ordering(err) : "";
  c.row(stage, "Figs. 6.2-6.4", "ordering by distance", ordering(kDistance), od,
        all ? (od == ordering(kDistance) ? "agrees" : "differs") : "",
        "TIGRE's extra distance: docs/benchmarks/exploration.md, \"TIGRE as the thesis "
        "defines it\" (setting by setting)");
  c.row(stage, "Figs. 6.2-6.4", "ordering by mean pose error", ordering(kError), oe,
        all ? (oe == ordering(kError) ? "agrees" : "differs") : "");
  // The goal's form of the error ordering: both edge-covering policies below both others.
  const bool covering_better = all && std::max(err[0], err[1]) < std::min(err[2], err[3]);
  c.row(stage, "Figs. 6.2-6.4", "mean pose error: TIGRE and CPP both below frontier and TSP", "yes",
        all ? (covering_better ? "yes" : "no") : "",
        all ? (covering_better ? "agrees" : "differs") : "");
  c.figure("Figs. 6.2-6.4", "Fig. 6.3: pose error / distance vs distance",
           stage + "/runs/error_per_distance_vs_distance.svg");
  c.figure("Figs. 6.2-6.4", "Fig. 6.4: coverage vs distance",
           stage + "/runs/coverage_vs_distance.svg");

  const std::string s61 = "ch6_fig_6_1";
  const std::vector<std::string> distances = c.snapshotDistances(s61);
  for (const auto& d : distances) {
    const std::string stem = s61 + "/run/snapshots/at_" + d + "m_";
    c.figure("Fig. 6.1", "TIGRE run, " + d + "m: map", stem + "map.png");
    c.figure("Fig. 6.1", "TIGRE run, " + d + "m: regions", stem + "regions.png");
    c.figure("Fig. 6.1", "TIGRE run, " + d + "m: topological graph", stem + "topology.svg");
  }
  const std::size_t snapshots = distances.size();
  c.figure("Fig. 6.1", "TIGRE run, end: map", s61 + "/run/map.png");
  c.figure("Fig. 6.1", "TIGRE run, end: topological graph", s61 + "/run/topology.svg");
  const json run = c.read(s61, "run/summary.json");
  c.row(s61, "Fig. 6.1", "snapshots of one TIGRE run (map, regions, graph)",
        "early stages, a loop-closing edge chosen before a frontier, the complete exploration",
        run.is_object() ? std::to_string(snapshots) + " snapshots and the end (" +
                              fmt(num(run, {"distance_m"})) + " m, " +
                              fmt(num(run, {"regions"}), 0) + " regions)"
                        : "",
        run.is_object() ? "qualitative: compare the pictures" : "");
}

}  // namespace

void chapter6(Collector& c) {
  const Settings& s = c.s_;
  c.section(
      "Figs. 6.2-6.4",
      "The cave with the author's robot and laser (configs/cave_thesis.ini) and TIGRE as the "
      "thesis defines it (overrides " +
          std::string(kThesisCaveOverrides) + ": configs/experiment_cave_as_thesis.ini), " +
          std::to_string(s.replications) + " seed(s) per policy" +
          (s.max_distance > 0 ? ", each run stopped after " + fmt(s.max_distance, 0) + " m" : "") +
          ". Thesis values: the author's spreadsheets (../shared/docs/thesis-notes.md).");
  policiesOnTheCave(c);
}

Report collect(const Settings& s, const std::vector<Stage>& stages,
               const std::vector<StageResult>& results) {
  Collector c(s, stages, results);
  chapter3(c);
  chapters4and5(c);
  chapter6(c);
  return c.report;
}

}  // namespace asf::studies::reproduce
