#pragma once
/// \file pipeline.h
/// The loop `asf run` drives: source -> front-end -> back-end -> map -> segmenter ->
/// topological graph -> policy -> source navigation, with recorders writing the outputs.
///
/// INI: [pipeline] names one plugin per slot and the run's budget; each plugin reads the
/// section named after the plugin; [map], [topology] and [map3d] configure the framework
/// services.
///
/// 3D map ([pipeline] map3d = true): the 3D observations of a frame that adds a pose-graph
/// node (SensorFrame::observations3d) become keyframes of an asf::mapping::Map3d at that node,
/// follow the node when the back-end moves it, and are projected to 2D; observations of frames that
/// add no node are not used. [pipeline] navigation_map chooses the grid the policy, the
/// navigation, the segmenter and the coverage see: the 2D scans' grid, the projection, or
/// both merged (asf::mapping::mergeOccupancy: an obstacle either sees is an obstacle).
#include <asf/evaluation/map_views.h>
#include <asf/framework/pipeline_config.h>
#include <asf/framework/run_summary.h>

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace asf::framework {

class Pipeline {
 public:
  /// Creates and configures every plugin of `cfg`; outputs go to `out_dir` (created).
  /// Throws ConfigError/PluginError.
  Pipeline(const ResolvedConfig& cfg, const std::string& out_dir);
  ~Pipeline();

  /// Runs until the source ends, the policy is done, the budget is spent or `stop` is set.
  /// Writes the outputs as it goes; on an exception the outputs of what happened so far
  /// are still written before it propagates. While `pause` is set the run waits between
  /// two steps (no source step, no decision; progress.json says "paused") and goes on as if
  /// nothing happened when it is cleared; `stop` still ends it. A live source (a robot) is
  /// halted instead and the run goes on mapping without decisions (source.h). Once `home`
  /// is set the robot drives back to the start and the run ends there. An operator can ask
  /// the same through the source (Source::takeOperatorRequest).
  RunSummary run(const std::atomic<bool>* stop = nullptr, const std::atomic<bool>* pause = nullptr,
                 const std::atomic<bool>* home = nullptr);

  /// A live view (`asf run --gui`): during run(), `show` gets the picture of the run
  /// (renderLiveView: map, regions, topological graph, pose graph, path, robot, goal; at most
  /// `max_side` px) from the run's thread, at most once per `period_s` seconds of wall time
  /// and once at the end, which is also written to live_view.png.
  void setLiveView(std::function<void(const evaluation::ViewImage&)> show, double period_s,
                   int max_side);

  /// The files a run writes, relative to out_dir (for messages and docs).
  static std::vector<std::string> outputFiles();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace asf::framework
