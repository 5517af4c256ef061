#pragma once
// The live source's side of the wire: one Cyclone DDS participant, readers that hand each
// ROS 2 message (converted to asf/ros2/messages.h) to a callback on Cyclone's receive thread,
// and writers. No asf state lives here (live_core.h holds it).
#include <asf/ros2/messages.h>

#include <cstdint>
#include <functional>
#include <list>
#include <string>
#include <utility>
#include <vector>

#include "live_core.h"

namespace asf::ros2live {

enum class Qos {
  SensorData,      ///< best effort, keep last (what ROS 2 drivers publish scans with)
  Reliable,        ///< reliable, volatile, keep last
  ReliableLatched, ///< reliable, transient local, keep last (/map, /tf_static, action status)
};

struct LinkOptions {
  int domain_id = 0;
  bool loopback = false;  ///< unicast discovery to 127.0.0.1 on lo only, no multicast
};

class CycloneLink {
 public:
  /// Throws std::runtime_error (Cyclone's reason) when the participant cannot be created.
  explicit CycloneLink(const LinkOptions& o);
  ~CycloneLink();
  CycloneLink(const CycloneLink&) = delete;
  CycloneLink& operator=(const CycloneLink&) = delete;

  // Readers; `ros_topic` is a ROS 2 name ("/scan"). Callbacks run on Cyclone's thread.
  void onScan(const std::string& ros_topic, Qos qos, int depth,
              std::function<void(ros2::LaserScan)> fn);
  void onOdometry(const std::string& ros_topic, Qos qos, std::function<void(ros2::Odometry)> fn);
  void onTransforms(const std::string& ros_topic, Qos qos,
                    std::function<void(std::vector<ros2::TransformStamped>)> fn);
  void onClock(const std::string& ros_topic, std::function<void(ros2::Stamp)> fn);
  void onGoalStatus(const std::string& ros_topic, std::function<void(std::vector<GoalStatusEntry>)> fn);
  void onOccupancy(const std::string& ros_topic, std::function<void(ros2::OccupancyGrid)> fn);
  /// std_msgs/String, reliable (what `ros2 topic pub` sends by default).
  void onString(const std::string& ros_topic, std::function<void(std::string)> fn);

  // Writers: advertise once, then publish. Each returns false when Cyclone refused the sample.
  int advertiseOccupancy(const std::string& ros_topic);
  int advertiseTransforms(const std::string& ros_topic, Qos qos);
  int advertisePose(const std::string& ros_topic);
  int advertiseString(const std::string& ros_topic);
  int advertiseMarkers(const std::string& ros_topic);
  /// geometry_msgs/Twist, reliable (what teleop and nav2's controller publish on /cmd_vel).
  int advertiseTwist(const std::string& ros_topic);
  bool publish(int writer, const ros2::OccupancyGrid& m);
  bool publish(int writer, const std::vector<ros2::TransformStamped>& m);
  bool publishPose(int writer, const ros2::Stamp& stamp, const std::string& frame,
                   const ros2::Transform& pose);
  bool publishString(int writer, const std::string& text);
  /// A planar velocity: linear.x [m/s] and angular.z [rad/s], the rest zero.
  bool publishTwist(int writer, double forward, double turn);
  /// One visualization_msgs/MarkerArray.
  bool publish(int writer, const std::vector<ros2::Marker>& markers);

  /// The types of the writers discovered on a ROS 2 topic (other participants and ours), for
  /// saying why nothing arrives.
  std::vector<std::string> publisherTypes(const std::string& ros_topic) const;
  /// Why nothing of `type` ("sensor_msgs/LaserScan") came on a ROS 2 topic for `waited` s:
  /// no publisher discovered, publishers of another type, or publishers that sent nothing
  /// we received (stopped, or QoS that does not match). Starts "[ros2] topic T: ".
  std::string whySilent(const std::string& ros_topic, const std::string& type, double waited) const;
  /// Why messages of `type` on a ROS 2 topic go back in time (`back` of them so far), when
  /// more than one publisher of that type is discovered: two robots or drivers on one topic.
  /// Empty with one publisher (a datagram reordered on the wire is no fault).
  std::string whyStampsGoBack(const std::string& ros_topic, const std::string& type,
                              std::uint64_t back) const;
  /// Readers of a ROS 2 topic this participant writes, discovered anywhere.
  std::size_t subscriberCount(const std::string& ros_topic) const;

 private:
  int reader(const void* descriptor, const std::string& ros_topic, Qos qos, int depth,
             std::function<void(int)> on_data);
  int writer(const void* descriptor, const std::string& ros_topic, Qos qos, int depth);
  int topic(const void* descriptor, const std::string& ros_topic);

  int domain_id_ = 0;
  bool loopback_ = false;
  int participant_ = 0, publications_ = 0, subscriptions_ = 0;
  std::list<std::function<void(int)>> callbacks_;  // stable addresses for the listeners
};

}  // namespace asf::ros2live
