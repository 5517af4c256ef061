#pragma once
// Following a planned path with velocity commands (a differential-drive robot, REP 103 units:
// m/s forward, rad/s counter-clockwise): what a controller server does between a planner's
// path and a robot's /cmd_vel. The rule is the simulator's own driving (sim2d) made
// continuous: turn in place while the heading error to the path is large, else drive and
// steer towards a point a little ahead on the path; slow down at the end; give up when no
// progress is made for a while.
#include <asf/geometry.h>
#include <mrpt/poses/CPose2D.h>

#include <string>
#include <vector>

namespace asf::navigation {

struct FollowerOptions {
  double max_forward = 0.5;         ///< [m/s]
  double max_turn = 1.745;          ///< [rad/s] (100 deg/s)
  double heading_tolerance = 0.35;  ///< above this heading error the robot turns in place [rad]
  double lookahead = 0.2;           ///< steer towards the path point this far ahead [m]
  double turn_gain = 2.5;           ///< turn rate per radian of heading error [1/s]
  double slow_down = 0.5;           ///< within this of the end the speed falls linearly [m]
  double arrival = 0.05;            ///< the end is reached within this [m]
  double stuck_time = 10;           ///< no progress for this long: stuck [s]
  double stuck_progress = 0.1;      ///< what counts as progress: this much less path left [m]
};

/// A velocity command.
struct Velocity {
  double forward = 0;  ///< [m/s]
  double turn = 0;     ///< [rad/s]
};

enum class FollowState { Idle, Following, Arrived, Stuck };

const char* followStateName(FollowState s);

class PathFollower {
 public:
  explicit PathFollower(const FollowerOptions& o = {}) : o_(o) {}

  /// Starts following `path` (waypoints in the frame of the poses given to update(), the end
  /// last) at time `t` [s]. An empty path is arrived at once.
  void start(const std::vector<Point2>& path, double t);
  /// A new path to the same end (a replan): the progress watch goes on.
  void replace(const std::vector<Point2>& path);
  /// Stops following (Idle).
  void stop();

  /// The command for the robot at `pose` at time `t` [s]; zero unless Following. Switches to
  /// Arrived within `arrival` of the end, to Stuck when the path left did not shrink by
  /// `stuck_progress` for `stuck_time`.
  Velocity update(const mrpt::poses::CPose2D& pose, double t);

  FollowState state() const { return state_; }
  bool following() const { return state_ == FollowState::Following; }
  /// Metres of path left from the last pose given to update() (start: the whole path).
  double remaining() const { return remaining_; }
  const std::vector<Point2>& path() const { return path_; }

 private:
  double remainingFrom(const Point2& p);  // advances next_ past passed waypoints

  FollowerOptions o_;
  std::vector<Point2> path_;
  std::size_t next_ = 0;  // the first waypoint not passed yet
  FollowState state_ = FollowState::Idle;
  double remaining_ = 0, best_remaining_ = 0, best_time_ = 0;
};

}  // namespace asf::navigation
