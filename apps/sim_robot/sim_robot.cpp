// asf sim-robot: an active asf source (sim2d, from a pipeline's INI file) behind ROS 2 topics,
// on Fast DDS. It publishes what a ROS 2 robot or simulator does (/clock, /scan, /odom,
// /tf odom -> base_link, /tf_static base_link -> laser) plus its truth (/ground_truth,
// /world_map), and drives as nav2 would: a geometry_msgs/PoseStamped on /goal_pose is planned
// on the latest /map and map -> odom, its outcome published on the NavigateToPose action's
// status topic. Its base also takes geometry_msgs/Twist on /cmd_vel, as a robot's driver does.
// Loaded by the launcher (`asf sim-robot`) from libasf_sim_robot.so.
#include <asf/abi.h>
#include <asf/config.h>
#include <asf/errors.h>
#include <asf/framework/pipeline_config.h>
#include <asf/framework/registry.h>
#include <asf/ros2/messages.h>
#include <asf/source.h>
#include <asf/statistics.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <mutex>
#include <optional>
#include <random>
#include <thread>

#include "action_msgsPubSubTypes.h"
#include "fastdds_node.h"
#include "sim_robot_options.h"
#include "received_log.h"
#include "geometry_msgsPubSubTypes.h"
#include "nav_msgsPubSubTypes.h"
#include "rosgraph_msgsPubSubTypes.h"
#include "sensor_msgsPubSubTypes.h"
#include "std_msgsPubSubTypes.h"
#include "tf2_msgsPubSubTypes.h"
#include "visualization_msgsPubSubTypes.h"

namespace {

namespace ros2 = asf::ros2;
using asf::simrobot::Options;
using asf::simrobot::parseArgs;
namespace bi = builtin_interfaces::msg::dds_;
namespace gm = geometry_msgs::msg::dds_;
using mrpt::poses::CPose2D;

std::atomic<bool> g_stop{false};

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}
extern "C" void onSignal(int) { g_stop = true; }

bi::Time_ rosTime(double t) {
  const ros2::Stamp s = ros2::toStamp(t);
  bi::Time_ m;
  m.sec(s.sec);
  m.nanosec(s.nanosec);
  return m;
}

gm::Pose_ rosPose(const ros2::Transform& t) {
  gm::Pose_ p;
  p.position().x(t.tx), p.position().y(t.ty), p.position().z(t.tz);
  p.orientation().x(t.qx), p.orientation().y(t.qy), p.orientation().z(t.qz),
      p.orientation().w(t.qw);
  return p;
}

gm::TransformStamped_ rosTransform(double t, const std::string& parent, const std::string& child,
                                   const ros2::Transform& tr) {
  gm::TransformStamped_ m;
  m.header().stamp(rosTime(t));
  m.header().frame_id(parent);
  m.child_frame_id(child);
  m.transform().translation().x(tr.tx), m.transform().translation().y(tr.ty),
      m.transform().translation().z(tr.tz);
  m.transform().rotation().x(tr.qx), m.transform().rotation().y(tr.qy),
      m.transform().rotation().z(tr.qz), m.transform().rotation().w(tr.qw);
  return m;
}

nav_msgs::msg::dds_::OccupancyGrid_ rosGrid(const ros2::OccupancyGrid& g) {
  nav_msgs::msg::dds_::OccupancyGrid_ m;
  m.header().stamp(rosTime(ros2::toSeconds(g.stamp)));
  m.header().frame_id(g.frame_id);
  m.info().resolution(g.resolution);
  m.info().width(g.width);
  m.info().height(g.height);
  m.info().origin(rosPose(g.origin));
  m.data(g.data);
  return m;
}

ros2::Transform fromRos(const gm::Pose_& p) {
  return {p.position().x(), p.position().y(), p.position().z(), p.orientation().x(),
          p.orientation().y(), p.orientation().z(), p.orientation().w()};
}

/// What the readers receive, under a mutex.
struct Inbox {
  std::mutex mu;
  std::optional<asf::Goal> goal;  // a new goal not yet handed to the simulator
  std::shared_ptr<mrpt::maps::COccupancyGridMap2D> map;
  std::uint64_t map_version = 0;
  CPose2D map_to_odom;
  std::size_t goals_received = 0;
  std::optional<asf::BaseVelocity> velocity;  // a new /cmd_vel not yet given to the base
  std::size_t velocities_received = 0;
  // What asf published, kept for --out (received/): the last map, markers and map -> odom.
  std::optional<ros2::OccupancyGrid> last_map;
  std::vector<visualization_msgs::msg::dds_::Marker_> last_markers;
  std::size_t maps = 0, marker_arrays = 0, map_to_odom_count = 0;
  std::vector<std::string> run_states;  // the "state" of asf's /asf/status, as it changed
};

}  // namespace

