#include <asf/coverage.h>
#include <asf/errors.h>
#include <asf/map3d.h>
#include <asf/pipeline.h>
#include <asf/run_report.h>
#include <asf/text.h>
#include <asf/trajectory_eval.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <set>
#include <sstream>

#include "recorder.h"

namespace asf {

namespace fs = std::filesystem;

namespace {

const KeySpec kPipelineKeys[] = {
    keyString("source", nullptr, "Source plugin: simulator or log (`asf plugins` lists them)"),
    keyString("frontend", nullptr, "Front-end plugin: frames -> pose-graph nodes and edges"),
    keyString("backend", "", "Back-end plugin: optimizes the graph, gives marginals (empty: none)"),
    keyString("segmenter", "", "Segmenter plugin: map -> regions (empty: none)"),
    keyString("planner", "", "Planner plugin: path between pose-graph nodes (empty: none)"),
    keyString("policy", "", "Exploration policy plugin; needs an active source (empty: none)"),
    keyInt("seed", "1", "Seed of every random draw of the run (each plugin gets its own stream)",
           0),
    keyString("plugin_path", "",
              "Extra plugin folders, ':'-separated, relative to this INI file's folder"),
    keyInt("max_steps", "100000", "Stop after this many source steps (0: no limit)", 0),
    keyDouble("max_distance", "0", "Stop after travelling this far [m] (0: no limit)", 0),
    keyInt("optimize_every", "1", "Run the back-end after this many new nodes", 1),
    keyBool("marginals", "true", "Recover marginal covariances after each optimization"),
    keyInt("segment_every", "1", "Segment every n-th map version", 1),
    keyInt("max_failed_goals", "50",
           "Stop when the policy's goals failed (unreachable/blocked) this many times in a row", 1),
    keyInt("max_idle_decisions", "200",
           "Stop when this many decisions in a row moved the robot less than 0.1 m in total "
           "(a policy going round in circles)",
           1),
    keyBool("map3d", "false",
            "Build the 3D map ([map3d]) from the frames' 3D observations at the keyframes; "
            "writes map3d.bt, map3d.ot, map3d.json, map3d_grid.png"),
    keyEnum("navigation_map", "scan2d", "scan2d|map3d|merged",
            "Grid the policy, navigation, segmenter and coverage use: the 2D scans' ([map]), "
            "the 3D map's projection, or both merged (an obstacle in either is one)"),
    keyDouble("progress_interval", "2.0", "Seconds between progress lines (0: none)", 0),
    keyDoubleList("snapshot_distances", "",
                  "Distances driven [m] at which the map, its regions and the topological graph "
                  "are saved to snapshots/ (thesis fig. 6.1; empty: none)",
                  0),
    keyEnum("verbosity", "INFO", "DEBUG|INFO|WARN|ERROR", "Log level of the host and plugins"),
};

const char* const kSlots[] = {"source", "frontend", "backend", "segmenter", "planner", "policy"};
const PluginKind kSlotKinds[] = {PluginKind::Source,    PluginKind::Frontend, PluginKind::Backend,
                                 PluginKind::Segmenter, PluginKind::Planner,  PluginKind::Policy};

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

mrpt::system::VerbosityLevel parseVerbosity(const std::string& s) {
  if (s == "DEBUG") return mrpt::system::LVL_DEBUG;
  if (s == "WARN") return mrpt::system::LVL_WARN;
  if (s == "ERROR") return mrpt::system::LVL_ERROR;
  return mrpt::system::LVL_INFO;
}

void appendSection(std::ostringstream& os, const std::string& name, const Params& p,
                   const KeySpec* keys, std::size_t n, const std::string& title) {
  os << "\n; " << title << "\n[" << name << "]\n";
  for (std::size_t i = 0; i < n; ++i) {
    const KeySpec& k = keys[i];
    if (!p.has(k.name)) continue;
    os << "; " << k.doc << " (" << keyTypeName(k.type);
    if (k.type == KeyType::Enum && k.choices) os << ": " << k.choices;
    if (!std::isinf(k.min) || !std::isinf(k.max))
      os << ", range [" << k.min << ", " << k.max << "]";
    os << (p.isDefault(k.name) ? ", default" : ", set") << ")\n";
    os << k.name << " = " << p.getString(k.name) << "\n";
  }
}

}  // namespace

const KeySpec* pipelineKeys(std::size_t& n) {
  n = std::size(kPipelineKeys);
  return kPipelineKeys;
}

std::vector<FrameworkSection> frameworkSections() {
  std::vector<FrameworkSection> v;
  std::size_t n;
  const KeySpec* k = pipelineKeys(n);
  v.push_back({"pipeline", k, n});
  k = MapBuilder::keys(n);
  v.push_back({"map", k, n});
  k = TopoBuilder::keys(n);
  v.push_back({"topology", k, n});
  k = Map3d::keys(n);
  v.push_back({"map3d", k, n});
  return v;
}

std::string ResolvedConfig::toIni() const {
  std::ostringstream os;
  os << "; asf configuration, resolved: every key with its value or default.\n";
  const auto fw = frameworkSections();
  appendSection(os, "pipeline", pipeline, fw[0].keys, fw[0].num_keys, "framework: the pipeline");
  appendSection(os, "map", map, fw[1].keys, fw[1].num_keys, "framework: occupancy grid builder");
  appendSection(os, "topology", topology, fw[2].keys, fw[2].num_keys,
                "framework: topological graph builder");
  appendSection(os, "map3d", map3d, fw[3].keys, fw[3].num_keys,
                "framework: 3D map (OctoMap), used with [pipeline] map3d = true");
  for (const char* slot : kSlots) {
    auto it = slots.find(slot);
    if (it == slots.end()) continue;
    const PluginInfo& info = *it->second;
    const auto& d = *info.descriptor;
    appendSection(os, d.name, plugin_params.at(d.name), d.keys, d.num_keys,
                  std::string(slot) + " plugin '" + d.name + "' " + d.version + ": " +
                      d.description + " (" + info.file + ")");
  }
  return os.str();
}

ResolvedConfig resolveConfig(const IniConfig& ini, Registry& registry) {
  ResolvedConfig rc;
  std::vector<std::string> errors;
  auto attempt = [&](auto&& fn) {
    try {
      fn();
    } catch (const Error& e) {
      errors.push_back(e.what());
    }
  };
  const auto fw = frameworkSections();
  attempt([&] { rc.pipeline = ini.resolve("pipeline", fw[0].keys, fw[0].num_keys); });
  attempt([&] { rc.map = ini.resolve("map", fw[1].keys, fw[1].num_keys); });
  attempt([&] { rc.topology = ini.resolve("topology", fw[2].keys, fw[2].num_keys); });
  attempt([&] { rc.map3d = ini.resolve("map3d", fw[3].keys, fw[3].num_keys); });
  attempt([&] {
    if (rc.pipeline.has("navigation_map") && rc.pipeline.getString("navigation_map") != "scan2d" &&
        !rc.pipeline.getBool("map3d"))
      rc.pipeline.fail("navigation_map", "'" + rc.pipeline.getString("navigation_map") +
                                             "' needs the 3D map: set [pipeline] map3d = true");
  });
  if (!ini.hasSection("pipeline"))
    errors.insert(errors.begin(), ini.fileName() + ": no [pipeline] section");

  for (const auto& d : Registry::defaultSearchPath()) registry.scanDirectory(d);
  // Slots and plugin_path are read from the INI directly, so their errors are reported
  // even when another [pipeline] key is invalid.
  {
    std::stringstream ss(ini.get("pipeline", "plugin_path"));
    std::string d;
    while (std::getline(ss, d, ':')) {
      if (d.empty()) continue;
      fs::path p(d);
      if (p.is_relative() && !ini.baseDir().empty()) p = fs::path(ini.baseDir()) / p;
      if (!fs::is_directory(p))
        errors.push_back(ini.where("pipeline", "plugin_path") + ": [pipeline] plugin_path: '" +
                         p.string() + "' is not a folder");
      registry.scanDirectory(p.string());
    }
  }

  for (std::size_t i = 0; i < std::size(kSlots); ++i) {
    const std::string name = ini.get("pipeline", kSlots[i]);
    if (name.empty()) continue;
    try {
      rc.slots[kSlots[i]] = registry.find(name, kSlotKinds[i]);
    } catch (const PluginError& e) {
      errors.push_back(ini.where("pipeline", kSlots[i]) + ": [pipeline] " + kSlots[i] + ": " +
                       e.what());
    }
  }
  if (rc.slots.count("policy") && rc.slots.count("source") && !rc.slots.count("segmenter"))
    rc.warnings.push_back(
        "[pipeline] a policy without a segmenter sees a topological graph "
        "with no regions");

  std::vector<std::string> known_sections;
  for (const auto& s : fw) known_sections.push_back(s.name);
  for (const auto& p : registry.plugins()) known_sections.push_back(p->name());
  for (const auto& section : ini.sections()) {
    bool framework = false;
    for (const auto& s : fw) framework = framework || section == s.name;
    if (framework) continue;
    bool selected = false;
    for (const auto& [slot, info] : rc.slots) selected = selected || info->name() == section;
    if (selected) continue;
    std::shared_ptr<const PluginInfo> other;
    try {
      other = registry.find(section);
    } catch (const PluginError&) {
    }
    if (other) {
      // Validated all the same, so a typo waits for no one to switch plugins.
      attempt([&] { ini.resolve(section, other->descriptor->keys, other->descriptor->num_keys); });
      rc.warnings.push_back(ini.where(section) + ": [" + section + "] configures plugin '" +
                            section + "', which this pipeline does not use");
      continue;
    }
    errors.push_back(ini.unknownSection(
        section, known_sections,
        "sections are [pipeline], [map], [topology], [map3d] and one per plugin, named after "
        "it"));
  }
  for (const auto& [slot, info] : rc.slots) {
    attempt([&, &info = info] {
      rc.plugin_params[info->name()] =
          ini.resolve(info->name(), info->descriptor->keys, info->descriptor->num_keys);
    });
  }
  if (!errors.empty()) {
    std::string msg;
    for (const auto& e : errors) msg += (msg.empty() ? "" : "\n") + e;
    throw ConfigError(msg);
  }
  return rc;
}

struct Pipeline::Impl : public mrpt::system::COutputLogger {
  Impl() : COutputLogger("asf") {}
  ResolvedConfig cfg;
  std::string out_dir;
  PluginHandle<Source> source;
  PluginHandle<Frontend> frontend;
  PluginHandle<Backend> backend;
  PluginHandle<Segmenter> segmenter;
  PluginHandle<Planner> planner;
  PluginHandle<Policy> policy;
  MapBuilder map;
  TopoBuilder topo;
  PoseGraph graph;
  Marginals marginals;
  Segmentation seg;
  std::vector<mrpt::poses::CPose2D> path;
  std::shared_ptr<const WorldTruth> world;
  std::unique_ptr<CoverageMeter> coverage;
  /// Free area and coverage of navMap(), updated with every version (O(changed cells)).
  MapAreaTracker area;
  TopoGraph world_topo;  ///< of the true world, map frame (offline baselines)
  bool have_world_topo = false;

