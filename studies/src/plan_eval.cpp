// asf plan-eval: the unreliable-path-avoidance protocol of thesis Table 3.1 (ch. 3.5.1) on
// a SLAM run. In a zone every scan is ignored and the links are wheel odometry with their
// covariance times a factor (asf/planning/unreliable_zone.h); the graph is re-optimized, its
// marginals recovered, place recognition estimated by Monte Carlo ICP on each node's own
// scan (asf/planning/place_recognition.h); for every start/goal pair of a node subset outside the
// zone each planner plugin picks its path, and its error rate is the share of pairs whose
// path crosses the zone.
#include <asf/atomic_file.h>
#include <asf/backend.h>
#include <asf/config.h>
#include <asf/errors.h>
#include <asf/planning/expected_uncertainty.h>
#include <asf/planning/place_recognition.h>
#include <asf/studies/plan_eval.h>
#include <asf/planner.h>
#include <asf/pose_graph.h>
#include <asf/io/rawlog_io.h>
#include <asf/framework/registry.h>
#include <asf/text.h>
#include <asf/planning/unreliable_zone.h>

#include <Eigen/LU>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <thread>

#include "plan_eval_figure.h"
#include "plan_eval_report.h"

namespace asf::studies {

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

constexpr const char* kSection = "plan_eval";

const KeySpec kKeys[] = {
    keyPath("graph", nullptr,
            "The SLAM pose graph (g2o), e.g. the graph.g2o an `asf run` writes; taken as "
            "optimized"),
    keyPath("keyframes", "",
            "The run's keyframes.txt (node times, for matching the rawlog's frames); empty: "
            "keyframes.txt beside the graph"),
    keyPath("rawlog", "",
            "The log the run read: the nodes' scans (place recognition, and what the zone "
            "ignores) and the wheel odometry between keyframes. Empty: the graph alone (no "
            "scans: p_recognition 1 outside the zone, zone_covariance odometry or scaled)"),
    keyString("laser_label", "", "The run's [rawlog] laser_label (empty: the first laser)"),
    keyString("planners", "expected_uncertainty mechanical_work sum_dopt shortest",
              "Planner plugins compared (space or comma separated); each reads its keys from "
              "its own section"),
    keyString("backend", "sparse_lm",
              "Back-end re-optimizing each scenario's graph and recovering its marginals and "
              "cross-covariances (its keys: its own section)"),
    keyBool("optimize", "true",
            "Re-optimize each scenario's graph (zone masked) before recovering the marginals"),
    keyDoubleList("zones", nullptr,
                  "Feature-void zones, four numbers each: x_min y_min x_max y_max in the "
                  "graph's frame [m]"),
    keyDoubleList("factors", "10 100",
                  "Covariance factors of the zone's edges: one scenario per zone and factor "
                  "(named A, B, ... zone by zone)",
                  1, 1e12),
    keyEnum("zone_covariance", "wheel_odometry", "wheel_odometry|odometry|scaled",
            "Edges left between consecutive keyframes with an end in the zone: wheel_odometry "
            "(the rawlog's odometry between the keyframes, mean and covariance, times the "
            "factor: the thesis), odometry (the edge's mean, MRPT's default motion model "
            "times the factor) or scaled (the edge's own covariance times the factor)"),
    keyEnum("zone_edges", "touching", "touching|inside",
            "Edges changed: those with an end in the zone, or both (odometry and scaled only)"),
    keyBool("drop_zone_loop_closures", "true",
            "Remove the non-consecutive edges with an end in the zone (no scans there to "
            "match); false only with odometry or scaled"),
    keyInt("recognition_samples", "40",
           "With a rawlog: p_recognition of every node outside the zone by Monte Carlo with "
           "this many ICP samples of its own scan against the other nodes' scans; 0: 1 "
           "outside the zone. Zone nodes: 0",
           0, 1e6),
    keyDouble("recognition_map_radius", "6.0",
              "Local map of the Monte Carlo: scans of the nodes within this distance [m]", 0.1,
              1e4),
    keyDouble("recognition_window_xy", "0.3",
              "Monte Carlo: half size of the window of believed positions [m] (thesis: 60 cm)", 0,
              100),
    keyDouble("recognition_window_phi_deg", "30",
              "Monte Carlo: half size of the window of believed headings [deg] (thesis: 60 deg)", 0,
              180),
    keyInt("threads", "0", "Threads of the Monte Carlo (0: one per core)", 0, 256),
    keyInt("pair_stride", "1", "Start/goal candidates: every k-th node by id", 1, 1e9),
    keyDouble("pair_grid", "0",
              "> 0: of those, one node per square cell of this size, the lowest id [m]", 0, 1e6),
    keyInt("max_pairs", "0",
           "> 0: a seeded random subset of this many pairs per zone (0: every pair)", 0, 1e9),
    keyBool("ordered", "false", "Plan both directions of each pair"),
    keyInt("seed", "1", "Seed of the pair subset and the Monte Carlo, handed to the planners too",
           0, 9.0e15),
    keyPath("out", "plan_eval", "Output folder: plan_eval.md, plan_eval.json (--out overrides)"),
    keyBool("write_graphs", "false",
            "Also write each scenario's graph (after re-optimization) as scenario_<name>.g2o, "
            "e.g. for `asf plan` with recognition_<name>.txt"),
    keyInt("progress_every", "25",
           "Print a progress line on stderr every this many pairs (0: only per scenario)", 0, 1e9),
};

std::vector<std::string> splitNames(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s + " ") {
    if (c == ',' || std::isspace(static_cast<unsigned char>(c))) {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  return out;
}

/// Components of the graph without the zone's nodes (-1 for zone nodes).
std::vector<int> componentsOutside(const PoseGraph& g, const std::vector<char>& in_zone) {
  std::vector<std::vector<NodeId>> adj(g.size());
  for (const auto& e : g.edges) {
    if (e.from >= g.size() || e.to >= g.size() || in_zone[e.from] || in_zone[e.to]) continue;
    adj[e.from].push_back(e.to);
    adj[e.to].push_back(e.from);
  }
  std::vector<int> comp(g.size(), -1);
  int next = 0;
  for (NodeId s = 0; s < g.size(); ++s) {
    if (in_zone[s] || comp[s] >= 0) continue;
    std::vector<NodeId> stack{s};
    comp[s] = next;
    while (!stack.empty()) {
      const NodeId v = stack.back();
      stack.pop_back();
      for (NodeId w : adj[v])
        if (comp[w] < 0) {
          comp[w] = next;
          stack.push_back(w);
        }
    }
    ++next;
  }
  return comp;
}

struct PlannerSlot {
  std::string name;
  std::shared_ptr<const framework::PluginInfo> info;
  Params params;
  framework::PluginHandle<Planner> planner;
  std::size_t warnings = 0;
  std::string first_warning;
};

std::vector<planning::Zone> zonesFrom(const Params& p) {
  const std::vector<double> zv = p.getDoubleList("zones");
  if (zv.empty() || zv.size() % 4 != 0)
    p.fail("zones", "expected four numbers per zone (x_min y_min x_max y_max), got " +
                        std::to_string(zv.size()));
  std::vector<planning::Zone> zones;
  for (std::size_t i = 0; i < zv.size(); i += 4) {
    planning::Zone z{zv[i], zv[i + 1], zv[i + 2], zv[i + 3]};
    if (!(z.x0 < z.x1 && z.y0 < z.y1))
      p.fail("zones",
             "zone " + std::to_string(i / 4 + 1) + " has x_min >= x_max or y_min >= y_max");
    zones.push_back(z);
  }
  return zones;
}

/// The planner plugins, and every section of the file accounted for.
std::vector<PlannerSlot> plannersFrom(const IniConfig& ini, const Params& p,
                                      framework::Registry& reg, const std::string& backend_name) {
  std::vector<PlannerSlot> slots;
  for (const auto& name : splitNames(p.getString("planners"))) {
    PlannerSlot s;
    s.name = name;
    s.info = reg.find(name, PluginKind::Planner);
    s.params = ini.resolve(name, s.info->descriptor->keys, s.info->descriptor->num_keys);
    slots.push_back(std::move(s));
  }
  if (slots.empty()) p.fail("planners", "no planner named");
  std::vector<std::string> known{kSection, lowercase(backend_name)};
  for (const auto& s : slots) known.push_back(lowercase(s.name));
  for (const auto& sec : ini.sections())
    if (std::find(known.begin(), known.end(), sec) == known.end())
      throw ConfigError(ini.unknownSection(
          sec, known, "sections are [plan_eval], the backend's and the planners'"));
  return slots;
}

/// The graph with the nodes' scans when the config names the run's log, and the log.
struct RunData {
  std::string graph_file;
  PoseGraph graph;
  std::optional<planning::KeyframeLog> log;
};

RunData runDataFrom(const Params& p) {
  RunData d;
  d.graph_file = p.getString("graph");
  const std::string rawlog = p.getString("rawlog");
  if (rawlog.empty()) {
    if (p.getString("zone_covariance") == "wheel_odometry")
      p.fail("zone_covariance",
             "wheel_odometry needs the run's log (key rawlog); without it use odometry or scaled");
    d.graph = readG2o(d.graph_file);
  } else {
    std::cerr << "plan-eval: reading the keyframes' scans and odometry from " << rawlog << "\n";
    d.log.emplace();
    d.graph = planning::readRunWithScans(d.graph_file, p.getString("keyframes"), rawlog,
                               p.getString("laser_label"), &*d.log);
  }
  if (d.graph.size() < 2) throw InputError(d.graph_file + ": fewer than two nodes");
  return d;
}

planning::ZoneMaskOptions maskOptionsFrom(const Params& p, double factor) {
  planning::ZoneMaskOptions o;
  o.factor = factor;
  const std::string c = p.getString("zone_covariance");
  o.covariance = c == "wheel_odometry" ? planning::ZoneCovariance::WheelOdometry
                 : c == "odometry"     ? planning::ZoneCovariance::OdometryModel
                                       : planning::ZoneCovariance::Scaled;
  o.touching = p.getString("zone_edges") == "touching";
  o.drop_loop_closures = p.getBool("drop_zone_loop_closures");
  if (o.covariance == planning::ZoneCovariance::WheelOdometry &&
      !(o.touching && o.drop_loop_closures))
    p.fail("zone_covariance",
           "wheel_odometry ignores every scan of the zone: it needs zone_edges = touching and "
           "drop_zone_loop_closures = true");
  return o;
}

/// Start/goal pairs of one zone: outside it and joined by a path avoiding it (else no
/// planner could avoid it).
struct PairSet {
  std::vector<std::pair<NodeId, NodeId>> pairs;
  std::size_t unavoidable = 0;
};

PairSet pairsFor(const PoseGraph& base, const std::vector<char>& in_zone, const Params& p,
                 std::size_t zone_index) {
  const std::size_t stride = static_cast<std::size_t>(p.getInt("pair_stride"));
  const double grid = p.getDouble("pair_grid");
  const std::size_t max_pairs = static_cast<std::size_t>(p.getInt("max_pairs"));
  std::vector<NodeId> cand;
  std::set<std::pair<long, long>> cells;
  for (NodeId v = 0; v < base.size(); v += static_cast<NodeId>(stride)) {
    if (in_zone[v]) continue;
    if (grid > 0) {
      const auto cell =
          std::make_pair(static_cast<long>(std::floor(base.nodes[v].pose.x() / grid)),
                         static_cast<long>(std::floor(base.nodes[v].pose.y() / grid)));
      if (!cells.insert(cell).second) continue;
    }
    cand.push_back(v);
  }
  const std::vector<int> comp = componentsOutside(base, in_zone);
  PairSet s;
  for (std::size_t i = 0; i < cand.size(); ++i)
    for (std::size_t j = i + 1; j < cand.size(); ++j) {
      if (comp[cand[i]] != comp[cand[j]]) {
        ++s.unavoidable;
        continue;
      }
      s.pairs.emplace_back(cand[i], cand[j]);
    }
  if (max_pairs > 0 && s.pairs.size() > max_pairs) {
    std::mt19937_64 rng(static_cast<std::uint64_t>(p.getInt("seed")) + zone_index);
    std::shuffle(s.pairs.begin(), s.pairs.end(), rng);
    s.pairs.resize(max_pairs);
    std::sort(s.pairs.begin(), s.pairs.end());
  }
  if (p.getBool("ordered")) {
    const std::size_t m = s.pairs.size();
    for (std::size_t i = 0; i < m; ++i) s.pairs.emplace_back(s.pairs[i].second, s.pairs[i].first);
  }
  return s;
}

/// p_recognition of every node of `g` with a scan by Monte Carlo (zone nodes have none: 0).
std::map<NodeId, double> recognitionByMonteCarlo(const PoseGraph& g, const Params& p,
                                                 const std::string& label) {
  planning::RecognitionMcOptions mc;
  mc.samples = static_cast<int>(p.getInt("recognition_samples"));
  mc.map_radius = p.getDouble("recognition_map_radius");
  mc.half_x = mc.half_y = p.getDouble("recognition_window_xy");
  mc.half_phi = p.getDouble("recognition_window_phi_deg") * M_PI / 180;
  mc.seed = static_cast<std::uint64_t>(p.getInt("seed"));
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<double> pr = planning::recognitionProbabilities(
      g, mc, static_cast<unsigned>(p.getInt("threads")), [&](std::size_t k, std::size_t n) {
        std::cerr << "[" << label << "] place recognition " << k << "/" << n << " nodes, "
                  << std::setprecision(3) << secondsSince(t0) << " s\n";
      });
  std::map<NodeId, double> out;
  for (NodeId v = 0; v < g.size(); ++v) out[v] = pr[v];
  return out;
}

/// One zone x factor: the masked, re-optimized graph, its marginals and recognition.
struct Scenario {
  std::string name;
  std::size_t zone_index = 0;  ///< 1-based
  planning::Zone zone;
  double factor = 1;
  PoseGraph graph;
  Marginals marginals;
  OptimizeReport opt;
  planning::ZoneMaskReport mask;
  double marginals_s = 0, recognition_s = 0;
  std::map<NodeId, double> recognition;  ///< empty: the planners' own p_recognition
};

void prepareScenario(Scenario& s, const RunData& run, const std::vector<char>& in_zone,
                     const Params& p, const std::shared_ptr<const framework::PluginInfo>& binfo,
                     const Params& bparams, const std::string& out_dir) {
  const planning::ZoneMaskOptions mo = maskOptionsFrom(p, s.factor);
  s.graph = planning::maskZone(run.graph, in_zone, mo, run.log ? &*run.log : nullptr, &s.mask);
  auto be = framework::Registry::create<Backend>(binfo);
  framework::logPluginToStderr(*be, binfo->name());
  PluginContext bctx;
  bctx.seed = static_cast<std::uint64_t>(p.getInt("seed"));
  be->configure(bparams, bctx);
  if (p.getBool("optimize")) s.opt = be->optimize(s.graph);
  if (p.getBool("write_graphs"))
    writeG2o(s.graph, (fs::path(out_dir) / ("scenario_" + s.name + ".g2o")).string());
  // Every cross-covariance block: the planners' relocalization probability may ask for any
  // pair of nodes on a candidate path.
  const std::size_t n = s.graph.size();
  std::vector<std::pair<NodeId, NodeId>> all_pairs;
  all_pairs.reserve(n * (n - 1) / 2);
  for (NodeId a = 0; a < n; ++a)
    for (NodeId b = a + 1; b < n; ++b) all_pairs.emplace_back(a, b);
  auto t0 = std::chrono::steady_clock::now();
  s.marginals = be->marginals(s.graph, all_pairs);
  s.marginals_s = secondsSince(t0);
  if (run.log && p.getInt("recognition_samples") > 0) {
    t0 = std::chrono::steady_clock::now();
    s.recognition = recognitionByMonteCarlo(s.graph, p, s.name);
    s.recognition_s = secondsSince(t0);
  }
}

/// The planners, configured for a scenario: its recognition probabilities (Monte Carlo, the
/// user's p_recognition_file over them, 0 in the zone) in recognition_<name>.txt.
void configurePlanners(std::vector<PlannerSlot>& slots, const Scenario& s,
                       const std::vector<char>& in_zone, std::uint64_t seed,
                       const std::string& out_dir) {
  const std::string rec_file = (fs::path(out_dir) / ("recognition_" + s.name + ".txt")).string();
  for (PlannerSlot& slot : slots) {
    Params params = slot.params;
    if (params.has("p_recognition_file")) {
      std::map<NodeId, double> rec = s.recognition;
      const std::string user = params.getString("p_recognition_file");
      if (!user.empty()) {
        try {
          for (const auto& [v, pr] : planning::readRecognitionProbabilities(user)) rec[v] = pr;
        } catch (const InputError& e) {
          params.fail("p_recognition_file", e.what());
        }
      }
      for (NodeId v = 0; v < in_zone.size(); ++v)
        if (in_zone[v]) rec[v] = 0;
      planning::writeRecognitionProbabilities(rec_file, rec);
      Params::Value val;
      val.text = rec_file;
      val.type = KeyType::Path;
      val.is_default = false;
      val.origin = "plan-eval";
      params.set("p_recognition_file", val);
    }
    slot.planner = framework::Registry::create<Planner>(slot.info);
    slot.planner->logging_enable_console_output = false;
    slot.warnings = 0;
    slot.first_warning.clear();
    slot.planner->logRegisterCallback([&slot](std::string_view msg,
                                              mrpt::system::VerbosityLevel lvl, std::string_view,
                                              const mrpt::Clock::time_point&) {
      if (lvl < mrpt::system::LVL_WARN) return;
      if (slot.warnings++ == 0) slot.first_warning = std::string(msg);
    });
    slot.planner->setLoggerName(slot.name);
    PluginContext ctx;
    ctx.seed = seed;
    slot.planner->configure(params, ctx);
  }
}

struct Tally {
  std::size_t found = 0, errors = 0, not_found = 0;
  double time_s = 0, max_s = 0;
};

/// Every planner on every pair of the scenario; the scenario's json record.
json sweepPairs(std::vector<PlannerSlot>& slots, const Scenario& s, const PairSet& ps,
                const std::vector<char>& in_zone,
                const std::optional<planning::PathSearchOptions>& search,
                std::size_t progress_every) {
  const auto t_scen = std::chrono::steady_clock::now();
  std::vector<Tally> tally(slots.size());
  json jpairs = json::array();
  std::size_t no_avoiding_candidate = 0;
  double search_s = 0;
  auto crosses = [&](const std::vector<NodeId>& path) {
    return std::any_of(path.begin(), path.end(), [&](NodeId v) { return in_zone[v] != 0; });
  };
  for (std::size_t pi = 0; pi < ps.pairs.size(); ++pi) {
    PlanRequest req;
    req.graph = &s.graph;
    req.marginals = &s.marginals;
    req.start = ps.pairs[pi].first;
    req.goal = ps.pairs[pi].second;
    json jp{{"start", req.start}, {"goal", req.goal}};
    if (search) {
      const auto t0 = std::chrono::steady_clock::now();
      const auto cands = planning::searchPaths(s.graph, req.start, req.goal, *search);
      search_s += secondsSince(t0);
      const bool avoids = !std::all_of(cands.paths.begin(), cands.paths.end(), crosses);
      no_avoiding_candidate += !avoids;
      jp["candidates"] = cands.paths.size();
      jp["avoiding_candidate"] = avoids;
    }
    for (std::size_t k = 0; k < slots.size(); ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      const PlanResult r = slots[k].planner->plan(req);
      const double dt = secondsSince(t0);
      Tally& t = tally[k];
      t.time_s += dt;
      t.max_s = std::max(t.max_s, dt);
      if (!r.found) {
        ++t.not_found;
        jp[slots[k].name] = {{"found", false}, {"reason", r.reason}};
        continue;
      }
      ++t.found;
      const bool crossed = crosses(r.nodes);
      t.errors += crossed;
      jp[slots[k].name] = {{"crosses", crossed},
                           {"cost", r.cost},
                           {"nodes", r.nodes.size()},
                           {"time_s", dt},
                           {"path", r.nodes}};
    }
    jpairs.push_back(std::move(jp));
    if ((progress_every > 0 && (pi + 1) % progress_every == 0) || pi + 1 == ps.pairs.size()) {
      std::cerr << "[" << s.name << "] " << pi + 1 << "/" << ps.pairs.size() << " pairs, "
                << std::setprecision(4) << secondsSince(t_scen) << " s; no avoiding candidate "
                << no_avoiding_candidate << "; errors:";
      for (std::size_t k = 0; k < slots.size(); ++k)
        std::cerr << " " << slots[k].name << " " << tally[k].errors;
      std::cerr << "\n";
    }
  }
  json js{{"pairs", ps.pairs.size()},
          {"pairs_without_avoiding_path", ps.unavoidable},
          {"pairs_without_avoiding_candidate", no_avoiding_candidate},
          {"candidate_search_time_s", search_s},
          {"sweep_time_s", secondsSince(t_scen)}};
  for (std::size_t k = 0; k < slots.size(); ++k) {
    const Tally& t = tally[k];
    js["planners"][slots[k].name] = {
        {"errors", t.errors},
        {"found", t.found},
        {"not_found", t.not_found},
        {"error_rate", t.found ? static_cast<double>(t.errors) / t.found : 0.0},
        {"sweep_time_s", t.time_s},
        {"mean_time_s", ps.pairs.empty() ? 0.0 : t.time_s / ps.pairs.size()},
        {"max_time_s", t.max_s},
        {"warnings", slots[k].warnings},
        {"first_warning", slots[k].first_warning}};
  }
  js["pair_results"] = std::move(jpairs);
  return js;
}

/// det of the nodes' marginal covariances, in the zone and outside (max, median): what
/// sum_dopt weighs, and why it avoids the zone or not.
json marginalSummary(const Scenario& s, const std::vector<char>& in_zone) {
  std::vector<double> in, out;
  for (NodeId v = 0; v < s.marginals.node.size() && v < in_zone.size(); ++v)
    (in_zone[v] ? in : out).push_back(s.marginals.node[v].determinant());
  auto stats = [](std::vector<double> d) -> json {
    if (d.empty()) return nullptr;
    std::sort(d.begin(), d.end());
    return {{"max", d.back()}, {"median", d[d.size() / 2]}};
  };
  return {{"zone", stats(in)}, {"outside", stats(out)}};
}

/// Mean, min and max p_recognition over the nodes outside the zone.
json recognitionSummary(const Scenario& s, const std::vector<char>& in_zone) {
  if (s.recognition.empty()) return nullptr;
  double sum = 0, lo = 1, hi = 0;
  std::size_t k = 0, zero = 0;
  for (const auto& [v, pr] : s.recognition) {
    if (in_zone[v]) continue;
    sum += pr;
    lo = std::min(lo, pr);
    hi = std::max(hi, pr);
    zero += pr == 0;
    ++k;
  }
  return {{"nodes", k},   {"mean", k ? sum / k : 0.0}, {"min", lo}, {"max", hi},
          {"zero", zero}, {"time_s", s.recognition_s}};
}

json scenarioRecord(const Scenario& s, const std::vector<char>& in_zone, json sweep) {
  json js{{"name", s.name},
          {"zone", {s.zone.x0, s.zone.y0, s.zone.x1, s.zone.y1}},
          {"zone_index", s.zone_index},
          {"factor", s.factor},
          {"zone_nodes", s.mask.zone_nodes},
          {"scans_removed", s.mask.scans_removed},
          {"scaled_edges", s.mask.edges_replaced},
          {"dropped_loop_closures", s.mask.loop_closures_dropped},
          {"duplicate_edges_dropped", s.mask.duplicate_edges_dropped},
          {"optimize",
           {{"initial_chi2", s.opt.initial_chi2},
            {"final_chi2", s.opt.final_chi2},
            {"iterations", s.opt.iterations}}},
          {"marginals_time_s", s.marginals_s},
          {"recognition", recognitionSummary(s, in_zone)},
          {"marginal_det", marginalSummary(s, in_zone)}};
  js.update(sweep);
  return js;
}

}  // namespace

const KeySpec* planEvalKeys(std::size_t& n) {
  n = std::size(kKeys);
  return kKeys;
}

PlanEvalOutput runPlanEval(const IniConfig& ini, framework::Registry& reg,
                           const std::string& out_override, const std::string& config_name) {
  const Params p = ini.resolve(kSection, kKeys, std::size(kKeys));
  const std::vector<planning::Zone> zones = zonesFrom(p);
  const std::vector<double> factors = p.getDoubleList("factors");
  if (factors.empty()) p.fail("factors", "expected at least one factor");
  maskOptionsFrom(p, 1);  // key combinations checked before any work

  const std::string backend_name = p.getString("backend");
  const auto binfo = reg.find(backend_name, PluginKind::Backend);
  std::vector<PlannerSlot> slots = plannersFrom(ini, p, reg, backend_name);
  const Params bparams =
      ini.resolve(backend_name, binfo->descriptor->keys, binfo->descriptor->num_keys);
  // The candidate search of the criterion planners (the first one's keys), to tell planner
  // errors from candidate sets without a path avoiding the zone.
  std::optional<planning::PathSearchOptions> search;
  std::string search_of;
  for (const auto& s : slots)
    if (s.params.has("k_paths")) {
      search = planning::pathSearchOptionsFrom(s.params);
      search_of = s.name;
      break;
    }

  const std::string out_dir = out_override.empty() ? p.getString("out") : out_override;
  fs::create_directories(out_dir);
  const RunData run = runDataFrom(p);
  const PoseGraph& base = run.graph;
  const std::size_t n = base.size();
  const std::uint64_t seed = static_cast<std::uint64_t>(p.getInt("seed"));

  std::cerr << "plan-eval: " << run.graph_file << ": " << n << " nodes, " << base.edges.size()
            << " edges; " << zones.size() << " zone(s) x " << factors.size() << " factor(s); "
            << slots.size() << " planners\n";
  json jscen = json::array();
  const auto t_all = std::chrono::steady_clock::now();
  char letter = 'A';
  for (std::size_t zi = 0; zi < zones.size(); ++zi) {
    std::vector<char> in_zone(n, 0);
    std::size_t zone_nodes = 0, zone_scans = 0;
    for (NodeId v = 0; v < n; ++v) {
      zone_nodes += in_zone[v] = zones[zi].contains(base.nodes[v].pose);
      zone_scans += in_zone[v] && base.nodes[v].scan;
    }
    if (zone_nodes == 0)
      p.fail("zones", "zone " + std::to_string(zi + 1) + " holds no node of the graph");
    if (run.log && zone_scans == 0)
      p.fail("zones", "zone " + std::to_string(zi + 1) + ": none of its " +
                          std::to_string(zone_nodes) + " nodes has a scan in " +
                          p.getString("rawlog") + ": there is nothing to ignore");
    const PairSet ps = pairsFor(base, in_zone, p, zi);
    for (double factor : factors) {
      Scenario s;
      s.name = std::string(1, letter++);
      s.zone_index = zi + 1;
      s.zone = zones[zi];
      s.factor = factor;
      prepareScenario(s, run, in_zone, p, binfo, bparams, out_dir);
      configurePlanners(slots, s, in_zone, seed, out_dir);
      std::cerr << "[" << s.name << "] zone " << zi + 1 << " (" << s.zone.x0 << " " << s.zone.y0
                << " " << s.zone.x1 << " " << s.zone.y1 << "): " << zone_nodes << " nodes, "
                << s.mask.scans_removed << " scans ignored; " << p.getString("zone_covariance")
                << " covariance x" << factor << " on " << s.mask.edges_replaced << " edges, "
                << s.mask.loop_closures_dropped << " loop closures dropped; " << ps.pairs.size()
                << " pairs (" << ps.unavoidable << " without a path avoiding the zone skipped); "
                << "marginals " << std::setprecision(3) << s.marginals_s << " s\n";
      json sweep = sweepPairs(slots, s, ps, in_zone, search,
                              static_cast<std::size_t>(p.getInt("progress_every")));
      json rec = scenarioRecord(s, in_zone, std::move(sweep));
      try {  // a picture that cannot be written must not cost the scenarios' results
        rec["figures"] = writeScenarioFigures(s.graph, s.zone, rec, out_dir);
      } catch (const Error& e) {
        std::cerr << "[" << s.name << "] figures not written: " << e.what() << "\n";
        rec["figures"] = {{"error", e.what()}};
      }
      jscen.push_back(std::move(rec));
    }
  }

  json j{{"graph", run.graph_file},
         {"rawlog", run.log ? json(p.getString("rawlog")) : json(nullptr)},
         {"zone_covariance", p.getString("zone_covariance")},
         {"config", config_name},
         {"nodes", n},
         {"edges", base.edges.size()},
         {"planners", json::array()},
         {"candidate_search_of", search_of},
         {"scenarios", jscen},
         {"time_s", secondsSince(t_all)}};
  for (const auto& s : slots) j["planners"].push_back(s.name);
  PlanEvalOutput out;
  out.markdown = planEvalMarkdown(j);
  out.md_file = (fs::path(out_dir) / "plan_eval.md").string();
  out.json_file = (fs::path(out_dir) / "plan_eval.json").string();
  writeFileAtomically(out.md_file, out.markdown, "file");
  writeFileAtomically(out.json_file, j.dump(1) + "\n", "file");
  return out;
}

}  // namespace asf::studies
