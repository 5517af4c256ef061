#pragma once
/// \file route_policy.h
/// The offline baselines of thesis ch. 6: given the whole map (ExplorationState::world_topo,
/// the true world segmented once), compute a walk over its topological graph and follow it:
/// the Chinese postman walk (every edge, `cpp_offline`) or the TSP walk (every region,
/// `tsp_offline`). Goals: each edge's border midpoint, then the next region's centroid.
/// A goal the navigation fails to reach is skipped (logged); the policy is done at the end of
/// the walk. Edge lengths: centroid -> border midpoint -> centroid.
#include <asf/graph/routes.h>
#include <asf/policy.h>

namespace asf::exploration {

class RoutePolicy : public Policy {
 public:
  enum class Route { ChinesePostman, Tsp };
  explicit RoutePolicy(Route r) : route_(r) {}
  void configure(const Params& params, const PluginContext& ctx) override;
  Decision decide(const ExplorationState& state) override;

  /// The walk over `topo` (region edges only, the component of `start`) and its goals
  /// (two per step: border midpoint, then centroid), exposed for tests.
  struct Plan {
    graph::Walk walk;
    std::vector<RegionId> regions;  ///< node index -> region id
    std::vector<Goal> goals;
    std::vector<std::string> labels;  ///< why each goal (for decision reasons)
    int edges = 0;                    ///< region edges of the walked component
    double edges_length = 0;          ///< their total length [m]
  };
  static Plan plan(const TopoGraph& topo, RegionId start, Route route, double tolerance,
                   std::uint32_t seed);

 private:
  Route route_;
  double tolerance_ = 0.4;
  std::uint32_t seed_ = 0;
  bool planned_ = false;
  Plan plan_;
  std::size_t next_ = 0;
  int skipped_ = 0;
};

}  // namespace asf::exploration
