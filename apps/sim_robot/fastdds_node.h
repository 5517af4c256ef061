#pragma once
// The simulated robot's side of the wire: one Fast DDS participant and typed writers and
// readers of the types fastddsgen made from libs/ros2_msgs/idl. The other DDS implementation
// than asf's source plugin (Cyclone DDS), so every exchange between them crosses vendors as two
// ROS 2 nodes on different middlewares do.
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace asf::simrobot {

enum class Qos { SensorData, Reliable, ReliableLatched };

class FastNode {
 public:
  /// Throws std::runtime_error when the participant cannot be made.
  FastNode(int domain_id, bool loopback);
  ~FastNode();  ///< close()
  /// Deletes every reader, writer and the participant: no listener runs after it returns.
  /// Call it before what the listeners use goes away. Idempotent.
  void close();
  FastNode(const FastNode&) = delete;
  FastNode& operator=(const FastNode&) = delete;

  /// A writer of `ros_topic` ("/scan") for the generated type Msg (PubSub: its TopicDataType).
  template <class Msg, class PubSub>
  eprosima::fastdds::dds::DataWriter* writer(const std::string& ros_topic, Qos qos, int depth) {
    return makeWriter(topic(ros_topic, [] { return new PubSub(); }), qos, depth);
  }
  /// A reader whose callback gets every sample (on Fast DDS's thread).
  template <class Msg, class PubSub>
  void reader(const std::string& ros_topic, Qos qos, int depth, std::function<void(const Msg&)> fn) {
    auto l = std::make_unique<Listener<Msg>>(std::move(fn));
    makeReader(topic(ros_topic, [] { return new PubSub(); }), qos, depth, l.get());
    listeners_.push_back(std::move(l));
  }

 private:
  struct ListenerBase : eprosima::fastdds::dds::DataReaderListener {};
  template <class Msg>
  struct Listener : ListenerBase {
    explicit Listener(std::function<void(const Msg&)> f) : fn(std::move(f)) {}
    void on_data_available(eprosima::fastdds::dds::DataReader* r) override {
      Msg m;
      eprosima::fastdds::dds::SampleInfo info;
      while (r->take_next_sample(&m, &info) == ReturnCode_t::RETCODE_OK)
        if (info.valid_data) fn(m);
    }
    std::function<void(const Msg&)> fn;
  };

  eprosima::fastdds::dds::Topic* topic(const std::string& ros_topic,
                                       const std::function<eprosima::fastdds::dds::TopicDataType*()>& make);
  eprosima::fastdds::dds::DataWriter* makeWriter(eprosima::fastdds::dds::Topic* t, Qos qos, int depth);
  void makeReader(eprosima::fastdds::dds::Topic* t, Qos qos, int depth, ListenerBase* l);

  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  std::map<std::string, eprosima::fastdds::dds::Topic*> topics_;
  std::vector<std::unique_ptr<ListenerBase>> listeners_;
};

}  // namespace asf::simrobot
