// asf plan-eval: the unreliable-path-avoidance protocol of thesis Table 3.1 on a SLAM pose
// graph. A feature-void zone is simulated (loop closures touching it removed, the
// covariances of its edges scaled, place recognition impossible at its nodes); for every
// start/goal pair of a node subset outside the zone, each planner plugin picks its path, and
// its error rate is the share of pairs whose path crosses the zone.
#include <asf/backend.h>
#include <asf/config.h>
#include <asf/errors.h>
#include <asf/expected_uncertainty.h>
#include <asf/planner.h>
#include <asf/pose_graph.h>
#include <asf/rawlog_io.h>
#include <asf/registry.h>
#include <tclap/CmdLine.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>
#include <optional>
#include <random>
#include <set>
#include <sstream>

#include "commands.h"
#include "plugin_cli.h"

namespace asf::app {

namespace {

using nlohmann::json;

constexpr const char* kSection = "plan_eval";

const KeySpec kKeys[] = {
    keyPath("graph", nullptr,
            "The SLAM pose graph (g2o), e.g. the graph.g2o an `asf run` writes; taken as "
            "optimized"),
    keyString("planners", "expected_uncertainty mechanical_work sum_dopt shortest",
              "Planner plugins compared (space or comma separated); each reads its keys from "
              "its own section"),
    keyString("backend", "sparse_lm",
              "Back-end re-optimizing each scenario's graph and recovering its marginals and "
              "cross-covariances (its keys: its own section)"),
    keyBool("optimize", "true",
            "Re-optimize each scenario's graph (loop closures dropped, covariances scaled) "
            "before recovering the marginals"),
    keyDoubleList("zones", nullptr,
                  "Feature-void zones, four numbers each: x_min y_min x_max y_max in the "
                  "graph's frame [m]"),
    keyDoubleList("factors", "10 100",
                  "Covariance factors of the zone's edges: one scenario per zone and factor "
                  "(named A, B, ... zone by zone)",
                  1, 1e12),
    keyEnum("zone_edges", "touching", "touching|inside",
            "Edges whose covariance is scaled: those with an end in the zone, or both"),
    keyEnum("zone_covariance", "odometry", "odometry|scaled",
            "Covariance of the zone's remaining edges: odometry (wheel odometry only, MRPT's "
            "Gaussian motion model with its default parameters, times the factor) or scaled "
            "(the edge's own covariance times the factor)"),
    keyBool("drop_zone_loop_closures", "true",
            "Remove the loop closures with an end in the zone (no scans there to match)"),
    keyInt("pair_stride", "1", "Start/goal candidates: every k-th node by id", 1, 1e9),
    keyDouble("pair_grid", "0",
              "> 0: of those, one node per square cell of this size, the lowest id [m]", 0, 1e6),
    keyInt("max_pairs", "0",
           "> 0: a seeded random subset of this many pairs per zone (0: every pair)", 0, 1e9),
    keyBool("ordered", "false", "Plan both directions of each pair"),
    keyInt("seed", "1", "Seed of the pair subset, handed to the planners too", 0, 9.0e15),
    keyPath("out", "plan_eval", "Output folder: plan_eval.md, plan_eval.json (--out overrides)"),
    keyBool("write_graphs", "false",
            "Also write each scenario's graph (after re-optimization) as scenario_<name>.g2o, "
            "e.g. for `asf plan` with recognition_<name>.txt"),
    keyInt("progress_every", "25",
           "Print a progress line on stderr every this many pairs (0: only per scenario)", 0,
           1e9),
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

struct Zone {
  double x0, y0, x1, y1;
  bool contains(const mrpt::poses::CPose2D& p) const {
    return p.x() >= x0 && p.x() <= x1 && p.y() >= y0 && p.y() <= y1;
  }
};

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

std::string percent(double x) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(1) << 100 * x << " %";
  return os.str();
}

struct PlannerSlot {
  std::string name;
  std::shared_ptr<const PluginInfo> info;
  Params params;
  PluginHandle<Planner> planner;
  std::size_t warnings = 0;
  std::string first_warning;
};

}  // namespace

int cmdPlanEval(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Unreliable-path avoidance (thesis ch. 3, Table 3.1) on a SLAM pose graph: for each "
      "feature-void zone and covariance factor of CONFIG.ini's [plan_eval] section, the "
      "zone's loop closures are removed, its edges' covariances scaled and its nodes made "
      "unrecognizable (p_recognition 0); the graph is re-optimized, its marginals and "
      "cross-covariances recovered, and every planner plans every start/goal pair of a node "
      "subset outside the zone. Error rate: share of the pairs whose path crosses the zone. "
      "Writes plan_eval.md and plan_eval.json; progress on stderr.",
      ' ', ASF_VERSION_STRING);
  TCLAP::UnlabeledValueArg<std::string> config("config", "The INI file", true, "", "CONFIG.ini",
                                               cmd);
  TCLAP::ValueArg<std::string> out_arg("o", "out", "Output folder (overrides [plan_eval] out)",
                                       false, "", "DIR", cmd);
  TCLAP::MultiArg<std::string> set("s", "set", "Override: section.key=value (repeatable)", false,
                                   "SECTION.KEY=VALUE", cmd);
  TCLAP::MultiArg<std::string> path("p", "plugin-path", "Extra plugin folder (repeatable)", false,
                                    "DIR", cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);

