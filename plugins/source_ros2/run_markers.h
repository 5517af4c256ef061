#pragma once
// What rviz2 and Foxglove show of a run, as visualization_msgs/Marker (one MarkerArray): the
// robot, its goal, the pose graph, the regions, the topological graph and its frontier edges.
#include <asf/ros2/messages.h>
#include <asf/source.h>

#include <vector>

namespace asf::ros2live {

/// The markers of `view` in `frame` (the map frame), stamped `stamp`. The array starts with a
/// DELETEALL, so regions and edges that went away disappear. Namespaces: robot, goal,
/// pose_graph_nodes, pose_graph_edges, loop_closures, regions, region_labels, topology_nodes,
/// topology_edges, frontiers.
std::vector<ros2::Marker> runMarkers(const RunView& view, const ros2::Stamp& stamp,
                                     const std::string& frame);

}  // namespace asf::ros2live
