#pragma once
/// \file policy.h
/// `policy` plugins: the exploration decision, taken when the robot is idle.
///
/// Contract:
/// - decide() returns GoTo with a finite goal, or Done with a reason. It is called again
///   after the robot reached the goal, or failed to (then `last_status` says why): a policy
///   must not return the same unreachable goal forever.
/// - Reads only the state; never blocks. It may ask `state.planner` for paths (e.g. the
///   most reliable way back to a well-localized node, thesis ch. 3); that time counts as
///   its decision time.
#include <asf/goal.h>
#include <asf/grid_map.h>
#include <asf/planner.h>
#include <asf/plugin.h>
#include <asf/pose_graph.h>
#include <asf/topo_graph.h>

namespace asf {

struct ExplorationState {
  const TopoGraph* topo = nullptr;   ///< never null
  mrpt::poses::CPose2D robot;        ///< estimate, map frame
  const GridMap* map = nullptr;      ///< may be null before the first map
  const PoseGraph* graph = nullptr;  ///< may be null
  /// Marginal covariances of `graph` from the last optimization; may be null.
  const Marginals* marginals = nullptr;
  /// The pipeline's [pipeline] planner, a service for the policy: plan() over `graph`,
  /// `marginals` and `map`; null when the pipeline has none.
  Planner* planner = nullptr;
  /// The regions `topo` was built from (labels in the map frame); may be null.
  const Segmentation* segmentation = nullptr;
  double time = 0;                          ///< seconds since the start of the run
  NavStatus last_status = NavStatus::Idle;  ///< outcome of the previous goal
  Goal last_goal;                           ///< meaningful unless last_status == Idle
  /// Offline baselines only (they are given the whole map by definition): the topological
  /// graph of the true world, segmented once by the pipeline's segmenter, in the map frame;
  /// null when the source does not know the world. On-line policies must not read it.
  const TopoGraph* world_topo = nullptr;
};

class Policy : public Plugin {
 public:
  static constexpr PluginKind kStaticKind = PluginKind::Policy;
  PluginKind kind() const final { return kStaticKind; }
  ~Policy() override;

  virtual Decision decide(const ExplorationState& state) = 0;
};

}  // namespace asf
