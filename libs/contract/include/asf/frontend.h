#pragma once
/// \file frontend.h
/// `frontend` plugins: turn SensorFrames into pose-graph nodes and edges.
///
/// Contract:
/// - process() may add nodes (ids consecutive, see PoseGraph) and edges, and must increment
///   graph.revision when it does; it never removes nodes or edges and never moves existing
///   nodes (the back-end does). Returns true iff the graph changed.
/// - The first frame creates node 0 at the origin (the map frame is the first pose).
/// - A frame without a scan is valid input (odometry only).
/// - currentPose() is the robot's pose estimate after the last frame (last node composed
///   with the odometry since), in the map frame.
#include <asf/plugin.h>
#include <asf/pose_graph.h>
#include <asf/sensor_frame.h>

namespace asf {

class Frontend : public Plugin {
 public:
  static constexpr PluginKind kStaticKind = PluginKind::Frontend;
  PluginKind kind() const final { return kStaticKind; }
  ~Frontend() override;

  virtual bool process(const SensorFrame& frame, PoseGraph& graph,
                       const Marginals& marginals) = 0;
  virtual mrpt::poses::CPose2D currentPose(const PoseGraph& graph) const = 0;
};

}  // namespace asf
