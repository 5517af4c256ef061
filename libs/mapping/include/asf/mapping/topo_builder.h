#pragma once
/// \file topo_builder.h
/// Framework service: topological graph from a Segmentation and the map, with the robot's
/// traversal history. Regions that share a free border at least `min_border_width` wide are
/// joined; a region bordering unknown space along a stretch at least `min_frontier_width`
/// wide gets an edge to the kUnexplored node (through the cells of all such stretches).
#include <asf/grid_map.h>
#include <asf/key_spec.h>
#include <asf/params.h>
#include <asf/pose_graph.h>
#include <asf/segmentation.h>
#include <asf/topo_graph.h>

#include <memory>

namespace asf::mapping {

namespace detail {
struct TopoBorderCache;
/// Owns TopoBuilder's border cache (topo_builder.cpp); a copy copies the cache, so that
/// TopoBuilder keeps its default copy and move.
class TopoBorderCacheHolder {
 public:
  TopoBorderCacheHolder();
  ~TopoBorderCacheHolder();
  TopoBorderCacheHolder(const TopoBorderCacheHolder& other);
  TopoBorderCacheHolder& operator=(const TopoBorderCacheHolder& other);
  TopoBorderCacheHolder(TopoBorderCacheHolder&&) noexcept;
  TopoBorderCacheHolder& operator=(TopoBorderCacheHolder&&) noexcept;
  TopoBorderCache& get();  ///< made empty on first use
  void reset();            ///< empty: the next update recomputes every stripe

 private:
  std::unique_ptr<TopoBorderCache> cache_;
};
}  // namespace detail

class TopoBuilder {
 public:
  static const KeySpec* keys(std::size_t& n);  ///< the [topology] section
  void configure(const Params& p);

  /// Recomputes nodes and edges from a new segmentation.
  ///
  /// With `history` (the pose graph: its nodes in order are the robot's past, at their
  /// optimized poses), traversals, visited flags, entrance edges and the current region are
  /// recomputed by replaying that trajectory, then the robot's last observed position,
  /// through the new regions: a region boundary moved, split or renamed by a re-segmentation
  /// then gets the history the robot really has with it. A step between two poses is
  /// sampled every half cell; a change of region along it is a traversal when the two
  /// regions share an edge. Without `history`, traversals, visited flags and entrance
  /// edges carry over for region ids that persist.
  void update(const Segmentation& seg, const GridMap& map, const PoseGraph* history = nullptr);
  /// Records the robot at (x, y) at time t: updates the current region, and a traversal
  /// when it moved into a neighbouring region.
  void observeRobot(double x, double y, double t);
  const TopoGraph& graph() const { return graph_; }

 private:
  double min_border_width_ = 0.3, min_frontier_width_ = 0.5, unknown_band_ = 0.02;
  void replay(const PoseGraph& history);
  /// Keeps the frontier cells (label-image indices, with their points in `border`) that
  /// lie on stretches of at least min_frontier_width.
  void keepWideFrontiers(std::vector<int>& cells, int width, double resolution,
                         std::vector<Point2>& border) const;

  Segmentation seg_;
  TopoGraph graph_;
  bool have_robot_ = false;
  double robot_x_ = 0, robot_y_ = 0, robot_t_ = 0;
  /// The last update's borders in stripes of rows, so that an update recomputes only the
  /// rows that changed (topo_builder.cpp).
  detail::TopoBorderCacheHolder borders_;
};

}  // namespace asf::mapping
