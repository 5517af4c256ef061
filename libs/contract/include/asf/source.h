#pragma once
/// \file source.h
/// `source` plugins: a simulator or a log, producing one SensorFrame per step.
///
/// Contract:
/// - next() returns frames with non-decreasing timestamps; std::nullopt when the stream has
///   ended, and again on every later call. Errors in the data throw asf::InputError naming the
///   file and record; frames returned before stay valid.
/// - An active source (isActive()) also moves towards the last goal given to navigate() on
///   each next(); status() says how that goes. A passive source returns
///   NavStatus::Unreachable from navigate() and ignores the goal.
/// - All randomness comes from PluginContext::seed.
/// - observe() is called after every step with what the run estimated, and once more at the
///   end (RunView::final) after the final optimization; a source that ignores it (the default)
///   is unaffected. It must not block the run: a source that shows the view somewhere (a live
///   robot's /map, transforms, markers) limits its own rate.
#include <asf/goal.h>
#include <asf/grid_map.h>
#include <asf/plugin.h>
#include <asf/sensor_frame.h>

#include <memory>
#include <optional>

namespace asf {

/// The true world, for a source that knows it (a simulator). Only for evaluation (coverage)
/// and for the offline baselines that are given the whole map by definition; never part of
/// the SLAM estimate.
struct WorldTruth {
  /// Occupancy grid of the world in the world frame (MRPT convention: 1 = free).
  std::shared_ptr<const mrpt::maps::COccupancyGridMap2D> grid;
  /// Pose of the map frame's origin (the robot's first true pose) in the world frame:
  /// p_map = map_origin^-1 (+) p_world.
  mrpt::poses::CPose2D map_origin;
  double robot_radius = 0.2;  ///< of the simulated robot [m]
};

/// What an active source may use to plan: the SLAM estimate, never the ground truth.
struct NavigationContext {
  mrpt::poses::CPose2D robot_estimate;  ///< robot pose in the map frame
  const GridMap* map = nullptr;         ///< current estimated map (may be null)
};

class PoseGraph;
struct Segmentation;
struct TopoGraph;

/// What the run estimated after a step, for a source that shows it on the robot's side. The
/// pointers are valid during the call only; null where the run has none yet.
struct RunView {
  double timestamp = 0;          ///< of the frame just processed (the source's clock)
  mrpt::poses::CPose2D robot;    ///< the robot's estimate in the map frame at that frame
  const GridMap* map = nullptr;  ///< the navigation map (version 0: none yet)
  const Segmentation* segmentation = nullptr;
  const TopoGraph* topo = nullptr;
  const PoseGraph* graph = nullptr;
  const Goal* goal = nullptr;  ///< the goal the robot is driving to, if any
  bool final = false;          ///< the run's last view (after its final optimization)
};

class Source : public Plugin {
 public:
  static constexpr PluginKind kStaticKind = PluginKind::Source;
  PluginKind kind() const final { return kStaticKind; }
  ~Source() override;

  virtual std::optional<SensorFrame> next() = 0;
  virtual bool isActive() const { return false; }
  /// Sets a new goal (replacing the previous); returns Moving, Reached or Unreachable.
  virtual NavStatus navigate(const Goal& goal, const NavigationContext& ctx) {
    return NavStatus::Unreachable;
  }
  virtual NavStatus status() const { return NavStatus::Idle; }
  /// The true world, or null when the source does not know it (logs). Valid after
  /// configure(); the host reads it once, before the first next().
  virtual std::shared_ptr<const WorldTruth> worldTruth() const { return nullptr; }
  /// The run's estimate after a step (see the contract above); the default ignores it.
  virtual void observe(const RunView& view) {}
};

}  // namespace asf
