// source_ros2: a live robot over ROS 2 (DDS, Cyclone DDS; no ROS installation). Frames are its
// LaserScans with the odometry (nav_msgs/Odometry, or tf odom -> base) at each scan's stamp
// and the laser's mounting from /tf_static. With drive = nav2 it is an active source: goals go
// out as geometry_msgs/PoseStamped on /goal_pose (what nav2's BT navigator takes from rviz),
// their outcome comes back on the NavigateToPose action's status topic, and /map and
// map -> odom go out for the navigator to plan on. With drive = cmd_vel asf navigates itself:
// a path on its map, followed with geometry_msgs/Twist on /cmd_vel (velocity_drive.h). An
// operator starts, pauses, stops or sends the robot home with std_msgs/String on /asf/command.
// Every run is recorded as a rawlog.
#include <asf/atomic_file.h>
#include <asf/errors.h>
#include <asf/io/ground_truth.h>
#include <asf/mapping/odometry_noise.h>
#include <asf/io/rawlog_io.h>
#include <asf/source.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <sstream>

#include "cyclone_link.h"
#include "live_bag.h"
#include "live_core.h"
#include "run_publisher.h"
#include "source_ros2_keys.h"
#include "source_ros2_options.h"
#include "velocity_drive.h"

namespace {

using asf::ros2live::Qos;
using mrpt::poses::CPose2D;
using mrpt::poses::CPose3D;
using SteadyClock = std::chrono::steady_clock;
namespace ros2 = asf::ros2;

double wallSeconds() {
  return std::chrono::duration<double>(SteadyClock::now().time_since_epoch()).count();
}

CPose2D planar(const ros2::Transform& t) {
  return CPose2D(t.tx, t.ty, ros2::yawFromQuaternion(t.qx, t.qy, t.qz, t.qw));
}

class Ros2Source final : public asf::Source {
 public:
  ~Ros2Source() override {
    try {
      endRecording();
    } catch (const std::exception& e) {
      MRPT_LOG_ERROR(e.what());
    }
    if (frames_ > 0 || scans_.arrived() > 0)
      MRPT_LOG_INFO_STREAM("topic " << scan_topic_ << ": " << scans_.arrived() << " scans received, "
                                    << frames_ << " passed to the pipeline, " << scans_.dropped()
                                    << " dropped (queue full), " << out_of_order_
                                    << " out of order, " << before_odometry_
                                    << " before the first odometry; stamps " << std::fixed << first_t_ << " to "
                                    << last_t_ << " s; " << (publisher_ ? publisher_->mapsSent() : 0) << " maps published on "
                                    << map_topic_);
    if (writer_)
      MRPT_LOG_INFO_STREAM("recorded " << writer_->framesWritten() << " frames to " << rawlog_path_);
  }

  // The robot stops and the link goes (no callback writes to the bag after it), then the files.
  void endRecording() override {
    if (link_) {
      const auto threads = asf::ros2live::otherThreadsCpuByName();  // before Cyclone's threads go
      if (velocity_) {
        velocity_->halt();  // the robot stops before asf leaves
        MRPT_LOG_INFO_STREAM(velocity_->commandsSent() << " velocity commands sent on " << cmd_vel_topic_);
      }
      link_.reset();
      if (frames_ > 0) logCpu(threads);
    }
    asf::closeEach({{"the bag " + bag_.folder() + ": ", [&] {
                                 if (const std::uint64_t n = bag_.close())
                                   MRPT_LOG_INFO_STREAM("wrote " << n << " messages to the bag " << bag_.folder());
                               }},
                              {"", [&] { if (writer_) writer_->close(); }},
                              {"", [&] { if (gt_writer_) gt_writer_->close(); }}});
  }

  void configure(const asf::Params& p, const asf::PluginContext& ctx) override {
    configureTopics(p);
    configureRecording(p, ctx);
    connect(p);
    if (!world_topic_.empty()) waitForWorld(p);
  }

  // The bridge's CPU: its part of the run's thread, and Cyclone DDS's threads (receiving and
  // delivering to the callbacks, timed events), by name; the other threads are the pipeline's.
  void logCpu(const std::map<std::string, double>& threads) {
    MRPT_LOG_INFO(asf::ros2live::bridgeCpuLine(threads, bridge_cpu_, recording_cpu_));
    MRPT_LOG_INFO_STREAM("scan-to-tf in asf (a scan queued by the receive thread to the map -> odom stamped "
                         "with it published): " << asf::ros2live::latencySummary(tf_latency_ms_));
  }

