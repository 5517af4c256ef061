// The ros2 source's keys read into the options of its parts (see source_ros2_options.h).
#include "source_ros2_options.h"

#include <asf/ros2/messages.h>

#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace asf::ros2live {

LinkOptions linkOptions(const asf::Params& p) {
  LinkOptions o;
  o.domain_id = static_cast<int>(p.getInt("domain_id"));
  if (o.domain_id < 0) {
    const char* env = std::getenv("ROS_DOMAIN_ID");
    o.domain_id = env && *env ? std::atoi(env) : 0;
  }
  o.loopback = p.getString("discovery") == "loopback";
  return o;
}

VelocityDriveOptions velocityDriveOptions(const asf::Params& p, double robot_radius,
                                          double goal_timeout) {
  VelocityDriveOptions o;
  o.nav.robot_radius = robot_radius + p.getDouble("nav_safety_margin");
  o.nav.inflation_margin = p.getDouble("nav_inflation_margin");
  o.nav.unknown_cost = p.getDouble("nav_unknown_cost");
  o.follow.max_forward = p.getDouble("max_speed");
  o.follow.max_turn = p.getDouble("max_turn_rate_deg") * M_PI / 180;
  o.follow.heading_tolerance = p.getDouble("heading_tolerance_deg") * M_PI / 180;
  o.follow.lookahead = p.getDouble("lookahead");
  o.follow.stuck_time = p.getDouble("stuck_timeout_s");
  o.replan_period = p.getDouble("replan_period_s");
  o.goal_timeout = goal_timeout;
  return o;
}

void checkTopicNames(const asf::Params& p) {
  for (const char* k : {"scan_topic", "odom_topic", "tf_topic", "tf_static_topic", "clock_topic",
                        "goal_topic", "cmd_vel_topic", "command_topic", "nav_status_topic",
                        "map_topic", "marker_topic", "status_topic", "ground_truth_topic",
                        "world_map_topic"}) {
    const std::string v = p.getString(k);
    if (v.empty() && (std::string(k) == "ground_truth_topic" ||
                      std::string(k) == "world_map_topic" || std::string(k) == "clock_topic"))
      continue;
    try {
      ros2::ddsTopic(v);
    } catch (const std::invalid_argument& e) {
      p.fail(k, e.what());
    }
  }
}

}  // namespace asf::ros2live