  // 3D map ([pipeline] map3d): keyframe ids are node * kObsPerNode + index in the frame.
  static constexpr Map3d::KeyframeId kObsPerNode = 16;
  std::unique_ptr<Map3d> map3d;
  std::string nav_kind = "scan2d";             ///< [pipeline] navigation_map
  GridMap projected;                           ///< last projection of map3d
  GridMap merged;                              ///< navigation_map = merged
  std::uint64_t projected_from = 0;            ///< map3d version of `projected`
  std::uint64_t merged_2d = 0, merged_3d = 0;  ///< input versions of `merged`
  std::uint64_t nav_version = 0;
  struct Map3dCounts {
    std::size_t keyframes = 0, observations = 0, not_keyframes = 0, unsupported = 0, over_cap = 0;
    double insert_ms = 0, project_ms = 0, rebuild_ms = 0;
  } m3;
  std::set<std::string> warned_3d;
  std::vector<std::pair<Map3d::KeyframeId, NodeId>> keyframes3d;  ///< in id order

  /// The grid the policy, navigation, segmenter and coverage use.
  const GridMap& navMap() const {
    if (nav_kind == "map3d") return projected;
    if (nav_kind == "merged") return merged;
    return map.map();
  }
  void addKeyframes3d(const SensorFrame& f, std::size_t nodes_before);
  void followKeyframes3d();
  /// Brings the projection (and the merged grid) up to date; true if navMap() changed.
  bool updateNavMap(bool map2d_changed);

