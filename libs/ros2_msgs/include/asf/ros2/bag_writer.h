#pragma once
/// \file bag_writer.h
/// A rosbag2 bag with MCAP storage (the default of rosbag2 since ROS 2 Iron; readable by
/// `ros2 bag`, Foxglove, and asf's own bag reader): a folder holding data.mcap and
/// metadata.yaml.
///
/// Contract:
/// - data.mcap: the MCAP magic, a Header (profile "ros2"), then per topic one Schema (encoding
///   "ros2msg", the type's definition from cdr.h) and one Channel (message encoding "cdr"), the
///   messages in the order written (unchunked), DataEnd, Footer and the magic again.
/// - metadata.yaml (rosbag2 version 5) is written by close() (and the destructor), with each
///   topic's message count and the time span; until then the folder is not a complete bag.
/// - Thread-safe: messages may be written from several threads.
#include <cstdint>
#include <fstream>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace asf::ros2 {

class BagWriter {
 public:
  /// Creates the folder (it must not hold a bag already). Throws std::runtime_error naming the
  /// path when it cannot.
  explicit BagWriter(const std::string& folder);
  ~BagWriter();
  BagWriter(const BagWriter&) = delete;
  BagWriter& operator=(const BagWriter&) = delete;

  /// Adds a topic of a ROS 2 type ("sensor_msgs/msg/LaserScan"); returns its channel. The
  /// QoS is recorded as rosbag2 does (offered_qos_profiles, YAML); empty: none.
  int topic(const std::string& name, const std::string& type, const std::string& qos_yaml = "");
  /// One message (CDR bytes with their encapsulation header, cdr.h) at `time_ns`.
  void write(int channel, std::int64_t time_ns, const std::vector<std::uint8_t>& cdr);
  /// Ends data.mcap and writes metadata.yaml; later writes are ignored.
  void close();
  std::uint64_t messages() const;

 private:
  void record(std::uint8_t op, const std::string& body);
  struct Topic {
    std::string name, type, qos;
    std::uint64_t count = 0;
  };
  mutable std::mutex mu_;
  std::string folder_;
  std::ofstream out_;
  std::vector<Topic> topics_;
  std::uint64_t messages_ = 0;
  std::int64_t first_ns_ = 0, last_ns_ = 0;
  bool closed_ = false;
};

}  // namespace asf::ros2