  IniConfig ini = IniConfig::fromFile(config.getValue());
  for (const auto& s : set.getValue()) {
    if (s.find('.') == std::string::npos || s.find('.') > s.find('='))
      throw ConfigError("--set " + s + ": expected section.key=value");
    ini.applyOverride(s);
  }
  const Params p = ini.resolve(kSection, kKeys, std::size(kKeys));

  // Zones and factors.
  const std::vector<double> zv = p.getDoubleList("zones");
  if (zv.empty() || zv.size() % 4 != 0)
    p.fail("zones", "expected four numbers per zone (x_min y_min x_max y_max), got " +
                        std::to_string(zv.size()));
  std::vector<Zone> zones;
  for (std::size_t i = 0; i < zv.size(); i += 4) {
    Zone z{zv[i], zv[i + 1], zv[i + 2], zv[i + 3]};
    if (!(z.x0 < z.x1 && z.y0 < z.y1))
      p.fail("zones", "zone " + std::to_string(i / 4 + 1) + " has x_min >= x_max or y_min >= y_max");
    zones.push_back(z);
  }
  const std::vector<double> factors = p.getDoubleList("factors");
  if (factors.empty()) p.fail("factors", "expected at least one factor");
  const bool touching = p.getString("zone_edges") == "touching";
  const bool odometry_cov = p.getString("zone_covariance") == "odometry";
  const OdometryNoiseModel odometry_model;

  // Plugins, and every section of the file accounted for.
  Registry reg;
  scanPlugins(reg, path.getValue());
  const std::string backend_name = p.getString("backend");
  const auto binfo = reg.find(backend_name, PluginKind::Backend);
  std::vector<PlannerSlot> slots;
  for (const auto& name : splitNames(p.getString("planners"))) {
    PlannerSlot s;
    s.name = name;
    s.info = reg.find(name, PluginKind::Planner);
    s.params = ini.resolve(name, s.info->descriptor->keys, s.info->descriptor->num_keys);
    slots.push_back(std::move(s));
  }
  if (slots.empty()) p.fail("planners", "no planner named");
  {
    std::vector<std::string> known{kSection, lowercase(backend_name)};
    for (const auto& s : slots) known.push_back(lowercase(s.name));
    for (const auto& sec : ini.sections())
      if (std::find(known.begin(), known.end(), sec) == known.end()) {
        std::string msg = ini.where(sec) + ": unknown section [" + sec +
                          "] (sections: plan_eval, the backend's and the planners')";
        const std::string hint = didYouMean(sec, known);
        if (!hint.empty()) msg += " (did you mean [" + hint + "]?)";
        throw ConfigError(msg);
      }
  }
  const Params bparams =
      ini.resolve(backend_name, binfo->descriptor->keys, binfo->descriptor->num_keys);
  // The candidate search of the criterion planners (the first one's keys), to tell planner
  // errors from candidate sets without a path avoiding the zone.
  std::optional<eu::PathSearchOptions> search;
  std::string search_of;
  for (const auto& s : slots)
    if (s.params.has("k_paths")) {
      search = eu::pathSearchOptionsFrom(s.params);
      search_of = s.name;
      break;
    }