  bool isActive() const override { return nav2_ || velocity_; }
  bool isLive() const override { return true; }

  asf::OperatorRequest takeOperatorRequest() override {
    for (const std::string& text : commands_.takeUnknown())
      MRPT_LOG_WARN_STREAM("topic " << command_topic_ << ": '" << text
                                    << "' is not a command (start, pause, resume, stop, return_home); ignored");
    return commands_.take();
  }

  // The robot stops where it is: nav2 gets a goal at the robot's pose (its navigator preempts
  // the running goal with it, as a new goal from rviz does); cmd_vel a zero velocity.
  void halt() override {
    if (velocity_) velocity_->halt();
    if (!nav2_) return;
    bool was_moving = false;
    {
      std::lock_guard<std::mutex> lock(mu_);
      was_moving = tracker_.active();
      tracker_.halt();
    }
    if (!was_moving) return;
    const ros2::Stamp stamp = now();
    const ros2::Transform pose = ros2::transformFromPose(last_robot_);
    link_->publishPose(goal_wr_, stamp, map_frame_, pose);
    bag_.goal(stamp, map_frame_, pose);
  }
  std::shared_ptr<const asf::WorldTruth> worldTruth() const override { return truth_; }

  std::optional<asf::SensorFrame> next() override {
    UsableScan u = first_ ? std::move(*first_) : nextUsableScan();
    first_.reset();
    return frame(u.scan, ros2::toSeconds(u.scan.msg.stamp), u.odom);
  }

  asf::NavStatus navigate(const asf::Goal& goal, const asf::NavigationContext& ctx) override {
    if (velocity_) return navigateByVelocity(goal, ctx);
    if (!nav2_) return asf::NavStatus::Unreachable;
    if (!std::isfinite(goal.x) || !std::isfinite(goal.y)) return asf::NavStatus::Unreachable;
    const CPose2D& r = ctx.robot_estimate;
    if (std::hypot(goal.x - r.x(), goal.y - r.y()) <= goal.tolerance) {
      tracker_.cancel();
      return asf::NavStatus::Reached;
    }
    const double yaw = std::atan2(goal.y - r.y(), goal.x - r.x());
    {
      std::lock_guard<std::mutex> lock(mu_);
      tracker_.sent(wallSeconds());
    }
    const ros2::Stamp stamp = now();
    const ros2::Transform pose = ros2::transformFromPose(CPose2D(goal.x, goal.y, yaw));
    link_->publishPose(goal_wr_, stamp, map_frame_, pose);
    bag_.goal(stamp, map_frame_, pose);
    ++goals_sent_;
    publishStatus(&goal, run_state_);
    return asf::NavStatus::Moving;
  }

  // The run's estimate after each step: map -> odom every time, /map and the markers at most
  // every map_period_s / marker_period_s of the robot's clock, and all of them at the end.
  void observe(const asf::RunView& v) override {
    if (frames_ == 0) return;
    const double cpu0 = asf::ros2live::threadCpuSeconds();
    publisher_->publish(v, last_odom_);
    if (pending_arrival_) {  // the frame's scan, queued by the receive thread, is now on /tf
      tf_latency_ms_.push_back(
          std::chrono::duration<double, std::milli>(SteadyClock::now() - *pending_arrival_).count());
      pending_arrival_.reset();
    }
    last_robot_ = v.robot;
    const std::string state = v.final ? "ended" : v.paused ? "paused" : v.returning_home ? "returning_home" : "exploring";
    if (state != run_state_) publishStatus(v.goal, run_state_ = state);
    bridge_cpu_ += asf::ros2live::threadCpuSeconds() - cpu0;
    if (velocity_ && v.final) velocity_->halt();
    else if (velocity_) velocity_->observe(driveView(v.map, v.robot, v.timestamp));
  }

 private:
  asf::ros2live::VelocityDrive::View driveView(const asf::GridMap* map, const CPose2D& robot, double t) const {
    return {map && map->version ? map->grid : nullptr, robot, last_odom_, last_scan_, t};
  }