  /// The pipeline's segmenter, a second instance, run once on the true world.
  void segmentWorld();

  template <class T>
  void make(const char* slot, int index, PluginHandle<T>& h) {
    auto it = cfg.slots.find(slot);
    if (it == cfg.slots.end()) return;
    h = Registry::create<T>(it->second);
    h->setMinLoggingLevel(getMinLoggingLevel());
    PluginContext ctx;
    ctx.seed = splitmix64(static_cast<std::uint64_t>(cfg.pipeline.getInt("seed")) * 8 + index);
    ctx.output_dir = out_dir;
    try {
      h->configure(cfg.plugin_params.at(it->second->name()), ctx);
    } catch (const ConfigError&) {
      throw;
    } catch (const std::exception& e) {
      throw PluginError(it->second->file + ": plugin '" + it->second->name() +
                        "': configure() failed: " + e.what());
    }
  }
};

Pipeline::Pipeline(const ResolvedConfig& cfg, const std::string& out_dir)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.cfg = cfg;
  m.out_dir = out_dir;
  // Plugins may write into the output folder from configure() on (e.g. a simulator's log).
  if (!out_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    if (ec) throw Error(out_dir + ": cannot create the output folder: " + ec.message());
  }
  m.setMinLoggingLevel(parseVerbosity(cfg.pipeline.getString("verbosity")));
  for (const auto& w : cfg.warnings) m.logStr(mrpt::system::LVL_WARN, w);
  m.make("source", 0, m.source);
  m.make("frontend", 1, m.frontend);
  m.make("backend", 2, m.backend);
  m.make("segmenter", 3, m.segmenter);
  m.make("planner", 4, m.planner);
  m.make("policy", 5, m.policy);
  if (!m.source || !m.frontend) throw ConfigError("[pipeline] needs a source and a frontend");
  m.map.configure(cfg.map);
  m.topo.configure(cfg.topology);
  if (cfg.pipeline.getBool("map3d")) {
    m.map3d = std::make_unique<Map3d>();
    m.map3d->configure(cfg.map3d);
  }
  m.nav_kind = cfg.pipeline.getString("navigation_map");
  m.world = m.source->worldTruth();
  if (m.world && m.world->grid) {
    m.coverage = std::make_unique<CoverageMeter>(*m.world);
    m.area = MapAreaTracker(m.coverage.get());
    if (m.policy && m.segmenter) m.segmentWorld();
  }
  if (m.policy && !m.source->isActive())
    m.logStr(mrpt::system::LVL_WARN,
             "the policy is ignored: source '" + cfg.slots.at("source")->name() + "' is passive");
}

