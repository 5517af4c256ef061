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
/// - driveVelocity() is for a source with a velocity-driven base (a simulator behind a robot's
///   /cmd_vel): the base moves at the last velocity given, within its own limits, until
///   another velocity or a navigate() replaces it; a source without one returns false.
/// - An operator may steer a run through its source (a live robot's command topic):
///   takeOperatorRequest() hands each request once, the run polls it after every step and
///   while paused. A live source (isLive(): frames come in real time whether or not the run
///   takes them) is halted when the run pauses (halt(): the robot stops, status() is Idle)
///   and stepped on meanwhile (the run maps, decides nothing); any other source is held
///   between two steps and goes on afterwards as if it had not been paused.
/// - endRecording() closes what the source writes into the run's folder (a rawlog, a bag,
///   ground truth), once, after the run's last frame and before the run says it finished: it
///   throws asf::Error naming the file when anything written was lost, after closing every
///   file. Neither next(), navigate() nor observe() is called after it; a second call does
///   nothing. A source that records nothing keeps the default, which does nothing.
#include <asf/goal.h>
#include <asf/grid_map.h>
#include <asf/plugin.h>
#include <asf/sensor_frame.h>

#include <memory>
#include <optional>
#include <string>

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
  bool paused = false;         ///< the run is paused (no decision)
  bool returning_home = false; ///< the robot is driving back to the start
};

/// A velocity command for a robot's base (REP 103: m/s ahead, rad/s counter-clockwise).
struct BaseVelocity {
  double forward = 0;
  double turn = 0;
};

/// What an operator asks of a run through its source.
struct OperatorRequest {
  enum class Kind {
    None,        ///< nothing (more) to do
    Pause,       ///< stop the robot and decide nothing until Resume
    Resume,      ///< go on exploring (also: start, for a run that waits for it)
    Stop,        ///< end the run, writing every output
    ReturnHome,  ///< drive back to the start, then end the run
  };
  Kind kind = Kind::None;
  std::string from;  ///< where it came from, for the log and the stop reason
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
  /// Drives the base at `v` from the next frame on (see the contract above): true when the
  /// source has such a base, false (the default) otherwise.
  virtual bool driveVelocity(const BaseVelocity& v) { return false; }
  /// The next operator request (see the contract above); the default has none.
  virtual OperatorRequest takeOperatorRequest() { return {}; }
  /// Stops the robot now, forgetting its goal (the run pauses); the default does nothing.
  virtual void halt() {}
  /// Frames come in real time whether or not the run takes them (see the contract above).
  virtual bool isLive() const { return false; }
  /// The run's estimate after a step (see the contract above); the default ignores it.
  virtual void observe(const RunView& view) {}
  /// Closes the run's recordings (see the contract above); the default has none.
  virtual void endRecording() {}
};

}  // namespace asf
