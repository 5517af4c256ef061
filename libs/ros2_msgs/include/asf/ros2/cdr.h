#pragma once
/// \file cdr.h
/// ROS 2 messages as the bytes ROS 2 stores and sends: CDR, little endian, with the 4-byte
/// encapsulation header (0x00 0x01 0x00 0x00) rosbag2 keeps in front of every message, and the
/// message definitions (ros2msg text) that describe them in a bag's schemas. For writing a live
/// run as a rosbag2 bag (bag_writer.h) without a DDS library.
///
/// Contract:
/// - Each encoder writes every field of the ROS 2 (Humble) message in order, aligned as CDR
///   aligns it (a primitive of n bytes at a multiple of n from the start of the payload after
///   the header); fields the plain struct does not hold (Odometry's twist and covariances, a
///   Marker's texture and mesh) are written as zeros or empty.
/// - messageDefinition(type) is the type's definition followed by every type it uses, each
///   after a line of 80 '=' and "MSG: pkg/Type", as rosbag2 writes schemas.
#include <asf/ros2/messages.h>

#include <cstdint>
#include <string>
#include <vector>

namespace asf::ros2 {

std::vector<std::uint8_t> cdrLaserScan(const LaserScan& m);
std::vector<std::uint8_t> cdrOdometry(const Odometry& m);
std::vector<std::uint8_t> cdrTfMessage(const std::vector<TransformStamped>& m);
std::vector<std::uint8_t> cdrOccupancyGrid(const OccupancyGrid& m);
std::vector<std::uint8_t> cdrMarkerArray(const std::vector<Marker>& m);
std::vector<std::uint8_t> cdrPoseStamped(const Stamp& stamp, const std::string& frame,
                                         const Transform& pose);
std::vector<std::uint8_t> cdrString(const std::string& text);

/// The ros2msg definition of "sensor_msgs/msg/LaserScan", "nav_msgs/msg/Odometry",
/// "tf2_msgs/msg/TFMessage", "nav_msgs/msg/OccupancyGrid", "visualization_msgs/msg/MarkerArray",
/// "geometry_msgs/msg/PoseStamped" or "std_msgs/msg/String"; throws std::invalid_argument for
/// another type.
std::string messageDefinition(const std::string& type);

}  // namespace asf::ros2
