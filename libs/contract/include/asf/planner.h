#pragma once
/// \file planner.h
/// `planner` plugins: a path in the pose graph between two nodes, under the plugin's
/// criterion.
///
/// Contract:
/// - A found path starts at `start`, ends at `goal`, and each consecutive pair is joined by
///   an edge of the graph (either direction), or, only for a planner told to drive through
///   mapped free space the robot never drove (the criterion planners' `voronoi_edges`, with
///   a `map`), by a path through the map's free space (asf/planning/voronoi_graph.h).
///   start == goal gives the one-node path.
/// - No path (disconnected, bad ids) is a result with found = false and a reason, not an
///   exception.
#include <asf/grid_map.h>
#include <asf/plugin.h>
#include <asf/pose_graph.h>

#include <string>
#include <vector>

namespace asf {

struct PlanRequest {
  const PoseGraph* graph = nullptr;
  const Marginals* marginals = nullptr;  ///< may be null
  const GridMap* map = nullptr;          ///< may be null
  NodeId start = 0, goal = 0;
};

struct PlanResult {
  bool found = false;
  std::vector<NodeId> nodes;
  double cost = 0;        ///< under `criterion`
  std::string criterion;  ///< e.g. "distance", "det(E[C])"
  std::string reason;     ///< why not found
};

class Planner : public Plugin {
 public:
  static constexpr PluginKind kStaticKind = PluginKind::Planner;
  PluginKind kind() const final { return kStaticKind; }
  ~Planner() override;

  virtual PlanResult plan(const PlanRequest& request) = 0;
};

}  // namespace asf