namespace {

class SimRobot {
 public:
  // The listeners use inbox_ and the writers' members: the participant goes first.
  ~SimRobot() { node_.close(); }

  explicit SimRobot(const Options& o) : o_(o), node_(o.domain, o.loopback) {
    loadSource();
    advertise();
    subscribe();
    subscribeMarkers();
    subscribeVelocity();
  }

  /// Steps the simulator at the real-time factor until stopped; returns the exit code.
  int run() {
    publishStatic();
    const auto start = std::chrono::steady_clock::now();
    double t = 0;
    std::sort(o_.commands.begin(), o_.commands.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    std::size_t next_command = 0;
    while (!g_stop) {
      for (; next_command < o_.commands.size() && o_.commands[next_command].first <= t;
           ++next_command) {
        std_msgs::msg::dds_::String_ m;
        m.data(o_.commands[next_command].second);
        command_->write(&m);
      }
      takeVelocity(t);
      takeGoal();
      std::optional<asf::SensorFrame> f = source_->next();
      if (!f) break;
      t = f->timestamp;
      publishFrame(*f);
      followGoal();
      if (o_.duration > 0 && t >= o_.duration) break;
      const auto due = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                   std::chrono::duration<double>(t / o_.rate));
      std::this_thread::sleep_until(due);
    }
    writeSummary(t);
    std::fprintf(stderr, "asf sim-robot: %zu scans published, %zu goals (%zu reached, %zu failed), "
                 "%zu velocity commands, %.1f s simulated\n",
                 scans_, inbox_.goals_received, reached_, failed_, inbox_.velocities_received, t);
    return 0;
  }

 private:
  void loadSource() {
    asf::IniConfig ini = asf::IniConfig::fromFile(o_.config);
    for (const auto& s : o_.sets) ini.applyOverride(s);
    asf::framework::ResolvedConfig cfg = asf::framework::resolveConfig(ini, registry_);
    const auto it = cfg.slots.find("source");
    if (it == cfg.slots.end()) throw asf::ConfigError(o_.config + ": [pipeline] names no source");
    plugin_ = asf::framework::Registry::instantiate(*it->second);
    source_ = dynamic_cast<asf::Source*>(plugin_.get());
    if (!source_) throw asf::ConfigError(o_.config + ": the source is not a source plugin");
    asf::PluginContext ctx;
    // The pipeline's seed for its source slot (framework/src/pipeline.cpp): the same noise
    // streams as the source in an `asf run` of the same configuration.
    ctx.seed = splitmix64(static_cast<std::uint64_t>(cfg.pipeline.getInt("seed")) * 8 + 0);
    ctx.output_dir = o_.out;
    if (!o_.out.empty()) {
      std::error_code ec;
      std::filesystem::create_directories(o_.out, ec);
      if (ec) throw asf::Error(o_.out + ": cannot create the output folder: " + ec.message());
    }
    const asf::Params& p = cfg.plugin_params.at(it->second->name());
    source_->configure(p, ctx);
    if (!source_->isActive())
      throw asf::ConfigError(o_.config + ": source '" + it->second->name() +
                             "' does not drive (asf sim-robot needs an active source, e.g. sim2d)");
    for (const char* k : {"sensor_x", "sensor_y", "sensor_z", "sensor_yaw_deg"})
      if (!p.has(k)) throw asf::ConfigError(o_.config + ": source has no key " + k);
    mount_ = mrpt::poses::CPose3D(p.getDouble("sensor_x"), p.getDouble("sensor_y"),
                                  p.getDouble("sensor_z"),
                                  p.getDouble("sensor_yaw_deg") * M_PI / 180, 0, 0);
    uuid_rng_.seed(ctx.seed);
  }

