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

/// Two grids merged cell by cell over the union of their extents, at a's resolution (cell
/// centres sampled in each): the least free of the known values (|p - 0.5| > unknown_band),
/// 0.5 where neither knows. An obstacle either grid sees stays one (a low box under the 2D
/// laser, a table top above it). MRPT convention: values are p(free).
std::shared_ptr<const mrpt::maps::COccupancyGridMap2D> mergeOccupancy(
    const mrpt::maps::COccupancyGridMap2D& a, const mrpt::maps::COccupancyGridMap2D& b,
    double unknown_band = 0.02);

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
