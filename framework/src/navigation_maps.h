#pragma once
// The run's maps: the 2D scans' occupancy grid, the optional 3D map with its keyframes at
// the pose-graph nodes, and the grid navigation uses ([pipeline] navigation_map). Private to
// the framework: the pipeline's map stage.
#include <asf/mapping/map3d.h>
#include <asf/mapping/map_builder.h>
#include <asf/pose_graph.h>
#include <asf/source.h>
#include <mrpt/system/COutputLogger.h>

#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "recorder.h"

namespace asf::framework {

class NavigationMaps {
 public:
  /// `map3d_params` is used only when `with_map3d`; `navigation_map` is scan2d|map3d|merged.
  void configure(const Params& map_params, bool with_map3d, const Params& map3d_params,
                 const std::string& navigation_map);

  /// The grid the policy, navigation, segmenter and coverage use.
  const GridMap& navigation() const {
    if (nav_kind_ == "map3d") return projected_;
    if (nav_kind_ == "merged") return merged_;
    return scan2d_.map();
  }
  bool hasMap3d() const { return static_cast<bool>(map3d_); }
  /// The 2D scans' grid: its versions and how many were rebuilds.
  const GridMap& scanMap() const { return scan2d_.map(); }
  std::size_t scanMapRebuilds() const { return scan2d_.rebuilds(); }

  /// The frame's 3D observations become keyframes at the node the front-end added for it
  /// (none when the graph did not grow past `nodes_before`). Unusable observations are
  /// counted and warned about once per cause through `log`.
  void addKeyframes3d(const SensorFrame& f, const PoseGraph& graph, std::size_t nodes_before,
                      mrpt::system::COutputLogger& log);
  /// Moves the 3D keyframes with their nodes after an optimization.
  void followGraph(const PoseGraph& graph);
  /// Rebuilds the 2D grid from `graph` when `graph_changed`, then brings the 3D projection
  /// and the merged grid up to date (one rebuild step of the 3D map at most); true if
  /// navigation() changed.
  bool update(const PoseGraph& graph, bool graph_changed);
  /// Completes a 3D rebuild under way, so the grids show the final graph's map.
  void completeRebuild();

  const mapping::Map3d& map3d() const { return *map3d_; }
  const GridMap& projected() const { return projected_; }
  /// Counts and timings of the 3D map for map3d.json.
  Recorder::Map3dInfo map3dInfo() const;

 private:
  bool updateNavigation(bool map2d_changed);
  bool updateMerged();

  // Keyframe ids are node * kObsPerNode + index of the observation in the frame.
  static constexpr mapping::Map3d::KeyframeId kObsPerNode = 16;
  mapping::MapBuilder scan2d_;
  std::unique_ptr<mapping::Map3d> map3d_;
  std::string nav_kind_ = "scan2d";
  GridMap projected_;                            ///< last projection of map3d_
  GridMap merged_;                               ///< navigation_map = merged
  std::uint64_t projected_from_ = 0;             ///< map3d_ version of projected_
  std::uint64_t merged_2d_ = 0, merged_3d_ = 0;  ///< input versions of merged_
  Recorder::Map3dInfo counts_;
  std::set<std::string> warned_3d_;
  std::vector<std::pair<mapping::Map3d::KeyframeId, NodeId>> keyframes3d_;  ///< in id order
};

}  // namespace asf::framework