Pipeline::~Pipeline() = default;

void Pipeline::Impl::segmentWorld() {
  PluginHandle<Segmenter> seg_world;
  make("segmenter", 3, seg_world);
  GridMap wm;
  wm.grid = world->grid;
  wm.version = 1;
  const Segmentation ws = seg_world->segment(wm, nullptr);
  TopoBuilder tb;
  tb.configure(cfg.topology);
  tb.update(ws, wm);
  // World frame -> map frame, so a baseline's goals are in the frame navigation uses.
  const mrpt::poses::CPose2D inv = -world->map_origin;
  auto toMap = [&](Point2& p) { inv.composePoint(p.x, p.y, p.x, p.y); };
  world_topo = tb.graph();
  for (auto& n : world_topo.nodes) toMap(n.centroid);
  for (auto& e : world_topo.edges) {
    toMap(e.midpoint);
    for (auto& b : e.border) toMap(b);
  }
  world_topo.current = ws.labels.atPoint(world->map_origin.x(), world->map_origin.y());
  have_world_topo = true;
  logStr(mrpt::system::LVL_INFO, "true world: " + std::to_string(ws.regions.size()) + " regions, " +
                                     std::to_string(world_topo.edges.size()) +
                                     " edges, reachable free area " +
                                     std::to_string(coverage->reachableArea()) + " m^2");
}

namespace {

using Clock = std::chrono::steady_clock;
}  // namespace

void Pipeline::Impl::addKeyframes3d(const SensorFrame& f, std::size_t nodes_before) {
  if (!map3d || f.observations3d.empty()) return;
  if (graph.size() <= nodes_before) {
    m3.not_keyframes += f.observations3d.size();
    return;
  }
  const auto t0 = Clock::now();
  const PoseNode& node = graph.nodes.back();  // the front-end's node for this frame
  Map3d::KeyframeId k = 0;
  for (const auto& o : f.observations3d) {
    if (!o) continue;
    ++m3.observations;
    if (k == kObsPerNode) {
      ++m3.over_cap;
      continue;
    }
    std::vector<Eigen::Vector3f> pts;
    mrpt::poses::CPose3D sensor;
    std::string why;
    if (!Map3d::observationPoints(*o, pts, sensor, &why)) {
      ++m3.unsupported;
      if (warned_3d.insert(why).second)
        logStr(mrpt::system::LVL_WARN,
               "map3d: observation '" + o->sensorLabel + "' not used: " + why + " (warned once)");
      continue;
    }
    const Map3d::KeyframeId id = node.id * kObsPerNode + k++;
    map3d->addKeyframe(id, node.pose, sensor, std::move(pts));
    keyframes3d.emplace_back(id, node.id);
    ++m3.keyframes;
  }
  m3.insert_ms += msSince(t0);
}

void Pipeline::Impl::followKeyframes3d() {
  if (!map3d || map3d->numKeyframes() == 0) return;
  std::map<Map3d::KeyframeId, mrpt::poses::CPose2D> poses;
  for (const auto& [id, node] : keyframes3d)
    poses.emplace_hint(poses.end(), id, graph.nodes[node].pose);
  map3d->updateKeyframePoses(poses);
}

