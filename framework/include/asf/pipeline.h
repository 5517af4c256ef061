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
/// node (SensorFrame::observations3d) become keyframes of an asf::Map3d at that node, follow
/// the node when the back-end moves it, and are projected to 2D; observations of frames that
/// add no node are not used. [pipeline] navigation_map chooses the grid the policy, the
/// navigation, the segmenter and the coverage see: the 2D scans' grid, the projection, or
/// both merged (asf::mergeOccupancy: an obstacle either sees is an obstacle).
#include <asf/backend.h>
#include <asf/config.h>
#include <asf/frontend.h>
#include <asf/map_builder.h>
#include <asf/planner.h>
#include <asf/policy.h>
#include <asf/registry.h>
#include <asf/segmenter.h>
#include <asf/source.h>
#include <asf/topo_builder.h>

#include <atomic>
#include <string>
#include <vector>

namespace asf {

/// Keys of the [pipeline] section.
const KeySpec* pipelineKeys(std::size_t& n);
/// Framework-owned sections and their key tables (pipeline, map, topology, map3d).
struct FrameworkSection {
  const char* name;
  const KeySpec* keys;
  std::size_t num_keys;
};
std::vector<FrameworkSection> frameworkSections();

/// A pipeline's configuration resolved against the framework's and the plugins' key tables.
struct ResolvedConfig {
  Params pipeline, map, topology, map3d;
  /// slot name -> plugin (empty slots absent)
  std::map<std::string, std::shared_ptr<const PluginInfo>> slots;
  std::map<std::string, Params> plugin_params;  ///< plugin name -> its section's values
  std::vector<std::string> warnings;
  /// The whole configuration as INI text, every default filled in and commented.
  std::string toIni() const;
};

/// Scans the default search path plus [pipeline] plugin_path into `registry`, then validates
/// every section. Throws ConfigError listing all problems (unknown sections/keys with "did
/// you mean", missing required keys, bad values, unknown plugins).
ResolvedConfig resolveConfig(const IniConfig& ini, Registry& registry);

struct RunSummary {
  long steps = 0;
  double distance_m = 0;       ///< travelled, from ground truth when known, else estimate
  std::size_t nodes = 0, edges = 0;
  double final_pose_error_m = -1;  ///< vs ground truth; -1 if unknown
  double mean_pose_error_m = -1;
  /// Absolute trajectory error of the final keyframe poses (graph nodes with ground truth)
  /// after SE(2) alignment (asf/trajectory_eval.h); -1 with fewer than 2 such nodes.
  double ate_rmse_m = -1, ate_max_m = -1;
  std::size_t ate_poses = 0;
  std::size_t regions = 0;
  int decisions = 0;
  /// Share of the reachable free area of the true world observed by the final map; -1
  /// when the source does not know the world.
  double coverage = -1;
  double reachable_area_m2 = -1;  ///< of the true world; -1 when unknown
  double explored_area_m2 = 0;    ///< free area of the final map
  std::size_t loop_closures = 0;  ///< loop-closure edges in the final graph
  double decision_ms_mean = 0, decision_ms_max = 0;  ///< policy decide() compute time
  double segment_ms_median = 0;   ///< segmenter + topological graph update, per update
  /// Segmentations of the run and how the segmenter made them (Segmentation::Mode).
  std::size_t segmentations = 0, segmentations_incremental = 0, segmentations_full = 0;
  double segment_ms_median_incremental = -1, segment_ms_median_full = -1;  ///< -1: none
  double changed_cells_median = -1;  ///< of the segmentations that report it; -1: none
  std::string policy;             ///< plugin name, empty without a policy
  long seed = 0;
  bool finished = false;       ///< the policy said done, or the passive source ended
  std::string stop_reason;
  double wall_time_s = 0;
  /// Outputs that could not be written at the end (full disk, permissions), each with its
  /// file and cause; empty when every output is on disk.
  std::string output_errors;
};

class Pipeline {
 public:
  /// Creates and configures every plugin of `cfg`; outputs go to `out_dir` (created).
  /// Throws ConfigError/PluginError.
  Pipeline(const ResolvedConfig& cfg, const std::string& out_dir);
  ~Pipeline();

  /// Runs until the source ends, the policy is done, the budget is spent or `stop` is set.
  /// Writes the outputs as it goes; on an exception the outputs of what happened so far
  /// are still written before it propagates.
  RunSummary run(const std::atomic<bool>* stop = nullptr);

  /// The files a run writes, relative to out_dir (for messages and docs).
  static std::vector<std::string> outputFiles();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace asf