  asf::NavStatus navigateByVelocity(const asf::Goal& goal, const asf::NavigationContext& ctx) {
    const asf::NavStatus st = velocity_->navigate(goal, driveView(ctx.map, ctx.robot_estimate, last_t_));
    ++goals_sent_;
    if (st == asf::NavStatus::Unreachable)
      MRPT_LOG_INFO_STREAM("goal " << goals_sent_ << " (" << goal.x << ", " << goal.y
                                   << "): unreachable (" << velocity_->why() << ")");
    publishStatus(&goal, run_state_);
    velocity_moving_ = st == asf::NavStatus::Moving;
    return st;
  }

 public:
  asf::NavStatus status() const override {
    if (velocity_) {
      const asf::NavStatus st = velocity_->status(last_t_);
      if (velocity_moving_ && st != asf::NavStatus::Moving)
        MRPT_LOG_INFO_STREAM("goal " << goals_sent_ << " by " << cmd_vel_topic_ << ": "
                                     << asf::navStatusName(st) << " (" << velocity_->why() << ")");
      velocity_moving_ = st == asf::NavStatus::Moving;
      return st;
    }
    if (!nav2_) return asf::NavStatus::Idle;
    std::lock_guard<std::mutex> lock(mu_);
    const bool was_active = tracker_.active();
    const asf::NavStatus st = tracker_.status(frames_, wallSeconds(), accept_timeout_, goal_timeout_);
    if (was_active && !tracker_.active())
      MRPT_LOG_INFO_STREAM("goal " << goals_sent_ << " on " << goal_topic_ << ": "
                                   << asf::navStatusName(st) << " (" << tracker_.why() << ")");
    return st;
  }

 private:
  void configureTopics(const asf::Params& p) {
    scan_topic_ = p.getString("scan_topic");
    odom_topic_ = p.getString("odom_topic");
    odom_from_tf_ = p.getString("odometry") == "tf";
    tf_topic_ = p.getString("tf_topic");
    tf_static_topic_ = p.getString("tf_static_topic");
    clock_topic_ = p.getString("clock_topic");
    use_sim_time_ = p.getBool("use_sim_time");
    map_frame_ = p.getString("map_frame");
    odom_frame_ = p.getString("odom_frame");
    base_frame_ = p.getString("base_frame");
    gt_topic_ = p.getString("ground_truth_topic");
    world_topic_ = p.getString("world_map_topic");
    nav2_ = p.getString("drive") == "nav2";
    command_topic_ = p.getString("command_topic");
    cmd_vel_topic_ = p.getString("cmd_vel_topic");
    goal_topic_ = p.getString("goal_topic");
    nav_status_topic_ = p.getString("nav_status_topic");
    map_topic_ = p.getString("map_topic");
    marker_topic_ = p.getString("marker_topic");
    status_topic_ = p.getString("status_topic");
    startup_timeout_ = p.getDouble("startup_timeout_s");
    message_timeout_ = p.getDouble("message_timeout_s");
    odom_tolerance_ = p.getDouble("odom_tolerance_s");
    accept_timeout_ = p.getDouble("goal_accept_timeout_s");
    goal_timeout_ = p.getDouble("goal_timeout_s");
    radius_ = p.getDouble("robot_radius");
    model_ = asf::mapping::OdometryNoiseModel::fromParams(p);
    asf::ros2live::checkTopicNames(p);
    if (!world_topic_.empty() && gt_topic_.empty())
      p.fail("world_map_topic", "needs ground_truth_topic (the world map is placed by the robot's true start)");
  }

  void configureRecording(const asf::Params& p, const asf::PluginContext& ctx) {
    if (ctx.output_dir.empty()) return;
    const std::string base = (std::filesystem::path(ctx.output_dir) / p.getString("record_name")).string();
    if (p.getBool("record")) {
      rawlog_path_ = base + ".rawlog";
      writer_ = std::make_unique<asf::io::RawlogWriter>(rawlog_path_);
      if (!gt_topic_.empty()) gt_writer_ = std::make_unique<asf::io::GroundTruthWriter>(base + ".gt.txt");
    }
    if (!p.getBool("bag")) return;
    asf::ros2live::LiveBagTopics t;
    t.scan = scan_topic_, t.tf = tf_topic_, t.tf_static = tf_static_topic_;
    t.odom = odom_from_tf_ ? "" : odom_topic_;
    t.ground_truth = gt_topic_, t.map = map_topic_, t.markers = marker_topic_;
    t.goal = nav2_ ? goal_topic_ : "";
    try {
      bag_.open(base + "_bag", t);
    } catch (const std::runtime_error& e) {
      p.fail("bag", e.what());
    }
  }

