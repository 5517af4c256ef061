#pragma once
// The ros2 source's keys read into the options of its parts (source_ros2_options.cpp): the DDS
// participant, the drive = cmd_vel follower, and the check of the topic names. Used by
// source_ros2.cpp; the keys themselves are its table (source_ros2_keys.h).
#include <asf/params.h>

#include "cyclone_link.h"
#include "velocity_drive.h"

namespace asf::ros2live {

/// domain_id (-1: $ROS_DOMAIN_ID, else 0) and discovery.
LinkOptions linkOptions(const asf::Params& p);

/// drive = cmd_vel: the planner keeps the simulator's margins (nav_*) around a robot of
/// `robot_radius`, the follower the robot's speeds; a goal running longer than `goal_timeout`
/// is Blocked.
VelocityDriveOptions velocityDriveOptions(const asf::Params& p, double robot_radius,
                                          double goal_timeout);

/// Fails (Params::fail) on a topic key whose value is not a ROS 2 topic name DDS can carry;
/// ground_truth_topic, world_map_topic and clock_topic may be empty (off).
void checkTopicNames(const asf::Params& p);

}  // namespace asf::ros2live
