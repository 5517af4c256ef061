#pragma once
// The ros2 source's INI keys: its ASF_PLUGIN table (source_ros2.cpp), in a file of its own for
// length. Included once, by source_ros2.cpp.
#include <asf/key_spec.h>

namespace {

const asf::KeySpec kKeys[] = {
    asf::keyInt("domain_id", "-1", "DDS domain (ROS_DOMAIN_ID); -1: $ROS_DOMAIN_ID, else 0", -1, 232),
    asf::keyEnum("discovery", "default", "default|loopback",
                 "default: DDS discovery as ROS 2 does it (multicast, or CYCLONEDDS_URI); loopback: "
                 "unicast to 127.0.0.1 on the loopback interface only, no multicast (tests)"),
    asf::keyString("scan_topic", "/scan", "sensor_msgs/LaserScan topic"),
    asf::keyEnum("scan_qos", "sensor_data", "sensor_data|reliable",
                 "QoS of the scan subscription: sensor_data (best effort; matches every "
                 "publisher) or reliable (matches reliable publishers only)"),
    asf::keyEnum("odometry", "topic", "topic|tf",
                 "Where the odometry comes from: odom_topic (nav_msgs/Odometry), or the transform "
                 "odom_frame -> base_frame on tf_topic"),
    asf::keyString("odom_topic", "/odom", "nav_msgs/Odometry topic (odometry = topic)"),
    asf::keyEnum("odom_qos", "sensor_data", "sensor_data|reliable",
                 "QoS of the odometry subscription: sensor_data (best effort: matches every "
                 "publisher, and acknowledges no message) or reliable"),
    asf::keyString("tf_topic", "/tf", "tf2_msgs/TFMessage topic of the moving transforms"),
    asf::keyString("tf_static_topic", "/tf_static",
                   "tf2_msgs/TFMessage topic of the fixed transforms (the laser's mounting)"),
    asf::keyString("map_frame", "map", "REP 105 map frame (asf publishes map -> odom)"),
    asf::keyString("odom_frame", "odom", "REP 105 odometry frame"),
    asf::keyString("base_frame", "base_link",
                   "Robot frame of odometry = tf (with odometry = topic, the odometry's child "
                   "frame is the robot frame)"),
    asf::keyBool("use_sim_time", "false",
                 "Stamp goals with the robot's clock (a simulator's), not the system "
                 "clock: the time on clock_topic, or without one the newest odometry stamp"),
    asf::keyString("clock_topic", "",
                   "rosgraph_msgs/Clock topic read with use_sim_time (e.g. /clock); empty: the "
                   "odometry's stamps are the robot's clock (a simulator's /clock can come at "
                   "1 kHz, each message costing the bridge as much as a scan)"),
    asf::keyDouble("odom_tolerance_s", "0.1",
                   "A scan needs odometry within this of its stamp (interpolated between two "
                   "around it) [s]",
                   0, 100),
    asf::keyDouble("startup_timeout_s", "30",
                   "Wait this long for the first scan, the laser's transform and the world map [s]",
                   0.1, 1e6),
    asf::keyDouble("message_timeout_s", "5",
                   "A run stops with an error naming the topic when no scan (or no odometry for "
                   "one) came for this long [s]",
                   0.1, 1e6),
    asf::keyEnum("drive", "none", "none|nav2|cmd_vel",
                 "none: asf maps while something else drives (a passive source); nav2: asf's "
                 "policy explores by sending goals to a navigator; cmd_vel: asf plans on its map "
                 "and drives the robot with velocity commands"),
    asf::keyString("goal_topic", "/goal_pose", "geometry_msgs/PoseStamped goal topic (drive = nav2)"),
    asf::keyString("nav_status_topic", "/navigate_to_pose/_action/status",
                   "action_msgs/GoalStatusArray topic of the navigator's action (drive = nav2)"),
    asf::keyDouble("goal_accept_timeout_s", "5",
                   "A goal no navigator accepted within this is a failed goal [s]", 0.1, 1e6),
    asf::keyDouble("goal_timeout_s", "0",
                   "A goal running longer than this is a failed goal (nav2: wall clock; cmd_vel: "
                   "robot clock); 0: no limit [s]",
                   0, 1e9),
    asf::keyString("cmd_vel_topic", "/cmd_vel",
                   "geometry_msgs/Twist topic of the robot's base (drive = cmd_vel)"),
    asf::keyDouble("max_speed", "0.5", "drive = cmd_vel: the fastest asf drives the robot [m/s]",
                   0.01, 10),
    asf::keyDouble("max_turn_rate_deg", "100", "drive = cmd_vel: the fastest asf turns it [deg/s]",
                   1, 3600),
    asf::keyDouble("heading_tolerance_deg", "20",
                   "drive = cmd_vel: above this heading error to the path the robot turns in "
                   "place [deg]",
                   1, 90),
    asf::keyDouble("lookahead", "0.2", "drive = cmd_vel: steer towards the path this far ahead [m]",
                   0.01, 10),
    asf::keyDouble("stuck_timeout_s", "10",
                   "drive = cmd_vel: a goal is failed when the path left did not shrink by 0.1 m "
                   "for this long (robot clock) [s]",
                   0.1, 1e6),
    asf::keyDouble("replan_period_s", "2",
                   "drive = cmd_vel: replan on the newest map and scan this often (robot clock); "
                   "0: once per goal [s]",
                   0, 1e6),
    asf::keyDouble("nav_safety_margin", "0.05",
                   "drive = cmd_vel: paths keep robot_radius plus this from obstacles [m]", 0, 1),
    asf::keyDouble("nav_inflation_margin", "0.4",
                   "drive = cmd_vel: beyond that, paths are penalised this close to obstacles [m]",
                   0, 100),
    asf::keyDouble("nav_unknown_cost", "4.0",
                   "drive = cmd_vel: cost factor of a path through unknown space", 1, 1e6),
    asf::keyString("map_topic", "/map",
                   "nav_msgs/OccupancyGrid of asf's map (reliable, transient local)"),
    asf::keyDouble("map_period_s", "1.0",
                   "Publish the map at most this often (robot clock), and only when it changed [s]",
                   0, 1e6),
    asf::keyString("marker_topic", "/asf/markers",
                   "visualization_msgs/MarkerArray: robot, goal, pose graph, regions, topological "
                   "graph, frontier edges"),
    asf::keyDouble("marker_period_s", "1.0", "Publish the markers at most this often (robot clock) [s]",
                   0, 1e6),
    asf::keyString("status_topic", "/asf/status",
                   "std_msgs/String (JSON): the run's state (exploring, paused, returning_home, "
                   "ended), goal and counters"),
    asf::keyString("command_topic", "/asf/command",
                   "std_msgs/String an operator sends: start (or resume), pause, stop, return_home"),
    asf::keyBool("wait_for_start", "false",
                 "The run starts paused: it maps, the robot stays, until 'start' on command_topic"),
    asf::keyString("ground_truth_topic", "",
                   "nav_msgs/Odometry of the true pose (a simulator's); empty: none"),
    asf::keyString("world_map_topic", "",
                   "nav_msgs/OccupancyGrid of the true world (a simulator's), for coverage; empty: none"),
    asf::keyDouble("robot_radius", "0.2",
                   "Robot radius, for the coverage of the true world and drive = cmd_vel's paths [m]",
                   0.01, 100),
    asf::keyDouble("odo_a1", "0.01", "Odometry covariance (MRPT Gaussian): xy std per metre [m/m]", 0, 10),
    asf::keyDouble("odo_a2", "0.001", "Odometry covariance: xy std per degree [m/deg]", 0, 10),
    asf::keyDouble("odo_a3", "1.0", "Odometry covariance: heading std per metre [deg/m]", 0, 1000),
    asf::keyDouble("odo_a4", "0.05", "Odometry covariance: heading std per degree [deg/deg]", 0, 10),
    asf::keyDouble("odo_min_std_xy", "0.001", "Odometry covariance: minimum xy std [m]", 0, 10),
    asf::keyDouble("odo_min_std_phi_deg", "0.05", "Odometry covariance: minimum heading std [deg]", 0, 360),
    asf::keyBool("record", "true",
                 "Record the run to <output>/<record_name>.rawlog (and .gt.txt with ground truth)"),
    asf::keyString("record_name", "ros2", "Base name of the recorded files"),
    asf::keyBool("bag", "false",
                 "Also write the run as a rosbag2 bag with MCAP storage, <output>/<record_name>_bag/: "
                 "the scans, odometry, tf, tf_static and ground truth received, the map -> odom, "
                 "/map, markers and goals published"),
};

}  // namespace