  void connect(const asf::Params& p) {
    const asf::ros2live::LinkOptions o = asf::ros2live::linkOptions(p);
    try {
      link_ = std::make_unique<asf::ros2live::CycloneLink>(o);
      subscribe(p);
      publisher_ = std::make_unique<asf::ros2live::RunPublisher>(*link_, bag_, publisherOptions(p));
      if (nav2_) {
        goal_wr_ = link_->advertisePose(goal_topic_);
        link_->onGoalStatus(nav_status_topic_, [this](std::vector<asf::ros2live::GoalStatusEntry> l) {
          std::lock_guard<std::mutex> lock(mu_);
          tracker_.statusArrived(l, scans_.arrived());
        });
      }
      if (p.getString("drive") == "cmd_vel") {
        const int wr = link_->advertiseTwist(cmd_vel_topic_);
        velocity_ = std::make_unique<asf::ros2live::VelocityDrive>(
            asf::ros2live::velocityDriveOptions(p, radius_, goal_timeout_),
            [this, wr](const asf::navigation::Velocity& v) {
              link_->publishTwist(wr, v.forward, v.turn);
            });
      }
      status_wr_ = link_->advertiseString(status_topic_);
    } catch (const std::runtime_error& e) {
      p.fail("domain_id", std::string("DDS: ") + e.what());
    }
  }

  asf::ros2live::RunPublisherOptions publisherOptions(const asf::Params& p) const {
    asf::ros2live::RunPublisherOptions o;
    o.tf_topic = tf_topic_, o.map_topic = map_topic_, o.marker_topic = marker_topic_;
    o.map_frame = map_frame_, o.odom_frame = odom_frame_;
    o.map_period = p.getDouble("map_period_s"), o.marker_period = p.getDouble("marker_period_s");
    return o;
  }

  void subscribe(const asf::Params& p) {
    const Qos scan_qos = p.getString("scan_qos") == "reliable" ? Qos::Reliable : Qos::SensorData;
    link_->onScan(scan_topic_, scan_qos, 64, [this](ros2::LaserScan m) {
      bag_.scan(m);
      scans_.push(std::move(m));
    });
    const Qos odom_qos = p.getString("odom_qos") == "reliable" ? Qos::Reliable : Qos::SensorData;
    if (!odom_from_tf_)
      link_->onOdometry(odom_topic_, odom_qos, [this](ros2::Odometry m) {
        bag_.odometry(m);
        const double t = ros2::toSeconds(m.stamp);
        {
          std::lock_guard<std::mutex> lock(mu_);
          if (robot_frame_.empty()) robot_frame_ = m.child_frame_id;
          odom_.add(t, planar(m.pose));
          cv_.notify_all();
        }
        if (velocity_) velocity_->odometry(planar(m.pose), t);  // the controller's tick
      });
    else
      robot_frame_ = base_frame_;
    link_->onTransforms(tf_static_topic_, Qos::ReliableLatched,
                        [this](std::vector<ros2::TransformStamped> l) { transformsArrived(true, l); });
    // /tf is read only when something needs it: odometry from tf, the bag, or a laser whose
    // mounting is not on /tf_static (mounting() subscribes then). A robot's /tf carries
    // odom -> base_link and its joints at tens of Hz, each message costing the bridge as much
    // as a scan.
    if (odom_from_tf_ || bag_.isOpen()) subscribeTf();
    link_->onString(command_topic_, [this](std::string text) { commands_.arrived(command_topic_, text); });
    if (p.getBool("wait_for_start"))
      commands_.push({asf::OperatorRequest::Kind::Pause, "wait_for_start: waiting for 'start' on " + command_topic_});
    if (use_sim_time_ && !clock_topic_.empty())
      link_->onClock(clock_topic_, [this](ros2::Stamp s) {
        std::lock_guard<std::mutex> lock(mu_);
        clock_ = s;
      });
    if (!gt_topic_.empty())
      link_->onOdometry(gt_topic_, Qos::SensorData, [this](ros2::Odometry m) {
        bag_.groundTruth(m);
        std::lock_guard<std::mutex> lock(mu_);
        gt_.add(ros2::toSeconds(m.stamp), planar(m.pose));
        cv_.notify_all();
      });
    if (!world_topic_.empty())
      link_->onOccupancy(world_topic_, [this](ros2::OccupancyGrid m) {
        std::lock_guard<std::mutex> lock(mu_);
        world_ = std::move(m);
        cv_.notify_all();
      });
  }

