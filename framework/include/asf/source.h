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
#include <asf/goal.h>
#include <asf/grid_map.h>
#include <asf/plugin.h>
#include <asf/sensor_frame.h>

#include <optional>

namespace asf {

/// What an active source may use to plan: the SLAM estimate, never the ground truth.
struct NavigationContext {
  mrpt::poses::CPose2D robot_estimate;  ///< robot pose in the map frame
  const GridMap* map = nullptr;         ///< current estimated map (may be null)
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
};

}  // namespace asf
