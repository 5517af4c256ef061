// The live source's Cyclone DDS participant (cyclone_link.h): ROS 2 topics are DDS topics
// "rt/<name>" of the types generated from libs/ros2_msgs/idl.
#include "cyclone_link.h"

#include <dds/dds.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include "action_msgs.h"
#include "geometry_msgs.h"
#include "nav_msgs.h"
#include "rosgraph_msgs.h"
#include "sensor_msgs.h"
#include "std_msgs.h"
#include "tf2_msgs.h"
#include "visualization_msgs.h"

namespace asf::ros2live {

namespace {

std::runtime_error ddsError(const std::string& what, dds_return_t rc) {
  return std::runtime_error(what + ": " + dds_strretcode(rc));
}

extern "C" void onDataAvailable(dds_entity_t reader, void* arg) {
  (*static_cast<std::function<void(int)>*>(arg))(reader);
}

// Takes every sample waiting in `rd` and hands the valid ones to fn.
template <class Sample, class Fn>
void takeAll(dds_entity_t rd, Fn&& fn) {
  constexpr int kBatch = 16;
  void* samples[kBatch];
  dds_sample_info_t infos[kBatch];
  for (;;) {
    for (void*& s : samples) s = nullptr;
    const int n = dds_take(rd, samples, infos, kBatch, kBatch);
    if (n <= 0) return;
    for (int i = 0; i < n; ++i)
      if (infos[i].valid_data) fn(*static_cast<const Sample*>(samples[i]));
    dds_return_loan(rd, samples, n);
  }
}

ros2::Stamp stampOf(const builtin_interfaces_msg_dds__Time_& t) { return {t.sec, t.nanosec}; }
builtin_interfaces_msg_dds__Time_ timeOf(const ros2::Stamp& s) { return {s.sec, s.nanosec}; }
std::string str(const char* s) { return s ? std::string(s) : std::string(); }

ros2::Transform fromPose(const geometry_msgs_msg_dds__Pose_& p) {
  return {p.position.x,    p.position.y,    p.position.z,   p.orientation.x,
          p.orientation.y, p.orientation.z, p.orientation.w};
}
geometry_msgs_msg_dds__Pose_ toPose(const ros2::Transform& t) {
  geometry_msgs_msg_dds__Pose_ p{};
  p.position = {t.tx, t.ty, t.tz};
  p.orientation = {t.qx, t.qy, t.qz, t.qw};
  return p;
}

dds_qos_t* makeQos(Qos qos, int depth) {
  dds_qos_t* q = dds_create_qos();
  dds_qset_reliability(q, qos == Qos::SensorData ? DDS_RELIABILITY_BEST_EFFORT : DDS_RELIABILITY_RELIABLE,
                       DDS_SECS(1));
  dds_qset_durability(q, qos == Qos::ReliableLatched ? DDS_DURABILITY_TRANSIENT_LOCAL
                                                     : DDS_DURABILITY_VOLATILE);
  dds_qset_history(q, DDS_HISTORY_KEEP_LAST, depth);
  return q;
}

}  // namespace

namespace {
// A process creates a configured domain once: the instances of the plugin in one process
// (the conformance kit makes several at once) share it, the last one deletes it.
std::mutex g_domains_mu;
std::map<int, std::pair<dds_entity_t, int>> g_domains;  // domain id -> (handle, users)

void acquireLoopbackDomain(int id) {
  std::lock_guard<std::mutex> lock(g_domains_mu);
  auto it = g_domains.find(id);
  if (it != g_domains.end()) {
    ++it->second.second;
    return;
  }
  const dds_entity_t d =
      dds_create_domain(static_cast<dds_domainid_t>(id), ros2::cycloneLoopbackXml(20).c_str());
  if (d < 0)
    throw ddsError("cannot create the DDS domain " + std::to_string(id) +
                       " (a participant of this process already uses it with another "
                       "configuration?)",
                   d);
  g_domains[id] = {d, 1};
}

void releaseLoopbackDomain(int id) {
  std::lock_guard<std::mutex> lock(g_domains_mu);
  auto it = g_domains.find(id);
  if (it == g_domains.end() || --it->second.second > 0) return;
  dds_delete(it->second.first);
  g_domains.erase(it);
}
}  // namespace

CycloneLink::CycloneLink(const LinkOptions& o) : domain_id_(o.domain_id), loopback_(o.loopback) {
  // A domain of our own configuration, or Cyclone's defaults (and CYCLONEDDS_URI).
  if (loopback_) acquireLoopbackDomain(domain_id_);
  participant_ = dds_create_participant(static_cast<dds_domainid_t>(o.domain_id), nullptr, nullptr);
  if (participant_ < 0) {
    if (loopback_) releaseLoopbackDomain(domain_id_);
    throw ddsError("cannot create a DDS participant in domain " + std::to_string(o.domain_id),
                   participant_);
  }
  publications_ = dds_create_reader(participant_, DDS_BUILTIN_TOPIC_DCPSPUBLICATION, nullptr, nullptr);
  subscriptions_ = dds_create_reader(participant_, DDS_BUILTIN_TOPIC_DCPSSUBSCRIPTION, nullptr, nullptr);
}

CycloneLink::~CycloneLink() {
  // Deleting the participant waits for listeners in progress; the callbacks outlive it.
  dds_delete(participant_);
  if (loopback_) releaseLoopbackDomain(domain_id_);
}

int CycloneLink::topic(const void* descriptor, const std::string& ros_topic) {
  const std::string name = ros2::ddsTopic(ros_topic);
  const dds_entity_t t = dds_create_topic(
      participant_, static_cast<const dds_topic_descriptor_t*>(descriptor), name.c_str(), nullptr, nullptr);
  if (t < 0) throw ddsError("topic " + ros_topic, t);
  return t;
}

int CycloneLink::reader(const void* descriptor, const std::string& ros_topic, Qos qos, int depth,
                        std::function<void(int)> on_data) {
  const dds_entity_t t = topic(descriptor, ros_topic);
  callbacks_.push_back(std::move(on_data));
  dds_listener_t* l = dds_create_listener(&callbacks_.back());
  dds_lset_data_available(l, onDataAvailable);
  dds_qos_t* q = makeQos(qos, depth);
  // Not our own writers' samples (the map -> odom we publish on the /tf we read).
  dds_qset_ignorelocal(q, DDS_IGNORELOCAL_PARTICIPANT);
  const dds_entity_t rd = dds_create_reader(participant_, t, q, l);
  dds_delete_qos(q);
  dds_delete_listener(l);
  if (rd < 0) throw ddsError("reader of " + ros_topic, rd);
  return rd;
}

int CycloneLink::writer(const void* descriptor, const std::string& ros_topic, Qos qos, int depth) {
  const dds_entity_t t = topic(descriptor, ros_topic);
  dds_qos_t* q = makeQos(qos, depth);
  const dds_entity_t wr = dds_create_writer(participant_, t, q, nullptr);
  dds_delete_qos(q);
  if (wr < 0) throw ddsError("writer of " + ros_topic, wr);
  return wr;
}

void CycloneLink::onScan(const std::string& ros_topic, Qos qos, int depth,
                         std::function<void(ros2::LaserScan)> fn) {
  reader(&sensor_msgs_msg_dds__LaserScan__desc, ros_topic, qos, depth, [fn](int rd) {
    takeAll<sensor_msgs_msg_dds__LaserScan_>(rd, [&](const sensor_msgs_msg_dds__LaserScan_& s) {
      ros2::LaserScan m;
      m.stamp = stampOf(s.header.stamp);
      m.frame_id = str(s.header.frame_id);
      m.angle_min = s.angle_min, m.angle_max = s.angle_max, m.angle_increment = s.angle_increment;
      m.time_increment = s.time_increment, m.scan_time = s.scan_time;
      m.range_min = s.range_min, m.range_max = s.range_max;
      m.ranges.assign(s.ranges._buffer, s.ranges._buffer + s.ranges._length);
      m.intensities.assign(s.intensities._buffer, s.intensities._buffer + s.intensities._length);
      fn(std::move(m));
    });
  });
}

void CycloneLink::onOdometry(const std::string& ros_topic, Qos qos,
                             std::function<void(ros2::Odometry)> fn) {
  reader(&nav_msgs_msg_dds__Odometry__desc, ros_topic, qos, 100, [fn](int rd) {
    takeAll<nav_msgs_msg_dds__Odometry_>(rd, [&](const nav_msgs_msg_dds__Odometry_& s) {
      fn({stampOf(s.header.stamp), str(s.header.frame_id), str(s.child_frame_id), fromPose(s.pose.pose)});
    });
  });
}

void CycloneLink::onTransforms(const std::string& ros_topic, Qos qos,
                               std::function<void(std::vector<ros2::TransformStamped>)> fn) {
  reader(&tf2_msgs_msg_dds__TFMessage__desc, ros_topic, qos, 100, [fn](int rd) {
    takeAll<tf2_msgs_msg_dds__TFMessage_>(rd, [&](const tf2_msgs_msg_dds__TFMessage_& s) {
      std::vector<ros2::TransformStamped> out;
      for (std::uint32_t i = 0; i < s.transforms._length; ++i) {
        const auto& t = s.transforms._buffer[i];
        const auto& tr = t.transform;
        out.push_back({stampOf(t.header.stamp), str(t.header.frame_id), str(t.child_frame_id),
                       {tr.translation.x, tr.translation.y, tr.translation.z, tr.rotation.x,
                        tr.rotation.y, tr.rotation.z, tr.rotation.w}});
      }
      fn(std::move(out));
    });
  });
}

void CycloneLink::onClock(const std::string& ros_topic, std::function<void(ros2::Stamp)> fn) {
  reader(&rosgraph_msgs_msg_dds__Clock__desc, ros_topic, Qos::SensorData, 1, [fn](int rd) {
    takeAll<rosgraph_msgs_msg_dds__Clock_>(rd, [&](const rosgraph_msgs_msg_dds__Clock_& s) { fn(stampOf(s.clock)); });
  });
}

void CycloneLink::onGoalStatus(const std::string& ros_topic,
                               std::function<void(std::vector<GoalStatusEntry>)> fn) {
  reader(&action_msgs_msg_dds__GoalStatusArray__desc, ros_topic, Qos::ReliableLatched, 1, [fn](int rd) {
    takeAll<action_msgs_msg_dds__GoalStatusArray_>(rd, [&](const action_msgs_msg_dds__GoalStatusArray_& s) {
      std::vector<GoalStatusEntry> out;
      for (std::uint32_t i = 0; i < s.status_list._length; ++i) {
        const auto& g = s.status_list._buffer[i];
        GoalStatusEntry e;
        std::memcpy(e.id.data(), g.goal_info.goal_id.uuid, 16);
        e.stamp = stampOf(g.goal_info.stamp);
        e.status = g.status;
        out.push_back(e);
      }
      fn(std::move(out));
    });
  });
}

void CycloneLink::onOccupancy(const std::string& ros_topic, std::function<void(ros2::OccupancyGrid)> fn) {
  reader(&nav_msgs_msg_dds__OccupancyGrid__desc, ros_topic, Qos::ReliableLatched, 1, [fn](int rd) {
    takeAll<nav_msgs_msg_dds__OccupancyGrid_>(rd, [&](const nav_msgs_msg_dds__OccupancyGrid_& s) {
      ros2::OccupancyGrid m;
      m.stamp = stampOf(s.header.stamp);
      m.frame_id = str(s.header.frame_id);
      m.resolution = s.info.resolution;
      m.width = s.info.width, m.height = s.info.height;
      m.origin = fromPose(s.info.origin);
      m.data.assign(s.data._buffer, s.data._buffer + s.data._length);
      fn(std::move(m));
    });
  });
}

void CycloneLink::onString(const std::string& ros_topic, std::function<void(std::string)> fn) {
  reader(&std_msgs_msg_dds__String__desc, ros_topic, Qos::Reliable, 10, [fn](int rd) {
    takeAll<std_msgs_msg_dds__String_>(rd, [&](const std_msgs_msg_dds__String_& s) { fn(str(s.data)); });
  });
}

int CycloneLink::advertiseOccupancy(const std::string& ros_topic) {
  return writer(&nav_msgs_msg_dds__OccupancyGrid__desc, ros_topic, Qos::ReliableLatched, 1);
}
int CycloneLink::advertiseTransforms(const std::string& ros_topic, Qos qos) {
  return writer(&tf2_msgs_msg_dds__TFMessage__desc, ros_topic, qos, 100);
}
int CycloneLink::advertisePose(const std::string& ros_topic) {
  return writer(&geometry_msgs_msg_dds__PoseStamped__desc, ros_topic, Qos::Reliable, 10);
}
int CycloneLink::advertiseMarkers(const std::string& ros_topic) {
  return writer(&visualization_msgs_msg_dds__MarkerArray__desc, ros_topic, Qos::Reliable, 5);
}
int CycloneLink::advertiseTwist(const std::string& ros_topic) {
  return writer(&geometry_msgs_msg_dds__Twist__desc, ros_topic, Qos::Reliable, 10);
}
int CycloneLink::advertiseString(const std::string& ros_topic) {
  return writer(&std_msgs_msg_dds__String__desc, ros_topic, Qos::ReliableLatched, 1);
}

bool CycloneLink::publish(int writer, const ros2::OccupancyGrid& m) {
  nav_msgs_msg_dds__OccupancyGrid_ s{};
  s.header.stamp = timeOf(m.stamp);
  s.header.frame_id = const_cast<char*>(m.frame_id.c_str());
  s.info.map_load_time = timeOf(m.stamp);
  s.info.resolution = m.resolution;
  s.info.width = m.width, s.info.height = m.height;
  s.info.origin = toPose(m.origin);
  s.data._buffer = const_cast<std::int8_t*>(m.data.data());
  s.data._length = s.data._maximum = static_cast<std::uint32_t>(m.data.size());
  s.data._release = false;
  return dds_write(writer, &s) == DDS_RETCODE_OK;
}

bool CycloneLink::publish(int writer, const std::vector<ros2::TransformStamped>& m) {
  std::vector<geometry_msgs_msg_dds__TransformStamped_> ts(m.size());
  for (std::size_t i = 0; i < m.size(); ++i) {
    auto& t = ts[i];
    t.header.stamp = timeOf(m[i].stamp);
    t.header.frame_id = const_cast<char*>(m[i].parent.c_str());
    t.child_frame_id = const_cast<char*>(m[i].child.c_str());
    const ros2::Transform& tr = m[i].transform;
    t.transform.translation = {tr.tx, tr.ty, tr.tz};
    t.transform.rotation = {tr.qx, tr.qy, tr.qz, tr.qw};
  }
  tf2_msgs_msg_dds__TFMessage_ s{};
  s.transforms._buffer = ts.data();
  s.transforms._length = s.transforms._maximum = static_cast<std::uint32_t>(ts.size());
  s.transforms._release = false;
  return dds_write(writer, &s) == DDS_RETCODE_OK;
}

bool CycloneLink::publishPose(int writer, const ros2::Stamp& stamp, const std::string& frame,
                              const ros2::Transform& pose) {
  geometry_msgs_msg_dds__PoseStamped_ s{};
  s.header.stamp = timeOf(stamp);
  s.header.frame_id = const_cast<char*>(frame.c_str());
  s.pose = toPose(pose);
  return dds_write(writer, &s) == DDS_RETCODE_OK;
}

bool CycloneLink::publishString(int writer, const std::string& text) {
  std_msgs_msg_dds__String_ s{};
  s.data = const_cast<char*>(text.c_str());
  return dds_write(writer, &s) == DDS_RETCODE_OK;
}

bool CycloneLink::publishTwist(int writer, double forward, double turn) {
  geometry_msgs_msg_dds__Twist_ s{};
  s.linear.x = forward;
  s.angular.z = turn;
  return dds_write(writer, &s) == DDS_RETCODE_OK;
}

bool CycloneLink::publish(int writer, const std::vector<ros2::Marker>& markers) {
  // The samples point into these; every string is set (Cyclone's serializer reads them all).
  static char empty[] = "";
  std::vector<visualization_msgs_msg_dds__Marker_> ms(markers.size());
  std::vector<std::vector<geometry_msgs_msg_dds__Point_>> points(markers.size());
  std::vector<std::vector<std_msgs_msg_dds__ColorRGBA_>> colors(markers.size());
  for (std::size_t i = 0; i < markers.size(); ++i) {
    const ros2::Marker& m = markers[i];
    auto& s = ms[i];
    s = visualization_msgs_msg_dds__Marker_{};
    s.header.stamp = timeOf(m.stamp);
    s.header.frame_id = const_cast<char*>(m.frame_id.c_str());
    s.ns = const_cast<char*>(m.ns.c_str());
    s.id = m.id, s.type = m.type, s.action = m.action;
    s.pose = toPose(m.pose);
    s.scale = {m.scale[0], m.scale[1], m.scale[2]};
    s.color = {m.color[0], m.color[1], m.color[2], m.color[3]};
    for (const auto& p : m.points) points[i].push_back({p[0], p[1], p[2]});
    for (const auto& c : m.colors) colors[i].push_back({c[0], c[1], c[2], c[3]});
    s.points._buffer = points[i].data();
    s.points._length = s.points._maximum = static_cast<std::uint32_t>(points[i].size());
    s.colors._buffer = colors[i].data();
    s.colors._length = s.colors._maximum = static_cast<std::uint32_t>(colors[i].size());
    s.text = const_cast<char*>(m.text.c_str());
    s.texture_resource = s.mesh_resource = empty;
    s.texture.header.frame_id = s.texture.format = empty;
    s.mesh_file.filename = empty;
  }
  visualization_msgs_msg_dds__MarkerArray_ a{};
  a.markers._buffer = ms.data();
  a.markers._length = a.markers._maximum = static_cast<std::uint32_t>(ms.size());
  return dds_write(writer, &a) == DDS_RETCODE_OK;
}

namespace {
// Every alive endpoint of a builtin reader (DCPSPublication or DCPSSubscription) on `topic`.
std::vector<std::string> endpointTypes(dds_entity_t builtin, const std::string& topic) {
  std::vector<std::string> out;
  constexpr int kMax = 256;
  void* samples[kMax] = {nullptr};
  dds_sample_info_t infos[kMax];
  const int n = dds_read_mask(builtin, samples, infos, kMax, kMax,
                              DDS_ANY_SAMPLE_STATE | DDS_ANY_VIEW_STATE | DDS_ALIVE_INSTANCE_STATE);
  for (int i = 0; i < n; ++i) {
    if (!infos[i].valid_data) continue;
    const auto* ep = static_cast<const dds_builtintopic_endpoint_t*>(samples[i]);
    if (ep->topic_name && topic == ep->topic_name) out.push_back(str(ep->type_name));
  }
  if (n > 0) dds_return_loan(builtin, samples, n);
  return out;
}
}  // namespace

std::vector<std::string> CycloneLink::publisherTypes(const std::string& ros_topic) const {
  return endpointTypes(publications_, ros2::ddsTopic(ros_topic));
}

std::size_t CycloneLink::subscriberCount(const std::string& ros_topic) const {
  return endpointTypes(subscriptions_, ros2::ddsTopic(ros_topic)).size();
}

}  // namespace asf::ros2live