  // The true world from world_map_topic, placed by the true pose at the first scan.
  void transformsArrived(bool is_static, const std::vector<ros2::TransformStamped>& l) {
    bag_.transforms(l, is_static);
    std::optional<std::pair<double, CPose2D>> odom;
    {
      std::lock_guard<std::mutex> lock(mu_);
      for (const auto& t : l) {
        if (odom_from_tf_ && !is_static && t.parent == odom_frame_ && t.child == base_frame_) {
          odom = {ros2::toSeconds(t.stamp), planar(t.transform)};
          odom_.add(odom->first, odom->second);
        } else if (t.parent != map_frame_) {  // map -> odom is ours (or another SLAM's)
          tree_.set(t.parent, t.child, ros2::poseFromTransform(t.transform));
        }
      }
      cv_.notify_all();
    }
    if (velocity_ && odom) velocity_->odometry(odom->second, odom->first);
  }

  // Best effort: asf needs the newest transforms, not every one; a reliable reader would
  // acknowledge each of the publisher's heartbeats.
  void subscribeTf() {
    if (tf_subscribed_) return;
    tf_subscribed_ = true;
    link_->onTransforms(tf_topic_, Qos::SensorData,
                        [this](std::vector<ros2::TransformStamped> l) { transformsArrived(false, l); });
  }

  void waitForWorld(const asf::Params& p) {
    // The first scan the odometry covers: the map frame's origin, whose true pose places the
    // world (the frames before it are dropped by next() too).
    first_ = nextUsableScan();  // its InputError names the topic that stayed silent
    const double t = ros2::toSeconds(first_->scan.msg.stamp);
    std::unique_lock<std::mutex> lock(mu_);
    const bool ok = cv_.wait_for(lock, std::chrono::milliseconds(static_cast<long>(1000 * startup_timeout_)),
                                 [&] { return world_ && gt_.newest() >= t; });
    if (!world_) {
      lock.unlock();
      p.fail("world_map_topic", link_->whySilent(world_topic_, "nav_msgs/OccupancyGrid", startup_timeout_));
    }
    if (!ok) {
      lock.unlock();
      p.fail("ground_truth_topic", link_->whySilent(gt_topic_, "nav_msgs/Odometry", startup_timeout_));
    }
    auto truth = std::make_shared<asf::WorldTruth>();
    try {
      truth->grid = ros2::mrptFromOccupancy(*world_);
    } catch (const std::exception& e) {
      lock.unlock();
      p.fail("world_map_topic", std::string("topic ") + world_topic_ + ": " + e.what());
    }
    truth->map_origin = *gt_.at(t, odom_tolerance_ + 1e9);
    truth->robot_radius = radius_;
    truth_ = std::move(truth);
  }

  struct UsableScan {
    asf::ros2live::ArrivedScan scan;
    CPose2D odom;  ///< the odometry at its stamp
  };

  // The next scan the pipeline can take, with the odometry at its stamp. Scans stamped before
  // the previous frame, or before the first odometry received (its subscription matched later
  // than the scans': a start-up race, not a fault), are dropped and counted. Throws
  // asf::InputError naming the topic when no scan comes, or no odometry for one.
  UsableScan nextUsableScan() {
    for (;;) {
      const double wait = frames_ == 0 ? startup_timeout_ : message_timeout_;
      std::optional<asf::ros2live::ArrivedScan> s =
          scans_.pop(std::chrono::milliseconds(static_cast<long>(1000 * wait)));
      if (!s) throw asf::InputError(link_->whySilent(scan_topic_, "sensor_msgs/LaserScan", wait));
      const double t = ros2::toSeconds(s->msg.stamp);
      if (frames_ > 0 && t < last_t_) {
        ++out_of_order_;  // the contract: timestamps never go back; two robots break it
        if (out_of_order_ < 10) continue;
        const std::string two = link_->whyStampsGoBack(scan_topic_, "sensor_msgs/LaserScan", out_of_order_);
        if (two.empty()) continue;
        throw asf::InputError(two);
      }
      const std::optional<CPose2D> odom = odometryAt(t);
      if (!odom) {
        ++before_odometry_;
        continue;
      }
      return {std::move(*s), *odom};
    }
  }

