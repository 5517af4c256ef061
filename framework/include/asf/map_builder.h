#pragma once
/// \file map_builder.h
/// Framework service: occupancy grid from the keyframe scans at their optimized poses.
/// Inserts new keyframes incrementally; rebuilds from scratch when the back-end moved
/// already inserted keyframes by more than a threshold (a loop closure).
#include <asf/grid_map.h>
#include <asf/key_spec.h>
#include <asf/params.h>
#include <asf/pose_graph.h>

#include <memory>
#include <vector>

namespace asf {

class MapBuilder {
 public:
  /// INI keys of the [map] section.
  static const KeySpec* keys(std::size_t& n);

  MapBuilder();
  ~MapBuilder();
  void configure(const Params& p);

  /// Brings the map up to date with the graph; returns true if it changed (then map()
  /// holds a new version).
  bool update(const PoseGraph& graph);
  const GridMap& map() const { return map_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  GridMap map_;
};

}  // namespace asf