bool Pipeline::Impl::updateNavMap(bool map2d_changed) {
  if (!map3d) return map2d_changed;
  if (map3d->rebuilding()) {
    const auto t0 = Clock::now();
    map3d->rebuildStep();
    m3.rebuild_ms += msSince(t0);
  }
  bool projected_changed = false;
  if (map3d->version() != projected_from) {
    const auto t0 = Clock::now();
    GridMap p = map3d->project();
    m3.project_ms += msSince(t0);
    projected_from = map3d->version();
    if (p.grid) {
      p.version = projected.version + 1;
      p.rebuilt = p.rebuilt || projected.version == 0;
      projected = std::move(p);
      projected_changed = true;
    }
  }
  if (nav_kind == "map3d") return projected_changed;
  if (nav_kind != "merged") return map2d_changed;
  const GridMap& m2 = map.map();
  if (!m2.grid || !projected.grid) {
    // One map alone: it is the merged one until the other exists.
    const GridMap& only = m2.grid ? m2 : projected;
    if (!only.grid || (only.version == (m2.grid ? merged_2d : merged_3d))) return false;
    (m2.grid ? merged_2d : merged_3d) = only.version;
    const std::uint64_t v = merged.version + 1;
    merged = only;
    merged.version = v;
    merged.rebuilt = true;
    return true;
  }
  if (m2.version == merged_2d && projected.version == merged_3d) return false;
  const bool whole = projected.version != merged_3d || m2.rebuilt;
  GridMap g;
  g.grid = mergeOccupancy(*m2.grid, *projected.grid);
  g.version = merged.version + 1;
  g.rebuilt = whole;
  if (whole)
    g.changed = {g.grid->getXMin(), g.grid->getYMin(), g.grid->getXMax(), g.grid->getYMax()};
  else
    g.changed = m2.changed;
  merged_2d = m2.version;
  merged_3d = projected.version;
  merged = std::move(g);
  return true;
}

std::vector<std::string> Pipeline::outputFiles() {
  return {"config.ini",    "trajectory.csv", "timeseries.csv", "decisions.csv", "graph.g2o",
          "keyframes.txt", "map.png",        "regions.png",    "occupancy.png", "occupancy.yaml",
          "topology.json", "topology.svg",   "summary.json",   "progress.json", "report.html"};
}

