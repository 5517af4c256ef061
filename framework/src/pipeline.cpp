#include <asf/errors.h>
#include <asf/framework/pipeline.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "pipeline_impl.h"

namespace asf::framework {

namespace {

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

}  // namespace

struct Pipeline::Impl : PipelineParts {};

template <class T>
void PipelineParts::make(const char* slot, int index, PluginHandle<T>& h) {
  auto it = cfg.slots.find(slot);
  if (it == cfg.slots.end()) return;
  h = Registry::create<T>(it->second);
  h->setMinLoggingLevel(getMinLoggingLevel());
  if (log) RunLog::attach(log, *h);
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
    m.out_lock = std::make_unique<OutputLock>(out_dir);  // before anything is written there
  }
  const mrpt::system::VerbosityLevel level = parseVerbosity(cfg.pipeline.getString("verbosity"));
  m.setMinLoggingLevel(level);
  // Every line to run.log; on the console warnings, errors and the progress line, unless a
  // verbosity was asked for (-v INFO: every INFO line there too, as before run.log existed).
  const auto console =
      cfg.pipeline.isDefault("verbosity") ? std::max(level, mrpt::system::LVL_WARN) : level;
  m.log = std::make_shared<RunLog>(out_dir.empty() ? "" : out_dir + "/run.log", console, stderr,
                                   isatty(fileno(stderr)) != 0);
  RunLog::attach(m.log, m);
  for (const auto& w : cfg.warnings) m.logStr(mrpt::system::LVL_WARN, w);
  m.make("source", 0, m.source);
  m.make("frontend", 1, m.frontend);
  m.make("backend", 2, m.backend);
  m.make("segmenter", 3, m.segmenter);
  m.make("planner", 4, m.planner);
  m.make("policy", 5, m.policy);
  if (!m.source || !m.frontend) throw ConfigError("[pipeline] needs a source and a frontend");
  m.maps.configure(cfg.map, cfg.pipeline.getBool("map3d"), cfg.map3d,
                   cfg.pipeline.getString("navigation_map"));
  m.topo.configure(cfg.topology);
  m.world = m.source->worldTruth();
  if (m.world && m.world->grid) {
    m.coverage = std::make_unique<mapping::CoverageMeter>(*m.world);
    m.area = mapping::MapAreaTracker(m.coverage.get());
    if (m.policy && m.segmenter) m.segmentWorld();
  }
  if (m.policy && !m.source->isActive())
    m.logStr(mrpt::system::LVL_WARN,
             "the policy is ignored: source '" + cfg.slots.at("source")->name() + "' is passive");
}

Pipeline::~Pipeline() = default;

void PipelineParts::segmentWorld() {
  PluginHandle<Segmenter> seg_world;
  make("segmenter", 3, seg_world);
  GridMap wm;
  wm.grid = world->grid;
  wm.version = 1;
  const Segmentation ws = seg_world->segment(wm, nullptr);
  mapping::TopoBuilder tb;
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

std::vector<std::string> Pipeline::outputFiles() {
  return {"config.ini",   "trajectory.csv", "timeseries.csv", "decisions.csv",
          "graph.g2o",    "keyframes.txt",  "map.png",        "regions.png",
          "map.pgm",      "map.yaml",       "topology.json",  "topology.svg",
          "summary.json", "progress.json",  "report.html",    "run.log"};
}

void Pipeline::setLiveView(std::function<void(const evaluation::ViewImage&)> show, double period_s,
                           int max_side) {
  impl_->live_view = std::move(show);
  impl_->live_period_s = period_s;
  impl_->live_max_side = max_side;
}

RunSummary Pipeline::run(const std::atomic<bool>* stop, const std::atomic<bool>* pause,
                         const std::atomic<bool>* home) {
  return runPipeline(*impl_, stop, pause, home);
}

}  // namespace asf::framework
