#pragma once
// What the ros2 source publishes of a run after each frame: map -> odom on /tf every time (the
// frame's stamp: it holds at that instant, where tf users look it up beside odom -> base_link),
// /map at most every map_period_s of the robot's clock and only when it changed, the markers at
// most every marker_period_s, and all of them after the final optimization. Each goes to the
// run's bag too.
#include <asf/ros2/messages.h>
#include <asf/source.h>

#include <cstdint>
#include <string>

#include "cyclone_link.h"
#include "live_bag.h"

namespace asf::ros2live {

struct RunPublisherOptions {
  std::string tf_topic = "/tf", map_topic = "/map", marker_topic = "/asf/markers";
  std::string map_frame = "map", odom_frame = "odom";
  double map_period = 1, marker_period = 1;  ///< robot clock [s]
};

class RunPublisher {
 public:
  /// Advertises the three topics on `link` (throws std::runtime_error as CycloneLink does).
  RunPublisher(CycloneLink& link, LiveBag& bag, RunPublisherOptions o);
  /// After a frame: `odom` is the odometry at the frame's stamp (map -> odom = v.robot - odom).
  void publish(const RunView& v, const mrpt::poses::CPose2D& odom);
  std::uint64_t mapsSent() const { return maps_sent_; }

 private:
  CycloneLink& link_;
  LiveBag& bag_;
  RunPublisherOptions o_;
  int tf_wr_ = 0, map_wr_ = 0, markers_wr_ = 0;
  ros2::OccupancyConverter map_converter_;  // the rows changed since the last /map
  std::uint64_t map_version_ = 0, maps_sent_ = 0;
  double map_sent_ = -1e300, markers_sent_ = -1e300;
};

}  // namespace asf::ros2live