  void advertise() {
    using asf::simrobot::Qos;
    clock_ =
        node_.writer<rosgraph_msgs::msg::dds_::Clock_, rosgraph_msgs::msg::dds_::Clock_PubSubType>(
            "/clock", Qos::SensorData, 1);
    if (o_.fault == "scan_as_string")
      scan_ = node_.writer<std_msgs::msg::dds_::String_, std_msgs::msg::dds_::String_PubSubType>(
          "/scan", Qos::SensorData, 5);
    else
      scan_ =
          node_.writer<sensor_msgs::msg::dds_::LaserScan_,
                       sensor_msgs::msg::dds_::LaserScan_PubSubType>("/scan", Qos::SensorData, 5);
    odom_ = node_.writer<nav_msgs::msg::dds_::Odometry_, nav_msgs::msg::dds_::Odometry_PubSubType>(
        "/odom", Qos::Reliable, 50);
    gt_ = node_.writer<nav_msgs::msg::dds_::Odometry_, nav_msgs::msg::dds_::Odometry_PubSubType>(
        "/ground_truth", Qos::Reliable, 50);
    tf_ = node_.writer<tf2_msgs::msg::dds_::TFMessage_, tf2_msgs::msg::dds_::TFMessage_PubSubType>(
        "/tf", Qos::Reliable, 100);
    tf_static_ =
        node_.writer<tf2_msgs::msg::dds_::TFMessage_, tf2_msgs::msg::dds_::TFMessage_PubSubType>(
            "/tf_static", Qos::ReliableLatched, 1);
    world_ = node_.writer<nav_msgs::msg::dds_::OccupancyGrid_,
                          nav_msgs::msg::dds_::OccupancyGrid_PubSubType>("/world_map",
                                                                         Qos::ReliableLatched, 1);
    command_ = node_.writer<std_msgs::msg::dds_::String_, std_msgs::msg::dds_::String_PubSubType>(
        "/asf/command", Qos::Reliable, 10);
    status_ = node_.writer<action_msgs::msg::dds_::GoalStatusArray_,
                           action_msgs::msg::dds_::GoalStatusArray_PubSubType>(
        "/navigate_to_pose/_action/status", Qos::ReliableLatched, 1);
  }

  void subscribe() {
    using asf::simrobot::Qos;
    node_.reader<gm::PoseStamped_, gm::PoseStamped_PubSubType>(
        "/goal_pose", Qos::Reliable, 10, [this](const gm::PoseStamped_& m) {
          std::lock_guard<std::mutex> lock(inbox_.mu);
          asf::Goal g;
          g.x = m.pose().position().x();
          g.y = m.pose().position().y();
          g.tolerance = goal_tolerance_;
          inbox_.goal = g;
          ++inbox_.goals_received;
        });
    node_
        .reader<nav_msgs::msg::dds_::OccupancyGrid_, nav_msgs::msg::dds_::OccupancyGrid_PubSubType>(
            "/map", Qos::ReliableLatched, 1, [this](const nav_msgs::msg::dds_::OccupancyGrid_& m) {
              ros2::OccupancyGrid g;
              g.resolution = m.info().resolution();
              g.width = m.info().width(), g.height = m.info().height();
              g.origin = fromRos(m.info().origin());
              g.data = m.data();
              g.stamp = {m.header().stamp().sec(), m.header().stamp().nanosec()};
              g.frame_id = m.header().frame_id();
              try {
                auto grid = ros2::mrptFromOccupancy(g);
                std::lock_guard<std::mutex> lock(inbox_.mu);
                inbox_.map = std::move(grid);
                ++inbox_.map_version;
                inbox_.last_map = std::move(g);
                ++inbox_.maps;
              } catch (const std::exception& e) {
                std::fprintf(stderr, "asf sim-robot: topic /map: %s (ignored)\n", e.what());
              }
            });
    node_.reader<tf2_msgs::msg::dds_::TFMessage_, tf2_msgs::msg::dds_::TFMessage_PubSubType>(
        "/tf", Qos::Reliable, 100, [this](const tf2_msgs::msg::dds_::TFMessage_& m) {
          for (const auto& t : m.transforms()) {
            if (t.header().frame_id() != "map" || t.child_frame_id() != "odom") continue;
            const auto& r = t.transform().rotation();
            std::lock_guard<std::mutex> lock(inbox_.mu);
            ++inbox_.map_to_odom_count;
            scanToTf(t.header().stamp());
            inbox_.map_to_odom =
                CPose2D(t.transform().translation().x(), t.transform().translation().y(),
                        ros2::yawFromQuaternion(r.x(), r.y(), r.z(), r.w()));
          }
        });
  }