  const std::string out_dir = out_arg.getValue().empty() ? p.getString("out") : out_arg.getValue();
  std::filesystem::create_directories(out_dir);
  const std::string graph_file = p.getString("graph");
  const PoseGraph base = readG2o(graph_file);
  const std::size_t n = base.size();
  if (n < 2) throw InputError(graph_file + ": fewer than two nodes");
  const std::uint64_t seed = static_cast<std::uint64_t>(p.getInt("seed"));
  const std::size_t stride = static_cast<std::size_t>(p.getInt("pair_stride"));
  const double grid = p.getDouble("pair_grid");
  const std::size_t max_pairs = static_cast<std::size_t>(p.getInt("max_pairs"));
  const bool ordered = p.getBool("ordered");
  const std::size_t progress_every = static_cast<std::size_t>(p.getInt("progress_every"));

  // Every cross-covariance block: the planners' relocalization probability may ask for any
  // pair of nodes on a candidate path.
  std::vector<std::pair<NodeId, NodeId>> all_pairs;
  all_pairs.reserve(n * (n - 1) / 2);
  for (NodeId a = 0; a < n; ++a)
    for (NodeId b = a + 1; b < n; ++b) all_pairs.emplace_back(a, b);

  std::cerr << "plan-eval: " << graph_file << ": " << n << " nodes, " << base.edges.size()
            << " edges; " << zones.size() << " zone(s) x " << factors.size() << " factor(s); "
            << slots.size() << " planners\n";
  json jscen = json::array();
  const auto t_all = std::chrono::steady_clock::now();
  char letter = 'A';
  for (std::size_t zi = 0; zi < zones.size(); ++zi) {
    const Zone& zone = zones[zi];
    std::vector<char> in_zone(n, 0);
    std::size_t zone_nodes = 0;
    for (NodeId v = 0; v < n; ++v) zone_nodes += in_zone[v] = zone.contains(base.nodes[v].pose);
    if (zone_nodes == 0)
      p.fail("zones", "zone " + std::to_string(zi + 1) + " holds no node of the graph");

    // Start/goal pairs: outside the zone and joined by a path avoiding it (else no planner
    // could avoid it), the same for every factor of this zone.
    std::vector<NodeId> cand;
    std::set<std::pair<long, long>> cells;
    for (NodeId v = 0; v < n; v += static_cast<NodeId>(stride)) {
      if (in_zone[v]) continue;
      if (grid > 0) {
        const auto cell = std::make_pair(static_cast<long>(std::floor(base.nodes[v].pose.x() / grid)),
                                         static_cast<long>(std::floor(base.nodes[v].pose.y() / grid)));
        if (!cells.insert(cell).second) continue;
      }
      cand.push_back(v);
    }
    const std::vector<int> comp = componentsOutside(base, in_zone);
    std::vector<std::pair<NodeId, NodeId>> pairs;
    std::size_t unavoidable = 0;
    for (std::size_t i = 0; i < cand.size(); ++i)
      for (std::size_t j = i + 1; j < cand.size(); ++j) {
        if (comp[cand[i]] != comp[cand[j]]) {
          ++unavoidable;
          continue;
        }
        pairs.emplace_back(cand[i], cand[j]);
      }
    if (max_pairs > 0 && pairs.size() > max_pairs) {
      std::mt19937_64 rng(seed + zi);
      std::shuffle(pairs.begin(), pairs.end(), rng);
      pairs.resize(max_pairs);
      std::sort(pairs.begin(), pairs.end());
    }
    if (ordered) {
      const std::size_t m = pairs.size();
      for (std::size_t i = 0; i < m; ++i) pairs.emplace_back(pairs[i].second, pairs[i].first);
    }

    for (double factor : factors) {
      const std::string name(1, letter++);
      const auto t_scen = std::chrono::steady_clock::now();
      // The scenario's graph.
      PoseGraph g = base;
      g.edges.clear();
      std::size_t dropped = 0, scaled = 0;
      for (PoseEdge e : base.edges) {
        const bool a = e.from < n && in_zone[e.from], b = e.to < n && in_zone[e.to];
        const NodeId gap = e.from > e.to ? e.from - e.to : e.to - e.from;
        const bool closure = e.kind == EdgeKind::LoopClosure || gap > 1;
        if (p.getBool("drop_zone_loop_closures") && closure && (a || b)) {
          ++dropped;
          continue;
        }
        if (touching ? (a || b) : (a && b)) {
          if (odometry_cov)
            e.information = edgeInformation(e.mean, factor * odometry_model.covariance(e.mean),
                                            1e-12 * Eigen::Matrix3d::Identity());
          else
            e.information /= factor;
          ++scaled;
        }
        g.edges.push_back(e);
      }
      auto be = Registry::create<Backend>(binfo);
      logToStderr(*be, binfo->name());
      PluginContext bctx;
      bctx.seed = seed;
      be->configure(bparams, bctx);
      OptimizeReport opt;
      if (p.getBool("optimize")) opt = be->optimize(g);
      if (p.getBool("write_graphs"))
        writeG2o(g, (std::filesystem::path(out_dir) / ("scenario_" + name + ".g2o")).string());
      auto t0 = std::chrono::steady_clock::now();
      const Marginals marginals = be->marginals(g, all_pairs);
      const double marginals_s = secondsSince(t0);

      // No place recognition in the zone: the planners' recognition file, zone nodes at 0.
      const std::string rec_file =
          (std::filesystem::path(out_dir) / ("recognition_" + name + ".txt")).string();
      std::map<NodeId, double> zone_rec;
      for (NodeId v = 0; v < n; ++v)
        if (in_zone[v]) zone_rec[v] = 0;

      json jpl = json::object();
      struct Tally {
        std::size_t found = 0, errors = 0, not_found = 0;
        double time_s = 0, max_s = 0;
      };
      std::vector<Tally> tally(slots.size());
      for (std::size_t k = 0; k < slots.size(); ++k) {
        PlannerSlot& s = slots[k];
        Params params = s.params;
        if (params.has("p_recognition_file")) {
          std::map<NodeId, double> rec;
          const std::string user = params.getString("p_recognition_file");
          if (!user.empty()) {
            try {
              rec = eu::readRecognitionProbabilities(user);
            } catch (const InputError& e) {
              params.fail("p_recognition_file", e.what());
            }
          }
          for (const auto& [v, pr] : zone_rec) rec[v] = pr;
          std::ofstream f(rec_file);
          f << "# plan-eval scenario " << name << ": no place recognition in the zone\n";
          for (const auto& [v, pr] : rec) f << v << " " << pr << "\n";
          if (!f) throw Error(rec_file + ": cannot write");
          Params::Value val;
          val.text = rec_file;
          val.type = KeyType::Path;
          val.is_default = false;
          val.origin = "plan-eval";
          params.set("p_recognition_file", val);
        }
        s.planner = Registry::create<Planner>(s.info);
        s.planner->logging_enable_console_output = false;
        s.warnings = 0;
        s.first_warning.clear();
        s.planner->logRegisterCallback([&s](std::string_view msg, mrpt::system::VerbosityLevel lvl,
                                            std::string_view, const mrpt::Clock::time_point&) {
          if (lvl < mrpt::system::LVL_WARN) return;
          if (s.warnings++ == 0) s.first_warning = std::string(msg);
        });
        s.planner->setLoggerName(s.name);
        PluginContext ctx;
        ctx.seed = seed;
        s.planner->configure(params, ctx);
      }

      std::cerr << "[" << name << "] zone " << zi + 1 << " (" << zone.x0 << " " << zone.y0 << " "
                << zone.x1 << " " << zone.y1 << "): " << zone_nodes << " nodes; "
                << (odometry_cov ? "odometry " : "") << "covariance x" << factor << " on "
                << scaled << " edges, " << dropped
                << " loop closures dropped; " << pairs.size() << " pairs ("
                << unavoidable << " without a path avoiding the zone skipped); marginals "
                << std::setprecision(3) << marginals_s << " s\n";
      json jpairs = json::array();
      std::size_t no_avoiding_candidate = 0;
      double search_s = 0;
      for (std::size_t pi = 0; pi < pairs.size(); ++pi) {
        PlanRequest req;
        req.graph = &g;
        req.marginals = &marginals;
        req.start = pairs[pi].first;
        req.goal = pairs[pi].second;
        json jp{{"start", req.start}, {"goal", req.goal}};
        if (search) {
          t0 = std::chrono::steady_clock::now();
          const auto cands = eu::searchPaths(g, req.start, req.goal, *search);
          search_s += secondsSince(t0);
          const bool avoids = std::any_of(cands.paths.begin(), cands.paths.end(), [&](const auto& c) {
            return std::none_of(c.begin(), c.end(), [&](NodeId v) { return in_zone[v] != 0; });
          });
          no_avoiding_candidate += !avoids;
          jp["candidates"] = cands.paths.size();
          jp["avoiding_candidate"] = avoids;
        }
        for (std::size_t k = 0; k < slots.size(); ++k) {
          t0 = std::chrono::steady_clock::now();
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
          const bool crossed = std::any_of(r.nodes.begin(), r.nodes.end(),
                                           [&](NodeId v) { return in_zone[v] != 0; });
          t.errors += crossed;
          jp[slots[k].name] = {{"crosses", crossed}, {"cost", r.cost}, {"nodes", r.nodes.size()},
                               {"time_s", dt}};
        }
        jpairs.push_back(std::move(jp));
        if ((progress_every > 0 && (pi + 1) % progress_every == 0) || pi + 1 == pairs.size()) {
          std::cerr << "[" << name << "] " << pi + 1 << "/" << pairs.size() << " pairs, "
                    << std::setprecision(4) << secondsSince(t_scen) << " s; no avoiding candidate "
                    << no_avoiding_candidate << "; errors:";
          for (std::size_t k = 0; k < slots.size(); ++k)
            std::cerr << " " << slots[k].name << " " << tally[k].errors;
          std::cerr << "\n";
        }
      }
      json js{{"name", name},
              {"zone", {zone.x0, zone.y0, zone.x1, zone.y1}},
              {"zone_index", zi + 1},
              {"factor", factor},
              {"zone_nodes", zone_nodes},
              {"scaled_edges", scaled},
              {"dropped_loop_closures", dropped},
              {"pairs", pairs.size()},
              {"pairs_without_avoiding_path", unavoidable},
              {"pairs_without_avoiding_candidate", no_avoiding_candidate},
              {"candidate_search_of", search_of},
              {"candidate_search_time_s", search_s},
              {"optimize", {{"initial_chi2", opt.initial_chi2},
                            {"final_chi2", opt.final_chi2},
                            {"iterations", opt.iterations}}},
              {"marginals_time_s", marginals_s},
              {"time_s", secondsSince(t_scen)}};
      for (std::size_t k = 0; k < slots.size(); ++k) {
        const Tally& t = tally[k];
        js["planners"][slots[k].name] = {
            {"errors", t.errors},
            {"found", t.found},
            {"not_found", t.not_found},
            {"error_rate", t.found ? static_cast<double>(t.errors) / t.found : 0.0},
            {"sweep_time_s", t.time_s},
            {"mean_time_s", pairs.empty() ? 0.0 : t.time_s / pairs.size()},
            {"max_time_s", t.max_s},
            {"warnings", slots[k].warnings},
            {"first_warning", slots[k].first_warning}};
      }
      js["pair_results"] = std::move(jpairs);
      jscen.push_back(std::move(js));
    }
  }

