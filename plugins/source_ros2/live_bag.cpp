// A live run as a rosbag2 bag (live_bag.h).
#include "live_bag.h"

#include <asf/ros2/cdr.h>

namespace asf::ros2live {

namespace {
std::int64_t ns(const ros2::Stamp& s) {
  return static_cast<std::int64_t>(s.sec) * 1000000000LL + s.nanosec;
}
// What rosbag2 records as a topic's QoS (offered_qos_profiles), for a player to offer again.
std::string qos(const char* reliability, const char* durability, int depth) {
  return std::string("- history: keep_last\n  depth: ") + std::to_string(depth) +
         "\n  reliability: " + reliability + "\n  durability: " + durability + "\n";
}
}  // namespace

void LiveBag::open(const std::string& folder, const LiveBagTopics& t) {
  w_ = std::make_unique<ros2::BagWriter>(folder);
  folder_ = folder;
  auto add = [&](const std::string& name, const char* type, const std::string& q) {
    return name.empty() ? 0 : w_->topic(name, type, q);
  };
  scan_ = add(t.scan, "sensor_msgs/msg/LaserScan", qos("best_effort", "volatile", 5));
  odom_ = add(t.odom, "nav_msgs/msg/Odometry", qos("reliable", "volatile", 10));
  tf_ = add(t.tf, "tf2_msgs/msg/TFMessage", qos("reliable", "volatile", 100));
  tf_static_ = add(t.tf_static, "tf2_msgs/msg/TFMessage", qos("reliable", "transient_local", 1));
  gt_ = add(t.ground_truth, "nav_msgs/msg/Odometry", qos("reliable", "volatile", 10));
  map_ = add(t.map, "nav_msgs/msg/OccupancyGrid", qos("reliable", "transient_local", 1));
  markers_ = add(t.markers, "visualization_msgs/msg/MarkerArray", qos("reliable", "volatile", 5));
  goal_ = add(t.goal, "geometry_msgs/msg/PoseStamped", qos("reliable", "volatile", 10));
}

void LiveBag::scan(const ros2::LaserScan& m) {
  if (w_ && scan_) w_->write(scan_, ns(m.stamp), ros2::cdrLaserScan(m));
}
void LiveBag::odometry(const ros2::Odometry& m) {
  if (w_ && odom_) w_->write(odom_, ns(m.stamp), ros2::cdrOdometry(m));
}
void LiveBag::groundTruth(const ros2::Odometry& m) {
  if (w_ && gt_) w_->write(gt_, ns(m.stamp), ros2::cdrOdometry(m));
}
void LiveBag::transforms(const std::vector<ros2::TransformStamped>& m, bool is_static) {
  const int ch = is_static ? tf_static_ : tf_;
  if (w_ && ch && !m.empty()) w_->write(ch, ns(m.front().stamp), ros2::cdrTfMessage(m));
}
void LiveBag::map(const ros2::OccupancyGrid& m) {
  if (w_ && map_) w_->write(map_, ns(m.stamp), ros2::cdrOccupancyGrid(m));
}
void LiveBag::markers(const std::vector<ros2::Marker>& m) {
  if (w_ && markers_ && !m.empty()) w_->write(markers_, ns(m.front().stamp), ros2::cdrMarkerArray(m));
}
void LiveBag::goal(const ros2::Stamp& stamp, const std::string& frame, const ros2::Transform& pose) {
  if (w_ && goal_) w_->write(goal_, ns(stamp), ros2::cdrPoseStamped(stamp, frame, pose));
}

std::uint64_t LiveBag::close() {
  if (!w_) return 0;
  const auto w = std::move(w_);  // closed once, even when the close throws
  w->close();
  return w->messages();
}

}  // namespace asf::ros2live