  // /cmd_vel: best effort, so that reliable and best-effort publishers (teleop, controllers)
  // both match.
  void subscribeVelocity() {
    node_.reader<gm::Twist_, gm::Twist_PubSubType>(
        "/cmd_vel", asf::simrobot::Qos::SensorData, 1, [this](const gm::Twist_& m) {
          std::lock_guard<std::mutex> lock(inbox_.mu);
          inbox_.velocity = asf::BaseVelocity{m.linear().x(), m.angular().z()};
          ++inbox_.velocities_received;
        });
  }

  void subscribeMarkers() {
    node_.reader<visualization_msgs::msg::dds_::MarkerArray_,
                 visualization_msgs::msg::dds_::MarkerArray_PubSubType>(
        "/asf/markers", asf::simrobot::Qos::Reliable, 5,
        [this](const visualization_msgs::msg::dds_::MarkerArray_& m) {
          std::lock_guard<std::mutex> lock(inbox_.mu);
          inbox_.last_markers = m.markers();
          ++inbox_.marker_arrays;
        });
    node_.reader<std_msgs::msg::dds_::String_, std_msgs::msg::dds_::String_PubSubType>(
        "/asf/status", asf::simrobot::Qos::ReliableLatched, 1,
        [this](const std_msgs::msg::dds_::String_& m) {
          const std::string key = "\"state\": \"";
          const std::size_t at = m.data().find(key);
          if (at == std::string::npos) return;
          const std::size_t from = at + key.size(), to = m.data().find('"', from);
          const std::string state = m.data().substr(from, to - from);
          std::lock_guard<std::mutex> lock(inbox_.mu);
          if (inbox_.run_states.empty() || inbox_.run_states.back() != state)
            inbox_.run_states.push_back(state);
        });
  }

  // The laser's mounting and the true world, once (transient local: late joiners get them).
  void publishStatic() {
    tf2_msgs::msg::dds_::TFMessage_ m;
    m.transforms().push_back(
        rosTransform(o_.clock_start, "base_link", "laser", ros2::transformFromPose(mount_)));
    if (o_.fault != "no_tf_static" && !o_.mount_on_tf) tf_static_->write(&m);
    if (const auto truth = source_->worldTruth()) {
      nav_msgs::msg::dds_::OccupancyGrid_ g =
          rosGrid(ros2::occupancyFromMrpt(*truth->grid, ros2::toStamp(o_.clock_start), "world"));
      world_->write(&g);
    }
  }

  void publishFrame(const asf::SensorFrame& f) {
    const double t = f.timestamp + o_.clock_start;
    rosgraph_msgs::msg::dds_::Clock_ c;
    c.clock(rosTime(t));
    clock_->write(&c);
    odom_pose_ = odom_pose_ + f.odometry;
    odom_pose_.normalizePhi();
    const ros2::Transform tr = ros2::transformFromPose(odom_pose_);
    nav_msgs::msg::dds_::Odometry_ o;
    o.header().stamp(rosTime(t));
    o.header().frame_id("odom");
    o.child_frame_id("base_link");
    o.pose().pose(rosPose(tr));
    odom_->write(&o);
    tf2_msgs::msg::dds_::TFMessage_ tf;
    tf.transforms().push_back(rosTransform(t, "odom", "base_link", tr));
    if (o_.mount_on_tf)
      tf.transforms().push_back(
          rosTransform(t, "base_link", "laser", ros2::transformFromPose(mount_)));
    tf_->write(&tf);
    if (f.ground_truth) {
      nav_msgs::msg::dds_::Odometry_ g = o;
      g.header().frame_id("world");
      g.pose().pose(rosPose(ros2::transformFromPose(*f.ground_truth)));
      gt_->write(&g);
    }
    if (f.scan && o_.fault == "scan_as_string") {
      std_msgs::msg::dds_::String_ text;
      text.data("not a scan");
      scan_->write(&text);
      ++scans_;
    } else if (f.scan) {
      const ros2::LaserScan s = ros2::laserScanFromMrpt(*f.scan, ros2::toStamp(t), "laser");
      sensor_msgs::msg::dds_::LaserScan_ m;
      m.header().stamp(rosTime(t));
      m.header().frame_id(s.frame_id);
      m.angle_min(s.angle_min), m.angle_max(s.angle_max), m.angle_increment(s.angle_increment);
      m.range_min(s.range_min), m.range_max(s.range_max);
      m.ranges(s.ranges);
      m.intensities(s.intensities);
      {
        std::lock_guard<std::mutex> lock(inbox_.mu);
        scan_sent_[m.header().stamp().sec() * 1000000000LL + m.header().stamp().nanosec()] =
            std::chrono::steady_clock::now();
        while (scan_sent_.size() > 4000) scan_sent_.erase(scan_sent_.begin());
      }
      scan_->write(&m);
      ++scans_;
    }
  }

