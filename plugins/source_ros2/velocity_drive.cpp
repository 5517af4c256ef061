#include "velocity_drive.h"

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <cmath>

namespace asf::ros2live {

using mrpt::poses::CPose2D;

navigation::NavPlan VelocityDrive::plan(const View& v) const {
  const std::vector<Point2> obstacles =
      v.scan ? navigation::scanEndpoints(*v.scan, v.robot) : std::vector<Point2>{};
  return navigation::planPath(v.map.get(), {v.robot.x(), v.robot.y()}, {goal_.x, goal_.y},
                              goal_.tolerance, o_.nav, obstacles);
}

NavStatus VelocityDrive::navigate(const Goal& goal, const View& v) {
  std::lock_guard<std::mutex> lock(mu_);
  map_to_odom_ = v.robot + (CPose2D() - v.odom);
  active_ = false;
  follower_.stop();
  why_.clear();
  // status() says what navigate() said until the goal moves (as a navigator's status does).
  outcome_time_ = v.time;
  if (!std::isfinite(goal.x) || !std::isfinite(goal.y) || !(goal.tolerance >= 0)) {
    why_ = "not a goal";
    return outcome_ = NavStatus::Unreachable;
  }
  if (std::hypot(goal.x - v.robot.x(), goal.y - v.robot.y()) <= goal.tolerance)
    return outcome_ = NavStatus::Reached;
  goal_ = goal;
  const navigation::NavPlan p = plan(v);
  if (!p.found) {
    why_ = p.reason;
    return outcome_ = NavStatus::Unreachable;
  }
  active_ = true;
  started_ = planned_ = v.time;
  outcome_ = NavStatus::Moving;
  follower_.start(p.waypoints, v.time);
  return NavStatus::Moving;
}

void VelocityDrive::observe(const View& v) {
  std::lock_guard<std::mutex> lock(mu_);
  map_to_odom_ = v.robot + (CPose2D() - v.odom);
  if (!active_ || !follower_.following() || o_.replan_period <= 0 || v.time - planned_ < o_.replan_period)
    return;
  planned_ = v.time;
  // The newest map and scan: where the map has drifted or the scan shows what it lacked.
  const navigation::NavPlan p = plan(v);
  if (p.found)
    follower_.replace(p.waypoints);
  else
    finish(NavStatus::Blocked, v.time, "no path any more on the newest map: " + p.reason);
}

void VelocityDrive::odometry(const CPose2D& odom, double t) {
  std::lock_guard<std::mutex> lock(mu_);
  if (!active_) return;
  if (o_.goal_timeout > 0 && t - started_ > o_.goal_timeout) {
    finish(NavStatus::Blocked, t, "the goal took longer than goal_timeout_s");
    return;
  }
  const navigation::Velocity cmd = follower_.update(map_to_odom_ + odom, t);
  switch (follower_.state()) {
    case navigation::FollowState::Arrived:
      finish(NavStatus::Reached, t, "arrived");
      return;
    case navigation::FollowState::Stuck:
      finish(NavStatus::Blocked, t, "no progress for stuck_timeout_s");
      return;
    default:
      break;
  }
  send_(cmd);
  ++sent_;
}

void VelocityDrive::finish(NavStatus s, double t, const std::string& why) {
  active_ = false;
  follower_.stop();
  outcome_ = s;
  outcome_time_ = t;
  why_ = why;
  send_({});  // the robot stops
  ++sent_;
}

void VelocityDrive::halt() {
  std::lock_guard<std::mutex> lock(mu_);
  const bool was = active_;
  active_ = false;
  follower_.stop();
  outcome_ = NavStatus::Idle;
  if (was || sent_ > 0) send_({}), ++sent_;
}

NavStatus VelocityDrive::status(double frame_time) const {
  std::lock_guard<std::mutex> lock(mu_);
  if (active_) return NavStatus::Moving;
  if (outcome_ == NavStatus::Moving) return NavStatus::Idle;  // halted
  if (outcome_ != NavStatus::Idle && frame_time < outcome_time_) return NavStatus::Moving;
  return outcome_;
}

std::string VelocityDrive::why() const {
  std::lock_guard<std::mutex> lock(mu_);
  return why_;
}

std::uint64_t VelocityDrive::commandsSent() const {
  std::lock_guard<std::mutex> lock(mu_);
  return sent_;
}

}  // namespace asf::ros2live