  // The odometry at t, waiting for it up to message_timeout_s; nullopt for a scan older than
  // the first odometry received.
  std::optional<CPose2D> odometryAt(double t) {
    std::unique_lock<std::mutex> lock(mu_);
    const auto deadline = SteadyClock::now() + std::chrono::milliseconds(static_cast<long>(1000 * message_timeout_));
    cv_.wait_until(lock, deadline, [&] { return odom_.newest() >= t; });
    if (auto p = odom_.at(t, odom_tolerance_)) return *p;
    if (frames_ == 0 && !odom_.empty() && t < odom_.oldest()) return std::nullopt;
    std::ostringstream os;
    os << "[ros2] " << (odom_from_tf_ ? "topic " + tf_topic_ + ": no transform " + odom_frame_ + " -> " + base_frame_
                                      : "topic " + odom_topic_ + ": no odometry")
       << " within " << odom_tolerance_ << " s of the scan stamped " << t << " s";
    if (odom_.empty())
      os << " (none has arrived)";
    else
      os << " (the newest is stamped " << odom_.newest() << " s)";
    lock.unlock();
    if (odom_.empty() && !odom_from_tf_ && link_->publisherTypes(odom_topic_).empty())
      os << "; no publisher of " << odom_topic_ << " was discovered (odometry = tf takes it from " << tf_topic_ << ")";
    throw asf::InputError(os.str());
  }

  // The laser's pose on the robot, waiting for /tf_static up to startup_timeout_s.
  CPose3D mounting(const std::string& laser_frame) {
    std::unique_lock<std::mutex> lock(mu_);
    const auto it = mounts_.find(laser_frame);
    if (it != mounts_.end()) return it->second;
    std::optional<CPose3D> m;
    const auto known = [&] {
      m = laser_frame == robot_frame_ ? CPose3D() : tree_.lookup(robot_frame_, laser_frame);
      return m.has_value();
    };
    // /tf_static (transient local) arrives with discovery; else read /tf for the rest.
    const double static_wait = tf_subscribed_ ? startup_timeout_ : std::min(1.0, startup_timeout_);
    if (!cv_.wait_for(lock, std::chrono::milliseconds(static_cast<long>(1000 * static_wait)), known) &&
        !tf_subscribed_) {
      lock.unlock();
      MRPT_LOG_INFO_STREAM("no transform " << robot_frame_ << " -> " << laser_frame << " on " << tf_static_topic_
                           << " after " << static_wait << " s: reading " << tf_topic_ << " for the laser's mounting");
      subscribeTf();
      lock.lock();
      cv_.wait_for(lock, std::chrono::milliseconds(static_cast<long>(1000 * (startup_timeout_ - static_wait))), known);
    }
    if (!m)
      throw asf::InputError("[ros2] topic " + scan_topic_ + ": no transform " + robot_frame_ + " -> " +
                            laser_frame + " (the scan's frame) on " + tf_static_topic_ + " or " + tf_topic_ +
                            "; known transforms: " + tree_.describe());
    mounts_[laser_frame] = *m;
    return *m;
  }

  asf::SensorFrame frame(const asf::ros2live::ArrivedScan& s, double t, const CPose2D& odom) {
    const double cpu0 = asf::ros2live::threadCpuSeconds();
    asf::SensorFrame f;
    f.timestamp = t;
    if (frames_ > 0) {
      f.odometry = odom - last_odom_;
      f.odometry_cov = model_.covariance(f.odometry);
    }
    try {
      f.scan = ros2::mrptFromLaserScan(s.msg, mounting(s.msg.frame_id), t);
    } catch (const std::invalid_argument& e) {
      throw asf::InputError("[ros2] topic " + scan_topic_ + ": scan stamped " + std::to_string(t) +
                            " s: " + e.what());
    }
    if (!gt_topic_.empty()) {
      std::lock_guard<std::mutex> lock(mu_);
      f.ground_truth = gt_.at(t, odom_tolerance_);
    }
    last_odom_ = odom;
    last_scan_ = f.scan;
    pending_arrival_ = s.arrived_at;
    if (frames_ == 0) first_t_ = t;
    last_t_ = t;
    // Three clock reads, not four: each is a system call, and the bridge's count includes them.
    const double rec0 = asf::ros2live::threadCpuSeconds();
    bridge_cpu_ += rec0 - cpu0;
    if (writer_) writer_->write(f);
    if (gt_writer_ && f.ground_truth) gt_writer_->write(t, *f.ground_truth);
    recording_cpu_ += asf::ros2live::threadCpuSeconds() - rec0;  // what every run records
    {
      std::lock_guard<std::mutex> lock(mu_);
      ++frames_;
    }
    return f;
  }