namespace asf::ros2live {

namespace {
/// "pkg/Type" is "pkg::msg::dds_::Type_" on the wire.
std::string wireType(const std::string& type) {
  const std::size_t slash = type.find('/');
  return type.substr(0, slash) + "::msg::dds_::" + type.substr(slash + 1) + "_";
}
}  // namespace

std::string CycloneLink::whyStampsGoBack(const std::string& topic, const std::string& type,
                                         std::uint64_t back) const {
  const auto types = publisherTypes(topic);
  const auto n = std::count(types.begin(), types.end(), wireType(type));
  if (n < 2) return {};
  std::ostringstream os;
  os << "[ros2] topic " << topic << ": " << n << " publishers of " << type << ", and " << back
     << " messages were stamped before the one received ahead of them: two robots (or two "
        "drivers) on one topic. asf maps the laser of one robot: give each robot its own domain "
        "id (ros2.domain_id) or its own topics (ros2.scan_topic, ros2.odom_topic)";
  return os.str();
}

std::string CycloneLink::whySilent(const std::string& topic, const std::string& type, double waited) const {
  std::ostringstream os;
  os << "[ros2] topic " << topic << ": no " << type << " for " << waited << " s; ";
  const auto types = publisherTypes(topic);
  if (types.empty()) {
    os << "no publisher of it was discovered (is the robot running, on the same domain id and "
          "network?)";
    return os.str();
  }
  const std::string wire = wireType(type);
  for (const std::string& t : types)
    if (t != wire) {
      os << "it is published with type " << t << ", not " << wire << " (" << type << ")";
      return os.str();
    }
  os << types.size() << " publisher(s) of it were discovered but sent nothing asf received "
     << "(stopped, or QoS that does not match: a best-effort publisher and a reliable reader)";
  return os.str();
}

}  // namespace asf::ros2live
