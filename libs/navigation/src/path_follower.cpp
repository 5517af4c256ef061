#include <asf/navigation/path_follower.h>
#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>

namespace asf::navigation {

namespace {

double dist(const Point2& a, const Point2& b) { return std::hypot(a.x - b.x, a.y - b.y); }

}  // namespace

const char* followStateName(FollowState s) {
  switch (s) {
    case FollowState::Idle: return "idle";
    case FollowState::Following: return "following";
    case FollowState::Arrived: return "arrived";
    case FollowState::Stuck: return "stuck";
  }
  return "?";
}

void PathFollower::start(const std::vector<Point2>& path, double t) {
  path_ = path;
  next_ = 0;
  state_ = path_.empty() ? FollowState::Arrived : FollowState::Following;
  remaining_ = 0;
  for (std::size_t i = 1; i < path_.size(); ++i) remaining_ += dist(path_[i - 1], path_[i]);
  best_remaining_ = -1;  // set by the first update, from where the robot is
  best_time_ = t;
}

void PathFollower::replace(const std::vector<Point2>& path) {
  if (state_ != FollowState::Following) return;
  if (path.empty()) {
    state_ = FollowState::Arrived;
    return;
  }
  path_ = path;
  next_ = 0;
  best_remaining_ = -1;  // a detour may be longer: progress counts from the new path's length
}

void PathFollower::stop() {
  state_ = FollowState::Idle;
  path_.clear();
  next_ = 0;
}

// A waypoint is passed when the robot is within the lookahead of it, or beyond it along the
// next segment (a robot that went wide of a corner does not turn back for it). The last one
// is never passed: it is the end.
double PathFollower::remainingFrom(const Point2& p) {
  while (next_ + 1 < path_.size()) {
    const Point2& a = path_[next_];
    const Point2& b = path_[next_ + 1];
    const double along = (p.x - a.x) * (b.x - a.x) + (p.y - a.y) * (b.y - a.y);
    if (dist(p, a) >= o_.lookahead && along <= 0) break;
    ++next_;
  }
  double r = dist(p, path_[next_]);
  for (std::size_t i = next_ + 1; i < path_.size(); ++i) r += dist(path_[i - 1], path_[i]);
  return r;
}

Velocity PathFollower::update(const mrpt::poses::CPose2D& pose, double t) {
  if (state_ != FollowState::Following) return {};
  const Point2 p{pose.x(), pose.y()};
  remaining_ = remainingFrom(p);
  const Point2& target = path_[next_];
  if (next_ + 1 == path_.size() && dist(p, target) <= o_.arrival) {
    state_ = FollowState::Arrived;
    return {};
  }
  if (best_remaining_ < 0 || remaining_ < best_remaining_ - o_.stuck_progress) {
    if (best_remaining_ >= 0) best_time_ = t;  // a rebase (start, replan) is not progress
    best_remaining_ = remaining_;
  } else if (t - best_time_ > o_.stuck_time) {
    state_ = FollowState::Stuck;
    return {};
  }
  const double err = mrpt::math::wrapToPi(std::atan2(target.y - p.y, target.x - p.x) - pose.phi());
  Velocity v;
  v.turn = std::clamp(o_.turn_gain * err, -o_.max_turn, o_.max_turn);
  if (std::abs(err) > o_.heading_tolerance) return v;  // turn in place first
  const double ramp = o_.slow_down > 0 ? std::clamp(remaining_ / o_.slow_down, 0.1, 1.0) : 1.0;
  v.forward = o_.max_forward * std::cos(err) * ramp;
  return v;
}

}  // namespace asf::navigation