  ros2::Stamp now() const {
    if (use_sim_time_) {
      std::lock_guard<std::mutex> lock(mu_);
      return clock_topic_.empty() ? ros2::toStamp(odom_.empty() ? 0.0 : odom_.newest()) : clock_;
    }
    return ros2::toStamp(std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count());
  }

  void publishStatus(const asf::Goal* g, const std::string& state) {
    std::ostringstream os;
    os << "{\"state\": \"" << state << "\", \"frames\": " << frames_ << ", \"scans_received\": " << scans_.arrived()
       << ", \"scans_dropped\": " << scans_.dropped() << ", \"goals_sent\": " << goals_sent_;
    if (g) os << ", \"goal\": [" << g->x << ", " << g->y << "]";
    os << "}";
    link_->publishString(status_wr_, os.str());
  }

  std::string scan_topic_, odom_topic_, tf_topic_, tf_static_topic_, clock_topic_, gt_topic_,
      world_topic_, goal_topic_, nav_status_topic_, map_topic_, marker_topic_, status_topic_,
      cmd_vel_topic_, command_topic_;
  std::string map_frame_, odom_frame_, base_frame_, robot_frame_, rawlog_path_;
  bool odom_from_tf_ = false, use_sim_time_ = false, nav2_ = false, tf_subscribed_ = false;
  double startup_timeout_ = 30, message_timeout_ = 5, odom_tolerance_ = 0.1, accept_timeout_ = 5,
         goal_timeout_ = 0, radius_ = 0.2;
  asf::mapping::OdometryNoiseModel model_;
  std::unique_ptr<asf::io::RawlogWriter> writer_;
  std::unique_ptr<asf::io::GroundTruthWriter> gt_writer_;
  asf::ros2live::LiveBag bag_;  // written from the receive thread too
  std::shared_ptr<const asf::WorldTruth> truth_;

  // Filled by the receive thread, under mu_.
  mutable std::mutex mu_;
  std::condition_variable cv_;
  asf::ros2live::PoseHistory odom_, gt_;
  asf::ros2live::TransformTree tree_;
  mutable asf::ros2live::GoalTracker tracker_;
  ros2::Stamp clock_;
  std::optional<ros2::OccupancyGrid> world_;
  asf::ros2live::ScanQueue scans_{20000};

  std::map<std::string, CPose3D> mounts_;
  std::optional<UsableScan> first_;  // taken by configure() (the world's origin), not yet returned
  std::uint64_t before_odometry_ = 0;  // scans dropped: sent before the first odometry arrived
  std::uint64_t frames_ = 0, out_of_order_ = 0, goals_sent_ = 0;
  double bridge_cpu_ = 0;  // CPU seconds of the run's thread in this source's own work
  double recording_cpu_ = 0;  // of which not counted: the rawlog every run records
  double first_t_ = 0, last_t_ = 0;
  std::optional<SteadyClock::time_point> pending_arrival_;  // of the frame not yet on /tf
  std::vector<double> tf_latency_ms_;  // per frame: its scan queued to its map -> odom published
  CPose2D last_odom_, last_robot_;  // odometry and estimate at the last frame
  std::string run_state_ = "exploring";  // as the status topic last said
  asf::ros2live::OperatorInbox commands_;  // from command_topic
  std::shared_ptr<const mrpt::obs::CObservation2DRangeScan> last_scan_;
  mutable bool velocity_moving_ = false;  // the last status() of drive = cmd_vel was Moving
  int goal_wr_ = 0, status_wr_ = 0;
  std::unique_ptr<asf::ros2live::RunPublisher> publisher_;  // map -> odom, /map, the markers
  std::unique_ptr<asf::ros2live::VelocityDrive> velocity_;  // drive = cmd_vel
  std::unique_ptr<asf::ros2live::CycloneLink> link_;  // last: destroyed first
};

}  // namespace

ASF_PLUGIN(Ros2Source, asf::PluginKind::Source, "ros2", "0.1.0",
           "A live robot over ROS 2 (DDS, no ROS installation): LaserScan, odometry and tf in; "
           "goals to nav2 or velocities to the base, /map and map -> odom out; recorded as a rawlog",
           asf::ThreadSafety::ThreadCompatible, kKeys)