RunSummary Pipeline::run(const std::atomic<bool>* stop) {
  Impl& m = *impl_;
  using Clock = std::chrono::steady_clock;
  const auto t_start = Clock::now();
  auto last_progress = t_start;
  Recorder rec(m.out_dir, m.cfg);
  RunSummary sum;

  const Params& P = m.cfg.pipeline;
  const long max_steps = static_cast<long>(P.getInt("max_steps"));
  const double max_distance = P.getDouble("max_distance");
  const long optimize_every = static_cast<long>(P.getInt("optimize_every"));
  const bool want_marginals = P.getBool("marginals");
  const long segment_every = static_cast<long>(P.getInt("segment_every"));
  const int max_failed = static_cast<int>(P.getInt("max_failed_goals"));
  const double progress_interval = P.getDouble("progress_interval");
  std::vector<double> snapshots = P.getDoubleList("snapshot_distances");
  std::sort(snapshots.begin(), snapshots.end());
  std::size_t next_snapshot = 0;
  const bool exploring = m.policy && m.source->isActive();

  std::optional<mrpt::poses::CPose2D> gt0, last_truth;
  mrpt::poses::CPose2D last_est;
  double err_sum = 0, t0 = 0, now_t = 0;
  long err_n = 0, nodes_since_opt = 0;
  int failed_in_row = 0;
  const int max_idle = static_cast<int>(P.getInt("max_idle_decisions"));
  int idle_decisions = 0;
  double idle_since_distance = 0;
  Goal last_goal;
  bool have_goal = false;
  // Compute time per stage since the last timeseries row, and per call for the summary.
  struct StageMs {
    double frontend = 0, backend = 0, map = 0, segment = 0, policy = 0;
  } stage;
  std::vector<double> decision_ms, segment_ms;
  SegmentationLog seg_log;
  auto msSince = [](Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
  };
  auto loopClosures = [&] {
    return static_cast<std::size_t>(
        std::count_if(m.graph.edges.begin(), m.graph.edges.end(),
                      [](const PoseEdge& e) { return e.kind == EdgeKind::LoopClosure; }));
  };
  double last_coverage = -1;
  auto seriesRow = [&](double pose_error) {
    Recorder::SeriesRow r;
    r.step = sum.steps;
    r.time = now_t;
    r.distance = sum.distance_m;
    const auto t_area = Clock::now();
    m.area.update(m.navMap());
    stage.map += msSince(t_area);
    if (m.coverage) last_coverage = r.coverage = m.area.coverage();
    r.explored_area = m.area.freeArea();
    r.pose_error = pose_error;
    r.loop_closures = loopClosures();
    r.nodes = m.graph.size();
    r.edges = m.graph.edges.size();
    r.regions = m.seg.regions.size();
    r.decisions = sum.decisions;
    r.ms = {stage.frontend, stage.backend, stage.map, stage.segment, stage.policy};
    r.segmentations = seg_log.total;
    r.incremental_segmentations = seg_log.incremental;
    r.changed_cells = seg_log.takeChangedSinceRow();
    rec.series(r);
    stage = {};
  };

  auto progress = [&](bool force) {
    const auto now = Clock::now();
    if (!force && (progress_interval <= 0 ||
                   std::chrono::duration<double>(now - last_progress).count() < progress_interval))
      return;
    last_progress = now;
    std::ostringstream os;
    os << std::fixed << std::setprecision(2) << "step " << sum.steps << "  dist " << sum.distance_m
       << " m  nodes " << m.graph.size() << "  edges " << m.graph.edges.size() << "  regions "
       << m.seg.regions.size() << "  decisions " << sum.decisions;
    if (last_coverage >= 0)
      os << "  coverage " << std::setprecision(1) << 100 * last_coverage << "%"
         << std::setprecision(2);
    if (err_n)
      os << "  pose error "
         << std::hypot(last_truth->x() - last_est.x(), last_truth->y() - last_est.y()) << " m";
    os << "  (" << std::setprecision(1) << std::chrono::duration<double>(now - t_start).count()
       << " s)";
    m.logStr(mrpt::system::LVL_INFO, os.str());
  };

  auto body = [&] {
    for (;;) {
      if (stop && stop->load()) {
        sum.stop_reason = "interrupted";
        break;
      }
      if (max_steps > 0 && sum.steps >= max_steps) {
        sum.stop_reason = "step budget (" + std::to_string(max_steps) + ") spent";
        break;
      }
      if (max_distance > 0 && sum.distance_m >= max_distance) {
        sum.stop_reason = "distance budget spent";
        break;
      }
      if (exploring && m.source->status() != NavStatus::Moving) {
        const NavStatus st = have_goal ? m.source->status() : NavStatus::Idle;
        failed_in_row =
            (st == NavStatus::Unreachable || st == NavStatus::Blocked) ? failed_in_row + 1 : 0;
        if (failed_in_row >= max_failed) {
          sum.stop_reason =
              "the policy's last " + std::to_string(failed_in_row) + " goals failed; giving up";
          break;
        }
        // Counts the decisions since the robot last moved 0.1 m (the previous one included).
        if (sum.distance_m - idle_since_distance >= 0.1) {
          idle_since_distance = sum.distance_m;
          idle_decisions = 0;
        } else if (sum.decisions > 0 && ++idle_decisions >= max_idle) {
          sum.stop_reason = "no progress: the policy's last " + std::to_string(idle_decisions) +
                            " decisions moved the robot less than 0.1 m";
          break;
        }
        ExplorationState s;
        s.topo = &m.topo.graph();
        s.robot = m.frontend->currentPose(m.graph);
        s.map = m.navMap().version ? &m.navMap() : nullptr;
        s.graph = &m.graph;
        s.time = now_t;
        s.last_status = st;
        s.last_goal = last_goal;
        s.segmentation = m.seg.regions.empty() ? nullptr : &m.seg;
        s.world_topo = m.have_world_topo ? &m.world_topo : nullptr;
        const auto t_dec = Clock::now();
        const Decision d = m.policy->decide(s);
        const double dec_ms = msSince(t_dec);
        stage.policy += dec_ms;
        decision_ms.push_back(dec_ms);
        ++sum.decisions;
        rec.decision(sum.steps, s.time, d, st);
        if (d.type == Decision::Type::Done) {
          sum.finished = true;
          sum.stop_reason = "policy done: " + d.reason;
          break;
        }
        if (!std::isfinite(d.goal.x) || !std::isfinite(d.goal.y))
          throw Error("policy '" + m.cfg.slots.at("policy")->name() +
                      "' returned a non-finite goal");
        NavigationContext ctx;
        ctx.robot_estimate = s.robot;
        ctx.map = s.map;
        m.logStr(mrpt::system::LVL_DEBUG, "goal (" + std::to_string(d.goal.x) + ", " +
                                              std::to_string(d.goal.y) + "): " + d.reason);
        m.source->navigate(d.goal, ctx);
        last_goal = d.goal;
        have_goal = true;
      }
      std::optional<SensorFrame> frame = m.source->next();
      if (!frame) {
        sum.finished = !exploring;
        sum.stop_reason = "source ended";
        break;
      }
      if (sum.steps == 0) t0 = frame->timestamp;
      ++sum.steps;
      now_t = frame->timestamp - t0;
      auto t_stage = Clock::now();
      const std::size_t nodes_before = m.graph.size();
      const bool changed = m.frontend->process(*frame, m.graph, m.marginals);
      stage.frontend += msSince(t_stage);
      t_stage = Clock::now();
      m.addKeyframes3d(*frame, nodes_before);
      stage.map += msSince(t_stage);
      if (changed) ++nodes_since_opt;
      if (changed && m.backend && nodes_since_opt >= optimize_every) {
        t_stage = Clock::now();
        nodes_since_opt = 0;
        m.backend->optimize(m.graph);
        if (want_marginals) m.marginals = m.backend->marginals(m.graph);
        m.marginals.graph_revision = m.graph.revision;
        stage.backend += msSince(t_stage);
        m.followKeyframes3d();
      }
      bool map_changed = false;
      t_stage = Clock::now();
      if (changed) map_changed = m.map.update(m.graph);
      map_changed = m.updateNavMap(map_changed);
      if (map_changed) m.area.update(m.navMap());  // every version: the change box holds
      stage.map += msSince(t_stage);
      if (map_changed && m.segmenter && m.navMap().version % segment_every == 0) {
        t_stage = Clock::now();
        m.seg = m.segmenter->segment(m.navMap(), m.seg.regions.empty() ? nullptr : &m.seg);
        m.seg.map_version = m.navMap().version;
        m.topo.update(m.seg, m.navMap(), &m.graph);
        const double ms = msSince(t_stage);
        stage.segment += ms;
        segment_ms.push_back(ms);
        seg_log.add(m.seg, ms);
      }
      const mrpt::poses::CPose2D est = m.frontend->currentPose(m.graph);
      m.topo.observeRobot(est.x(), est.y(), frame->timestamp - t0);
      std::optional<mrpt::poses::CPose2D> truth;
      if (frame->ground_truth) {
        if (!gt0) gt0 = *frame->ground_truth;
        truth = *frame->ground_truth - *gt0;  // in the map frame (first pose = origin)
      }
      if (sum.steps > 1) {
        if (truth && last_truth)
          sum.distance_m += std::hypot(truth->x() - last_truth->x(), truth->y() - last_truth->y());
        else
          sum.distance_m += std::hypot(est.x() - last_est.x(), est.y() - last_est.y());
      }
      if (truth) {
        err_sum += std::hypot(truth->x() - est.x(), truth->y() - est.y());
        ++err_n;
      }
      last_truth = truth;
      last_est = est;
      m.path.push_back(est);
      rec.step({sum.steps, frame->timestamp - t0, est, truth, m.graph.size(), m.graph.edges.size(),
                sum.distance_m});
      for (; next_snapshot < snapshots.size() && sum.distance_m >= snapshots[next_snapshot];
           ++next_snapshot)
        rec.snapshot(snapshots[next_snapshot], m.graph, m.navMap(), m.seg, m.topo.graph(), m.path);
      if (map_changed)
        seriesRow(truth ? std::hypot(truth->x() - est.x(), truth->y() - est.y()) : -1);
      progress(false);
    }
  };

  auto finish = [&] {
    if (m.map3d) {
      // A rebuild still under way is completed: the outputs show the final graph's map.
      try {
        while (m.map3d->rebuilding()) m.map3d->rebuildStep();
        m.updateNavMap(false);
      } catch (const std::exception& e) {
        m.logStr(mrpt::system::LVL_ERROR, std::string("map3d: ") + e.what());
      }
    }
    sum.nodes = m.graph.size();
    sum.edges = m.graph.edges.size();
    sum.regions = m.seg.regions.size();
    if (err_n) {
      sum.mean_pose_error_m = err_sum / err_n;
      sum.final_pose_error_m =
          std::hypot(last_truth->x() - last_est.x(), last_truth->y() - last_est.y());
    }
    std::vector<mrpt::poses::CPose2D> kf_est, kf_gt;
    for (const PoseNode& n : m.graph.nodes)
      if (n.ground_truth) {
        kf_est.push_back(n.pose);
        kf_gt.push_back(*n.ground_truth);
      }
    if (kf_est.size() >= 2) {
      const TrajectoryError te = evaluateMatched(kf_est, kf_gt);
      sum.ate_rmse_m = te.ate_rmse_m;
      sum.ate_max_m = te.ate_max_m;
      sum.ate_poses = te.poses;
    }
    sum.loop_closures = loopClosures();
    sum.explored_area_m2 = freeArea(m.navMap());
    if (m.coverage) {
      sum.coverage = m.coverage->coverage(m.navMap());
      sum.reachable_area_m2 = m.coverage->reachableArea();
    }
    if (!decision_ms.empty()) {
      double total = 0;
      for (double v : decision_ms) total += v;
      sum.decision_ms_mean = total / decision_ms.size();
      sum.decision_ms_max = *std::max_element(decision_ms.begin(), decision_ms.end());
    }
    if (!segment_ms.empty()) {
      std::vector<double> v = segment_ms;
      std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
      sum.segment_ms_median = v[v.size() / 2];
    }
    seg_log.summarize(sum);
    if (m.policy) sum.policy = m.cfg.slots.at("policy")->name();
    sum.seed = static_cast<long>(m.cfg.pipeline.getInt("seed"));
    seriesRow(err_n ? std::hypot(last_truth->x() - last_est.x(), last_truth->y() - last_est.y())
                    : -1);
    sum.wall_time_s = std::chrono::duration<double>(Clock::now() - t_start).count();
    std::string err;
    rec.finish(m.graph, m.navMap(), m.seg, m.topo.graph(), m.path, sum, err);
    if (m.map3d) {
      Recorder::Map3dInfo info;
      info.keyframes = m.m3.keyframes;
      info.observations = m.m3.observations;
      info.not_keyframes = m.m3.not_keyframes;
      info.unsupported = m.m3.unsupported;
      info.over_cap = m.m3.over_cap;
      info.insert_ms = m.m3.insert_ms;
      info.project_ms = m.m3.project_ms;
      info.rebuild_ms = m.m3.rebuild_ms;
      info.navigation_map = m.nav_kind;
      rec.finishMap3d(*m.map3d, m.projected, m.cfg.map3d, info, err);
      if (m.m3.keyframes == 0)
        m.logStr(mrpt::system::LVL_WARN,
                 "[pipeline] map3d: no 3D observation reached a keyframe (does the source give "
                 "any? e.g. [rawlog] observations3d = true)");
    }
    try {
      writeRunReport(m.out_dir);
    } catch (const std::exception& e) {
      err += std::string(err.empty() ? "" : "; ") + "report.html: " + e.what();
    }
    if (!err.empty()) m.logStr(mrpt::system::LVL_ERROR, "writing outputs: " + err);
    sum.output_errors = err;
  };

  // Keyframes added since the last optimization are optimized once more at the end, so the
  // outputs (graph, map, ATE) are those of the whole graph, not of an earlier state of it.
  auto finalOptimization = [&] {
    if (!m.backend || nodes_since_opt == 0 || m.graph.size() < 2) return;
    nodes_since_opt = 0;
    m.backend->optimize(m.graph);
    if (want_marginals) m.marginals = m.backend->marginals(m.graph);
    m.marginals.graph_revision = m.graph.revision;
    m.followKeyframes3d();
    if (m.map3d)  // the whole rebuild now: the final segmentation sees the final graph's map
      while (m.map3d->rebuilding()) m.map3d->rebuildStep();
    if (m.updateNavMap(m.map.update(m.graph)) && m.segmenter) {
      m.seg = m.segmenter->segment(m.navMap(), m.seg.regions.empty() ? nullptr : &m.seg);
      m.seg.map_version = m.navMap().version;
      m.topo.update(m.seg, m.navMap(), &m.graph);
    }
  };

  try {
    body();
    finalOptimization();
  } catch (const std::exception& e) {
    sum.stop_reason = std::string("error: ") + e.what();
    finish();
    throw;
  }
  progress(true);
  finish();
  // The planner's check comes after the outputs are on disk: a slow planner on a large graph
  // then costs time, never the run's files; an interrupted run skips it.
  if (m.planner && m.graph.size() > 1 && !(stop && stop->load())) {
    PlanRequest req;
    req.graph = &m.graph;
    req.marginals = m.marginals.valid() ? &m.marginals : nullptr;
    req.map = m.navMap().version ? &m.navMap() : nullptr;
    req.start = static_cast<NodeId>(m.graph.size() - 1);
    req.goal = 0;
    const PlanResult r = m.planner->plan(req);
    std::ostringstream os;
    if (r.found)
      os << "planner: path home (node " << req.start << " -> 0): " << r.nodes.size() << " nodes, "
         << r.criterion << " " << r.cost;
    else
      os << "planner: no path home: " << r.reason;
    m.logStr(mrpt::system::LVL_INFO, os.str());
  }
  return sum;
}

}  // namespace asf
