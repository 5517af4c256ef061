#pragma once
// The pipeline's plugins and services, shared by its construction (pipeline.cpp) and its run
// (pipeline_run.cpp). Private to the framework.
#include <asf/backend.h>
#include <asf/mapping/coverage.h>
#include <asf/frontend.h>
#include <asf/framework/pipeline.h>
#include <asf/planner.h>
#include <asf/policy.h>
#include <asf/segmenter.h>
#include <asf/source.h>
#include <asf/mapping/topo_builder.h>
#include <mrpt/system/COutputLogger.h>

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "navigation_maps.h"
#include "output_lock.h"
#include "run_log.h"

namespace asf::framework {

/// What Pipeline::Impl holds, at namespace scope so the run (RunState) can name it.
struct PipelineParts : public mrpt::system::COutputLogger {
  PipelineParts() : COutputLogger("asf") {}
  ResolvedConfig cfg;
  std::string out_dir;
  std::unique_ptr<OutputLock> out_lock;  ///< held while the pipeline lives (output_lock.h)
  /// run.log and the console, for the host's and every plugin's lines (kept alive by them).
  std::shared_ptr<RunLog> log;
  PluginHandle<Source> source;
  PluginHandle<Frontend> frontend;
  PluginHandle<Backend> backend;
  PluginHandle<Segmenter> segmenter;
  PluginHandle<Planner> planner;
  PluginHandle<Policy> policy;
  NavigationMaps maps;
  mapping::TopoBuilder topo;
  PoseGraph graph;
  Marginals marginals;
  Segmentation seg;
  std::vector<mrpt::poses::CPose2D> path;
  std::shared_ptr<const WorldTruth> world;
  std::unique_ptr<mapping::CoverageMeter> coverage;
  /// Free area and coverage of the navigation grid, updated with every version (O(changed
  /// cells)).
  mapping::MapAreaTracker area;
  /// Pipeline::setLiveView: the viewer (empty: none), its period [s] and picture size.
  std::function<void(const evaluation::ViewImage&)> live_view;
  double live_period_s = 0.5;
  int live_max_side = 800;
  TopoGraph world_topo;  ///< of the true world, map frame (offline baselines)
  bool have_world_topo = false;

  const GridMap& navMap() const { return maps.navigation(); }

  /// The pipeline's segmenter, a second instance, run once on the true world.
  void segmentWorld();
  /// Creates and configures the plugin of `slot` (none if the slot is empty); `index` picks
  /// its random stream.
  template <class T>
  void make(const char* slot, int index, PluginHandle<T>& h);
};

/// Runs the pipeline once (Pipeline::run).
RunSummary runPipeline(PipelineParts& parts, const std::atomic<bool>* stop,
                       const std::atomic<bool>* pause = nullptr,
                       const std::atomic<bool>* home = nullptr);

}  // namespace asf::framework
