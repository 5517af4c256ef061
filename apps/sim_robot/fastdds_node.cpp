// The simulated robot's Fast DDS participant (fastdds_node.h).
#include "fastdds_node.h"

#include <asf/ros2/messages.h>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>

namespace asf::simrobot {

using namespace eprosima::fastdds::dds;

FastNode::FastNode(int domain_id, bool loopback) {
  DomainParticipantQos pq = PARTICIPANT_QOS_DEFAULT;
  pq.name("asf_sim_robot");
  if (loopback) {
    // Unicast discovery to 127.0.0.1 over the loopback interface only, no multicast.
    pq.transport().use_builtin_transports = false;
    auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
    udp->interfaceWhiteList.emplace_back("127.0.0.1");
    udp->maxInitialPeersRange = 20;
    pq.transport().user_transports.push_back(udp);
    eprosima::fastrtps::rtps::Locator_t peer;
    eprosima::fastrtps::rtps::IPLocator::setIPv4(peer, 127, 0, 0, 1);
    pq.wire_protocol().builtin.initialPeersList.push_back(peer);
    pq.wire_protocol().builtin.avoid_builtin_multicast = true;
    pq.wire_protocol().builtin.metatrafficMulticastLocatorList.clear();
  }
  participant_ = DomainParticipantFactory::get_instance()->create_participant(
      static_cast<DomainId_t>(domain_id), pq);
  if (!participant_)
    throw std::runtime_error("Fast DDS: cannot create a participant in domain " + std::to_string(domain_id));
  publisher_ = participant_->create_publisher(PUBLISHER_QOS_DEFAULT);
  subscriber_ = participant_->create_subscriber(SUBSCRIBER_QOS_DEFAULT);
}

FastNode::~FastNode() { close(); }

void FastNode::close() {
  if (!participant_) return;
  participant_->delete_contained_entities();
  DomainParticipantFactory::get_instance()->delete_participant(participant_);
  participant_ = nullptr;
}

Topic* FastNode::topic(const std::string& ros_topic, const std::function<TopicDataType*()>& make) {
  const std::string name = ros2::ddsTopic(ros_topic);
  const auto it = topics_.find(name);
  if (it != topics_.end()) return it->second;
  TypeSupport type(make());
  type.register_type(participant_);
  Topic* t = participant_->create_topic(name, type.get_type_name(), TOPIC_QOS_DEFAULT);
  if (!t) throw std::runtime_error("Fast DDS: cannot create topic " + ros_topic);
  topics_[name] = t;
  return t;
}

namespace {
template <class Q>
void applyQos(Q& q, Qos qos, int depth) {
  q.reliability().kind = qos == Qos::SensorData ? BEST_EFFORT_RELIABILITY_QOS : RELIABLE_RELIABILITY_QOS;
  q.durability().kind = qos == Qos::ReliableLatched ? TRANSIENT_LOCAL_DURABILITY_QOS : VOLATILE_DURABILITY_QOS;
  q.history().kind = KEEP_LAST_HISTORY_QOS;
  q.history().depth = depth;
}
}  // namespace

DataWriter* FastNode::makeWriter(Topic* t, Qos qos, int depth) {
  DataWriterQos q = DATAWRITER_QOS_DEFAULT;
  applyQos(q, qos, depth);
  // Payloads of any size (maps): grown as needed, sent from Fast DDS's own thread.
  q.endpoint().history_memory_policy = eprosima::fastrtps::rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE;
  q.publish_mode().kind = ASYNCHRONOUS_PUBLISH_MODE;
  DataWriter* w = publisher_->create_datawriter(t, q);
  if (!w) throw std::runtime_error("Fast DDS: cannot create a writer of " + t->get_name());
  return w;
}

void FastNode::makeReader(Topic* t, Qos qos, int depth, ListenerBase* l) {
  DataReaderQos q = DATAREADER_QOS_DEFAULT;
  applyQos(q, qos, depth);
  q.endpoint().history_memory_policy = eprosima::fastrtps::rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE;
  if (!subscriber_->create_datareader(t, q, l))
    throw std::runtime_error("Fast DDS: cannot create a reader of " + t->get_name());
}

}  // namespace asf::simrobot