  // The newest /cmd_vel drives the base for cmd_vel_timeout of simulated time, then the base
  // stops (as robot drivers do when commands stop); the first one preempts a goal.
  void takeVelocity(double t) {
    std::optional<asf::BaseVelocity> v;
    {
      std::lock_guard<std::mutex> lock(inbox_.mu);
      v.swap(inbox_.velocity);
    }
    if (!v && (!by_velocity_ || t <= velocity_until_)) return;
    if (!v) v = asf::BaseVelocity{};  // timed out
    if (active_) setState(ros2::GoalState::Canceled), ++failed_, active_ = false;
    if (!source_->driveVelocity(*v))
      throw asf::ConfigError(o_.config + ": the source does not take velocities (/cmd_vel)");
    by_velocity_ = v->forward != 0 || v->turn != 0;
    velocity_until_ = t + o_.cmd_vel_timeout;
  }

  // A new goal from /goal_pose: planned on the latest /map from where map -> odom puts the
  // robot (nav2 plans on the SLAM map and pose); the goal before it is canceled (preempted).
  void takeGoal() {
    asf::Goal g;
    asf::NavigationContext ctx;
    asf::GridMap map;
    {
      std::lock_guard<std::mutex> lock(inbox_.mu);
      if (!inbox_.goal) return;
      g = *inbox_.goal;
      inbox_.goal.reset();
      map.grid = inbox_.map;
      map.version = inbox_.map ? inbox_.map_version : 0;
      ctx.robot_estimate = inbox_.map_to_odom + odom_pose_;
      planned_with_ = inbox_.map_to_odom;
    }
    ctx.map = map.version ? &map : nullptr;
    goal_ = g;
    by_velocity_ = false;  // navigate() takes the base back
    if (active_) setState(ros2::GoalState::Canceled), ++failed_;
    goals_.push_back({newUuid(), 0});
    active_ = true;
    setState(ros2::GoalState::Executing);
    if (o_.fault == "stuck") return;  // accepted and executing, forever
    settle(source_->navigate(g, ctx));
  }

  // As nav2 follows the latest map -> odom: when asf's estimate moved the robot (a loop
  // closure) by more than 5 cm or 2 degrees since the goal was planned, it is planned again
  // from where the new estimate puts the robot.
  void followGoal() {
    if (!active_ || o_.fault == "stuck") return;
    asf::NavigationContext ctx;
    asf::GridMap map;
    bool replan = false;
    {
      std::lock_guard<std::mutex> lock(inbox_.mu);
      const CPose2D moved = planned_with_ - inbox_.map_to_odom;
      replan = std::hypot(moved.x(), moved.y()) > 0.05 || std::abs(moved.phi()) > 2 * M_PI / 180;
      if (replan) {
        planned_with_ = inbox_.map_to_odom;
        map.grid = inbox_.map;
        map.version = inbox_.map ? inbox_.map_version : 0;
        ctx.robot_estimate = inbox_.map_to_odom + odom_pose_;
      }
    }
    if (!replan) return settle(source_->status());
    ctx.map = map.version ? &map : nullptr;
    ++replans_;
    settle(source_->navigate(goal_, ctx));
  }

  void settle(asf::NavStatus st) {
    if (st == asf::NavStatus::Moving || !active_) return;
    const bool ok = st == asf::NavStatus::Reached;
    setState(ok ? ros2::GoalState::Succeeded : ros2::GoalState::Aborted);
    ++(ok ? reached_ : failed_);
    active_ = false;
  }

  std::array<std::uint8_t, 16> newUuid() {
    std::array<std::uint8_t, 16> id;
    for (auto& b : id) b = static_cast<std::uint8_t>(uuid_rng_());
    return id;
  }

  // The status list as an action server keeps it: the last goals, newest last.
  void setState(ros2::GoalState s) {
    goals_.back().second = static_cast<std::int8_t>(s);
    while (goals_.size() > 8) goals_.erase(goals_.begin());
    action_msgs::msg::dds_::GoalStatusArray_ m;
    for (const auto& [id, state] : goals_) {
      action_msgs::msg::dds_::GoalStatus_ e;
      e.goal_info().goal_id().uuid(id);
      e.status(state);
      m.status_list().push_back(e);
    }
    status_->write(&m);
  }

