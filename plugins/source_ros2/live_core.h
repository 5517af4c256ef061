#pragma once
// The live source's state, independent of DDS: what arrived (scans in order, poses over time,
// transforms, goal outcomes) and the rules that turn it into SensorFrames and navigation
// states. The DDS side (cyclone_link) feeds it from its receive thread; the plugin reads it.
#include <asf/goal.h>
#include <asf/source.h>
#include <asf/ros2/messages.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>

#include <array>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace asf::ros2live {

/// Planar poses over time (odometry, ground truth), oldest first, at most `capacity`.
class PoseHistory {
 public:
  explicit PoseHistory(std::size_t capacity = 4000) : capacity_(capacity) {}
  /// Adds a pose; one older than the newest is dropped (returns false).
  bool add(double t, const mrpt::poses::CPose2D& p);
  /// The pose at `t`: interpolated between the two around it, or the nearest end when `t` is
  /// outside the history by at most `tolerance`; nullopt otherwise.
  std::optional<mrpt::poses::CPose2D> at(double t, double tolerance) const;
  bool empty() const { return poses_.empty(); }
  double newest() const { return poses_.empty() ? -1e300 : poses_.back().first; }
  double oldest() const { return poses_.empty() ? 1e300 : poses_.front().first; }

 private:
  std::size_t capacity_;
  std::deque<std::pair<double, mrpt::poses::CPose2D>> poses_;
};

/// Transforms parent -> child as they arrive on /tf_static (and the latest of /tf).
class TransformTree {
 public:
  void set(const std::string& parent, const std::string& child, const mrpt::poses::CPose3D& p);
  /// The pose of `frame` in `base` by following parents from `frame` up to `base` (at most 16
  /// links); nullopt when `frame` does not lead to `base`.
  std::optional<mrpt::poses::CPose3D> lookup(const std::string& base,
                                             const std::string& frame) const;
  /// "a -> b, c -> d": what is known, for error messages.
  std::string describe() const;

 private:
  std::map<std::string, std::pair<std::string, mrpt::poses::CPose3D>> parent_of_;
};

using Uuid = std::array<std::uint8_t, 16>;

/// One entry of an action's status list.
struct GoalStatusEntry {
  Uuid id{};
  ros2::Stamp stamp;
  std::int8_t status = 0;
};

/// Follows the goals sent to a navigation stack through its action's status topic (nav2's
/// NavigateToPose: goals from /goal_pose get an id asf cannot know). A goal is adopted as ours
/// when an id appears that was not in any status list before we sent the goal. Its outcome
/// is reported only after the scans that arrived before the outcome did have been handed to
/// the pipeline, so the policy decides on a map that has seen where the robot stopped.
class GoalTracker {
 public:
  /// A goal was sent; `scans_arrived` counts the scans received so far.
  void sent(double wall_time);
  /// A status list arrived after `scans_arrived` scans had.
  void statusArrived(const std::vector<GoalStatusEntry>& list, std::uint64_t scans_arrived);
  /// What navigation says after `scans_returned` scans went to the pipeline, at `wall_time`:
  /// Moving until the adopted goal's outcome is visible (Reached on success, Unreachable when
  /// aborted, Blocked when canceled), Unreachable when no goal was adopted within
  /// `accept_timeout` s, Blocked when the goal ran longer than `goal_timeout` s (0: never).
  NavStatus status(std::uint64_t scans_returned, double wall_time, double accept_timeout,
                   double goal_timeout);
  bool active() const { return pending_; }
  /// Why the last goal ended the way it did (for the log): "" while it runs.
  const std::string& why() const { return why_; }
  void cancel() { pending_ = false; }
  /// The robot was stopped (the run paused): no goal, status Idle.
  void halt() {
    pending_ = false;
    last_ = NavStatus::Idle;
  }

 private:
  std::set<Uuid> seen_;
  std::optional<Uuid> ours_;
  bool pending_ = false;
  double sent_at_ = 0;
  std::int8_t state_ = 0;
  std::uint64_t state_after_scans_ = 0;
  NavStatus last_ = NavStatus::Idle;
  std::string why_;
};

/// One scan as it arrived, numbered in arrival order from 1.
struct ArrivedScan {
  ros2::LaserScan msg;
  std::uint64_t seq = 0;
  std::chrono::steady_clock::time_point arrived_at;  ///< when the receive thread queued it
};

/// Latencies in milliseconds, summarised as "median M ms, p95 P ms, max X ms over N", by
/// asf::percentile (nearest rank), as sim-robot reports its end-to-end figure. "none" for no
/// value.
std::string latencySummary(const std::vector<double>& ms);

/// Scans waiting for the pipeline, filled by the receive thread. At most `capacity` wait;
/// the oldest is dropped beyond (counted).
class ScanQueue {
 public:
  explicit ScanQueue(std::size_t capacity) : capacity_(capacity) {}
  void push(ros2::LaserScan msg);
  /// Waits up to `timeout` for a scan.
  std::optional<ArrivedScan> pop(std::chrono::milliseconds timeout);
  std::uint64_t arrived() const;
  std::uint64_t dropped() const;

 private:
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::deque<ArrivedScan> q_;
  std::size_t capacity_;
  std::uint64_t arrived_ = 0, dropped_ = 0;
};

/// An operator's command as text (std_msgs/String on the command topic): start or resume,
/// pause, stop, return_home (blanks and case ignored). Kind::None for anything else.
OperatorRequest::Kind parseOperatorCommand(const std::string& text);

/// Operator requests as they arrive on the command topic (receive thread), taken by the run.
class OperatorInbox {
 public:
  /// A text from `topic`: a request when it is a command, else kept to be reported.
  void arrived(const std::string& topic, const std::string& text);
  void push(OperatorRequest r);
  /// The oldest request not taken yet (Kind::None: none).
  OperatorRequest take();
  /// The texts that were not commands since the last call.
  std::vector<std::string> takeUnknown();

 private:
  std::mutex mu_;
  std::deque<OperatorRequest> requests_;
  std::vector<std::string> unknown_;
};

/// CPU seconds the calling thread has used so far.
double threadCpuSeconds();
/// CPU seconds of this process's threads other than the calling one, by thread name, from
/// /proc/self/task (Linux; empty elsewhere). Threads of one name are summed.
std::map<std::string, double> otherThreadsCpuByName();
/// Whether a thread name is one of Cyclone DDS's (recv, recvUC, recvMC, tev, dq.builtins,
/// dq.user, gc, lease, xmit.*, dds_*).
bool isCycloneThread(const std::string& name);
/// CPU seconds of the whole process.
double processCpuSeconds();
/// run.log's "bridge CPU" line: `run_thread_s` of the bridge's work on the run's thread,
/// `recording_s` of it recording the rawlog, Cyclone DDS's threads among `threads`
/// (otherThreadsCpuByName), against the whole process.
std::string bridgeCpuLine(const std::map<std::string, double>& threads, double run_thread_s,
                          double recording_s);

}  // namespace asf::ros2live
