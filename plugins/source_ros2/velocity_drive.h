#pragma once
// drive = cmd_vel: asf's own navigation on a live robot without a navigator. A goal is planned
// on the run's map (asf::navigation::planPath, the simulator's planner) and followed with
// velocity commands (PathFollower) on every odometry message, from the pose map -> odom (the
// run's estimate) places the odometry at; the path is replanned every replan_period on the
// newest map and scan. No DDS here: commands leave through a callback.
#include <asf/goal.h>
#include <asf/navigation/grid_path.h>
#include <asf/navigation/path_follower.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>

#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace mrpt::maps {
class COccupancyGridMap2D;
}

namespace asf::ros2live {

struct VelocityDriveOptions {
  navigation::NavOptions nav;
  navigation::FollowerOptions follow;
  double replan_period = 2;  ///< [s] of the robot's clock; 0: plan once per goal
  double goal_timeout = 0;   ///< a goal running longer is Blocked [s]; 0: no limit
};

class VelocityDrive {
 public:
  using Send = std::function<void(const navigation::Velocity&)>;
  VelocityDrive(const VelocityDriveOptions& o, Send send) : o_(o), send_(std::move(send)) {}

  /// What the planner sees: the map (may be null), the robot in the map frame, the odometry
  /// at that moment (placing map -> odom), the latest scan (its endpoints are obstacles on
  /// top of the map, right relative to the robot where the map has drifted; may be null) and
  /// the robot's clock. Run thread.
  struct View {
    std::shared_ptr<const mrpt::maps::COccupancyGridMap2D> map;
    mrpt::poses::CPose2D robot, odom;
    std::shared_ptr<const mrpt::obs::CObservation2DRangeScan> scan;
    double time = 0;
  };

  /// A new goal (replacing the one before): Reached when the robot is within its tolerance,
  /// Unreachable without a path (why() says why), else Moving.
  NavStatus navigate(const Goal& goal, const View& v);
  /// The run's estimate after a step: map -> odom, and a replan when one is due.
  void observe(const View& v);
  /// An odometry pose at time t: the next command, sent at once (receive thread).
  void odometry(const mrpt::poses::CPose2D& odom, double t);
  /// Stops the robot (a zero command) and forgets the goal.
  void halt();
  /// The goal's state as the run has seen it: an outcome at robot time T shows once a frame
  /// of time >= T went to the pipeline (`frame_time`), so the policy decides on a map that has
  /// seen where the robot stopped.
  NavStatus status(double frame_time) const;
  /// Why the last goal ended as it did, or was unreachable ("" while it runs).
  std::string why() const;
  std::uint64_t commandsSent() const;

 private:
  void finish(NavStatus s, double t, const std::string& why);  // under mu_
  navigation::NavPlan plan(const View& v) const;

  VelocityDriveOptions o_;
  Send send_;
  mutable std::mutex mu_;
  navigation::PathFollower follower_{o_.follow};
  mrpt::poses::CPose2D map_to_odom_;
  Goal goal_;
  bool active_ = false;
  NavStatus outcome_ = NavStatus::Idle;
  double outcome_time_ = 0, started_ = 0, planned_ = 0;
  std::string why_;
  std::uint64_t sent_ = 0;
};

}  // namespace asf::ros2live
