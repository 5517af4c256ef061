#pragma once
/// \file run_summary.h
/// What a run of the pipeline did, in numbers: summary.json, the experiment tables and the
/// report read it.
#include <cstddef>
#include <string>

namespace asf::framework {

struct RunSummary {
  long steps = 0;
  double distance_m = 0;  ///< travelled, from ground truth when known, else estimate
  std::size_t nodes = 0, edges = 0;
  double final_pose_error_m = -1;  ///< vs ground truth; -1 if unknown
  double mean_pose_error_m = -1;
  /// Absolute trajectory error of the final keyframe poses (graph nodes with ground truth)
  /// after SE(2) alignment (asf/evaluation/trajectory_eval.h); -1 with fewer than 2 such nodes.
  double ate_rmse_m = -1, ate_max_m = -1;
  std::size_t ate_poses = 0;
  /// Relative pose error of consecutive final keyframes (asf::evaluation::relativePoseError, delta
  /// 1); -1 with fewer than 2 keyframes with ground truth.
  double rpe_trans_rmse_m = -1, rpe_rot_rmse_deg = -1;
  /// Distance driven and simulated time when the coverage (of the timeseries rows) first
  /// reached each of kCoverageMilestones; -1 if it never did.
  static constexpr double kCoverageMilestones[5] = {0.25, 0.5, 0.75, 0.9, 0.99};
  double coverage_distance_m[5] = {-1, -1, -1, -1, -1};
  double coverage_time_s[5] = {-1, -1, -1, -1, -1};
  std::size_t regions = 0;
  int decisions = 0;
  /// Share of the reachable free area of the true world observed by the final map; -1
  /// when the source does not know the world.
  double coverage = -1;
  double reachable_area_m2 = -1;  ///< of the true world; -1 when unknown
  double explored_area_m2 = 0;    ///< free area of the final map
  /// The final map: its cells, what it says and its entropy over itself
  /// (asf::mapping::mapInformationBits, mapEntropyBits; -1: no map).
  std::size_t map_cells = 0;
  double map_information_bits = -1, map_entropy_bits = -1;
  /// Versions of the scans' occupancy grid, and how many of them were rebuilt from every
  /// scan because the back-end moved inserted keyframes.
  std::size_t map_versions = 0, map_rebuilds = 0;
  std::size_t loop_closures = 0;                     ///< loop-closure edges in the final graph
  double decision_ms_mean = 0, decision_ms_max = 0;  ///< policy decide() compute time
  double segment_ms_median = 0;  ///< segmenter + topological graph update, per update
  /// Segmentations of the run and how the segmenter made them (Segmentation::Mode).
  std::size_t segmentations = 0, segmentations_incremental = 0, segmentations_full = 0;
  double segment_ms_median_incremental = -1, segment_ms_median_full = -1;  ///< -1: none
  double changed_cells_median = -1;  ///< of the segmentations that report it; -1: none
  std::string policy;                ///< plugin name, empty without a policy
  long seed = 0;
  /// A run that continued another ([pipeline] resume): that folder, the recorded steps it
  /// replayed, and the recorded decisions the policy took again (those whose goal or kind
  /// came out otherwise: the replay's estimates differ from the recorded run's).
  std::string resumed_from;
  long resumed_after_steps = 0;
  int replayed_decisions = 0, replayed_decisions_differing = 0;
  bool finished = false;  ///< the policy said done, or the passive source ended
  std::string stop_reason;
  double wall_time_s = 0;
  /// Outputs that could not be written at the end (full disk, permissions), each with its
  /// file and cause; empty when every output is on disk.
  std::string output_errors;
};

}  // namespace asf::framework