  // Scan-to-tf latency: from publishing a scan to receiving the map -> odom asf stamped with
  // it (under inbox_.mu).
  void scanToTf(const builtin_interfaces::msg::dds_::Time_& stamp) {
    const auto it = scan_sent_.find(stamp.sec() * 1000000000LL + stamp.nanosec());
    if (it == scan_sent_.end()) return;
    latency_ms_.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - it->second)
            .count());
  }

  std::string latencyJson() {
    std::vector<double> v;
    {
      std::lock_guard<std::mutex> lock(inbox_.mu);
      v = latency_ms_;
    }
    if (v.empty()) return "null";
    std::ostringstream os;  // the quantiles asf's own scan-to-tf line uses (nearest rank)
    os << "{\"count\": " << v.size() << ", \"median_ms\": " << asf::percentile(v, 50)
       << ", \"p95_ms\": " << asf::percentile(v, 95)
       << ", \"max_ms\": " << *std::max_element(v.begin(), v.end()) << "}";
    return os.str();
  }

  std::string statesJson() {
    std::lock_guard<std::mutex> lock(inbox_.mu);
    std::string j = "[";
    for (const auto& s : inbox_.run_states) j += (j.size() > 1 ? ", \"" : "\"") + s + "\"";
    return j + "]";
  }

  void writeSummary(double t) {
    if (o_.out.empty()) return;
    {
      std::lock_guard<std::mutex> lock(inbox_.mu);
      asf::simrobot::writeReceived(o_.out + "/received", inbox_.last_map, inbox_.last_markers,
                                   inbox_.map_to_odom);
    }
    std::ofstream f(o_.out + "/sim_robot.json");
    f << "{\"scans_published\": " << scans_ << ", \"goals_received\": " << inbox_.goals_received
      << ", \"velocities_received\": " << inbox_.velocities_received
      << ", \"goals_reached\": " << reached_ << ", \"replans_after_map_to_odom\": " << replans_
      << ", \"goals_failed\": " << failed_ << ", \"maps_received\": " << inbox_.maps
      << ", \"marker_arrays_received\": " << inbox_.marker_arrays
      << ", \"map_to_odom_received\": " << inbox_.map_to_odom_count
      << ", \"scan_to_tf_latency\": " << latencyJson() << ", \"asf_states\": " << statesJson()
      << ", \"simulated_s\": " << t << ", \"stopped_by_signal\": " << (g_stop ? "true" : "false")
      << "}\n";
  }

  Options o_;
  asf::simrobot::FastNode node_;
  asf::framework::Registry registry_;
  std::unique_ptr<asf::Plugin> plugin_;
  asf::Source* source_ = nullptr;
  mrpt::poses::CPose3D mount_;
  CPose2D odom_pose_;
  double goal_tolerance_ = 0.3;
  Inbox inbox_;
  std::vector<std::pair<std::array<std::uint8_t, 16>, std::int8_t>> goals_;
  bool active_ = false;
  bool by_velocity_ = false;  // the base moves at a /cmd_vel until velocity_until_
  asf::Goal goal_;             // the active goal
  CPose2D planned_with_;       // the map -> odom it was last planned with
  std::size_t replans_ = 0;    // goals planned again after a map -> odom correction
  double velocity_until_ = 0;
  std::size_t scans_ = 0, reached_ = 0, failed_ = 0;
  std::mt19937_64 uuid_rng_;
  std::map<long long, std::chrono::steady_clock::time_point> scan_sent_;  // stamp ns -> sent
  std::vector<double> latency_ms_;
  eprosima::fastdds::dds::DataWriter *clock_ = nullptr, *scan_ = nullptr, *odom_ = nullptr,
                                     *gt_ = nullptr, *tf_ = nullptr, *tf_static_ = nullptr,
                                     *world_ = nullptr, *status_ = nullptr, *command_ = nullptr;
};

}  // namespace

extern "C" ASF_EXPORT int asf_sim_robot_main(int argc, char** argv) {
  try {
    const Options o = parseArgs(argc, argv);
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    SimRobot robot(o);
    std::fprintf(stderr, "asf sim-robot: %s on domain %d%s, real-time factor %g\n",
                 o.config.c_str(), o.domain, o.loopback ? " (loopback)" : "", o.rate);
    return robot.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "asf sim-robot: error: %s\n", e.what());
    return 1;
  }
}