  // The tables.
  std::ostringstream md;
  md << "# Unreliable-path avoidance (thesis Table 3.1 protocol)\n\n"
     << "Graph: `" << graph_file << "` (" << n << " nodes, " << base.edges.size()
     << " edges). Config: `" << config.getValue() << "`. Error rate: share of the start/goal "
     << "pairs whose chosen path crosses the zone (in parentheses: the count). \"no avoiding "
     << "candidate\": pairs for which no candidate path of the criterion planners' search ("
     << (search_of.empty() ? std::string("none") : search_of) << "'s keys) avoids the zone, so "
     << "that every criterion planner must cross it.\n\n| scenario | zone | factor | pairs | "
     << "no avoiding candidate |";
  for (const auto& s : slots) md << " " << s.name << " |";
  md << "\n|---|---|---:|---:|---:|";
  for (std::size_t k = 0; k < slots.size(); ++k) md << "---:|";
  md << "\n";
  for (const auto& js : jscen) {
    const auto z = js["zone"];
    md << "| " << js["name"].get<std::string>() << " | " << js["zone_index"].get<int>() << ": ("
       << z[0].get<double>() << ", " << z[1].get<double>() << ")-(" << z[2].get<double>() << ", "
       << z[3].get<double>() << ") | x" << js["factor"].get<double>() << " | "
       << js["pairs"].get<std::size_t>() << " | "
       << js["pairs_without_avoiding_candidate"].get<std::size_t>() << " |";
    for (const auto& s : slots) {
      const auto& jp = js["planners"][s.name];
      md << " " << percent(jp["error_rate"].get<double>()) << " (" << jp["errors"].get<std::size_t>()
         << ")";
      if (jp["not_found"].get<std::size_t>()) md << ", " << jp["not_found"].get<std::size_t>() << " not found";
      md << " |";
    }
    md << "\n";
  }
  md << "\nPlanning time of the sweep (all pairs of the scenario) [s], mean / max per pair [ms]:\n\n"
     << "| scenario |";
  for (const auto& s : slots) md << " " << s.name << " |";
  md << "\n|---|";
  for (std::size_t k = 0; k < slots.size(); ++k) md << "---:|";
  md << "\n";
  for (const auto& js : jscen) {
    md << "| " << js["name"].get<std::string>() << " |";
    for (const auto& s : slots) {
      const auto& jp = js["planners"][s.name];
      md << std::fixed << std::setprecision(2) << " " << jp["sweep_time_s"].get<double>() << " ("
         << std::setprecision(1) << 1000 * jp["mean_time_s"].get<double>() << " / "
         << 1000 * jp["max_time_s"].get<double>() << ") |" << std::defaultfloat;
    }
    md << "\n";
  }
  bool any_warning = false;
  for (const auto& js : jscen)
    for (const auto& s : slots)
      if (js["planners"][s.name]["warnings"].get<std::size_t>()) {
        if (!any_warning) md << "\nPlanner warnings (count, first):\n\n";
        any_warning = true;
        md << "- " << js["name"].get<std::string>() << " " << s.name << ": "
           << js["planners"][s.name]["warnings"].get<std::size_t>() << ", "
           << js["planners"][s.name]["first_warning"].get<std::string>() << "\n";
      }
  const double total_s = secondsSince(t_all);
  md << "\nTotal " << std::setprecision(4) << total_s << " s.\n";
  json j{{"graph", graph_file},
         {"config", config.getValue()},
         {"nodes", n},
         {"edges", base.edges.size()},
         {"planners", json::array()},
         {"scenarios", jscen},
         {"time_s", total_s}};
  for (const auto& s : slots) j["planners"].push_back(s.name);
  const std::string md_file = (std::filesystem::path(out_dir) / "plan_eval.md").string();
  const std::string json_file = (std::filesystem::path(out_dir) / "plan_eval.json").string();
  {
    std::ofstream f(md_file);
    f << md.str();
    if (!f) throw Error(md_file + ": cannot write");
  }
  {
    std::ofstream f(json_file);
    f << j.dump(1) << "\n";
    if (!f) throw Error(json_file + ": cannot write");
  }
  std::cout << md.str() << "\nwrote " << md_file << " and " << json_file << "\n";
  return kOk;
}

}  // namespace asf::app
