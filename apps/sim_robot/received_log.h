#pragma once
// What asf sim-robot received from asf, written out for the tests that check it against the
// run's own outputs (tests/ros2/check_received.py): decoded on Fast DDS, so a test compares what
// crossed the vendor boundary, not what asf meant to send.
#include <asf/ros2/messages.h>
#include <mrpt/poses/CPose2D.h>

#include <optional>
#include <string>
#include <vector>

#include "visualization_msgs.h"

namespace asf::simrobot {

/// Writes into `dir` (created): map.pgm (one byte per cell, row 0 = the lowest y as in ROS: the
/// ROS value 0..100, 255 for unknown) and map.json (its header), markers.json (every marker of
/// the last MarkerArray: ns, id, type, action, pose, points, text) and map_to_odom.json.
void writeReceived(const std::string& dir, const std::optional<ros2::OccupancyGrid>& map,
                   const std::vector<visualization_msgs::msg::dds_::Marker_>& markers,
                   const mrpt::poses::CPose2D& map_to_odom);

}  // namespace asf::simrobot
