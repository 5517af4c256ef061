// ROS 1 bags through the official ROS 1 library (rosbag_storage): topics, and every message's
// serialized bytes in time order; the messages are decoded by rosbag2.cpp's reader (Wire::Ros1).
#include <asf/errors.h>
#include <ros/serialization.h>
#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <rosbag/view.h>

#include <filesystem>
#include <map>
#include <set>

#include "asf/io/rosbag2.h"

namespace asf::io {

namespace {

/// "pkg/Type" as ROS 2 spells it, "pkg/msg/Type".
std::string ros2Type(const std::string& t) {
  const auto slash = t.find('/');
  if (slash == std::string::npos || t.find("/msg/") != std::string::npos) return t;
  return t.substr(0, slash) + "/msg/" + t.substr(slash + 1);
}

}  // namespace

struct Ros1BagReader::Impl {
  std::string file;
  rosbag::Bag bag;
  std::vector<BagTopic> topics;
};

Ros1BagReader::Ros1BagReader(const std::string& path) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.file = path;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": no such ROS 1 bag");
  try {
    m.bag.open(path, rosbag::bagmode::Read);
    rosbag::View all(m.bag);
    std::map<std::string, std::size_t> by_name;
    for (const rosbag::ConnectionInfo* c : all.getConnections()) {
      auto it = by_name.find(c->topic);
      if (it == by_name.end()) {
        it = by_name.emplace(c->topic, m.topics.size()).first;
        m.topics.push_back({c->topic, ros2Type(c->datatype), "ros1", 0});
      }
    }
    for (auto& t : m.topics) t.messages = rosbag::View(m.bag, rosbag::TopicQuery(t.name)).size();
  } catch (const rosbag::BagException& e) {
    throw InputError(path + ": not a readable ROS 1 bag (" + e.what() + ")");
  }
}

Ros1BagReader::~Ros1BagReader() = default;

const std::vector<BagTopic>& Ros1BagReader::topics() const { return impl_->topics; }

void Ros1BagReader::visit(const std::vector<std::string>& topics, Visitor v, void* ctx) const {
  std::vector<std::uint8_t> buf;
  try {
    // The view merges the bag's connections in time order (ties in the order written).
    rosbag::View view(impl_->bag, rosbag::TopicQuery(topics));
    for (const rosbag::MessageInstance& msg : view) {
      buf.resize(msg.size());
      ros::serialization::OStream out(buf.data(), static_cast<std::uint32_t>(buf.size()));
      msg.write(out);
      const ros::Time t = msg.getTime();
      if (!v(ctx, msg.getTopic(), static_cast<std::int64_t>(t.sec) * 1000000000 + t.nsec,
             buf.data(), buf.size()))
        return;
    }
  } catch (const rosbag::BagUnindexedException& e) {
    throw InputError(impl_->file + ": the bag is not indexed (reindex it with `rosbag reindex`)");
  } catch (const rosbag::BagException& e) {
    // e.g. a chunk compressed with a format this library was built without
    throw InputError(impl_->file + ": " + e.what());
  }
}

}  // namespace asf::io
