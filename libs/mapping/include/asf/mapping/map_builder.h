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

namespace asf::mapping {

/// Two grids merged cell by cell over the union of their extents, at a's resolution (cell
/// centres sampled in each). A value is known when |p - 0.5| > unknown_band. Occupied in
/// either: the more occupied value, so an obstacle either grid sees stays one (a low box
/// under the 2D laser, a table top above it); else free in either: the more free value (a
/// 3D map that saw the floor once does not dilute the 2D laser's certainty); else 0.5.
/// MRPT convention: values are p(free).
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
  /// Versions that were rebuilds (every scan inserted again), over the builder's life.
  std::size_t rebuilds() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  GridMap map_;
};

}  // namespace asf::mapping
