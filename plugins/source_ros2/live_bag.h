#pragma once
// A live run as a rosbag2 bag (MCAP): what the ros2 source received (scans, odometry, tf,
// tf_static, ground truth) and what it published (map -> odom, /map, markers, goals), each on
// its topic, stamped with the message's own time. Safe to call from the receive thread and the
// run's thread at once; every call does nothing when no bag was opened.
#include <asf/ros2/bag_writer.h>
#include <asf/ros2/messages.h>

#include <memory>
#include <string>
#include <vector>

namespace asf::ros2live {

struct LiveBagTopics {
  std::string scan, odom, tf, tf_static, ground_truth, map, markers, goal;  ///< "" = not recorded
};

class LiveBag {
 public:
  /// Opens the bag folder (throws std::runtime_error naming it).
  void open(const std::string& folder, const LiveBagTopics& topics);
  void scan(const ros2::LaserScan& m);
  void odometry(const ros2::Odometry& m);
  void groundTruth(const ros2::Odometry& m);
  void transforms(const std::vector<ros2::TransformStamped>& m, bool is_static);
  void map(const ros2::OccupancyGrid& m);
  void markers(const std::vector<ros2::Marker>& m);
  void goal(const ros2::Stamp& stamp, const std::string& frame, const ros2::Transform& pose);
  /// Writes metadata.yaml; returns the messages written (0 without a bag or when closed).
  std::uint64_t close();
  const std::string& folder() const { return folder_; }
  bool isOpen() const { return w_ != nullptr; }

 private:
  std::unique_ptr<ros2::BagWriter> w_;
  std::string folder_;
  int scan_ = 0, odom_ = 0, tf_ = 0, tf_static_ = 0, gt_ = 0, map_ = 0, markers_ = 0, goal_ = 0;
};

}  // namespace asf::ros2live
