#pragma once
// One run of the pipeline (pipeline_run.cpp, pipeline_resume.cpp): the loop's state and its
// stages. Private to the framework.
#include <asf/io/recorded_run.h>

#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "pipeline_impl.h"
#include "recorder.h"

namespace asf::framework::run {

using Clock = std::chrono::steady_clock;

inline double planarDistance(const mrpt::poses::CPose2D& a, const mrpt::poses::CPose2D& b) {
  return std::hypot(a.x() - b.x(), a.y() - b.y());
}

/// The [pipeline] keys the loop reads, once.
struct RunLimits {
  explicit RunLimits(const Params& p)
      : max_steps(static_cast<long>(p.getInt("max_steps"))),
        steps_budget(!p.isDefault("max_steps") && max_steps > 0),
        max_distance(p.getDouble("max_distance")),
        optimize_every(static_cast<long>(p.getInt("optimize_every"))),
        segment_every(static_cast<long>(p.getInt("segment_every"))),
        max_failed(static_cast<int>(p.getInt("max_failed_goals"))),
        max_idle(static_cast<int>(p.getInt("max_idle_decisions"))),
        want_marginals(p.getBool("marginals")),
        return_home(p.getBool("return_home")),
        timeline(p.getBool("timeline")),
        timeline_max_side(static_cast<int>(p.getInt("timeline_max_side"))),
        progress_timeout_m(p.getDouble("progress_timeout_m")),
        progress_timeout_s(p.getDouble("progress_timeout_s")),
        progress_min_area(p.getDouble("progress_min_area")),
        progress_interval(p.getDouble("progress_interval")),
        snapshots(p.getDoubleList("snapshot_distances")),
        resume(p.getString("resume")) {
    std::sort(snapshots.begin(), snapshots.end());
  }
  long max_steps;
  bool steps_budget;  ///< max_steps was set (not the default): the progress line has an ETA
  double max_distance;
  long optimize_every, segment_every;
  int max_failed, max_idle;
  bool want_marginals;
  bool return_home;
  bool timeline;
  int timeline_max_side;
  double progress_timeout_m, progress_timeout_s, progress_min_area;
  double progress_interval;
  std::vector<double> snapshots;  ///< sorted
  std::string resume;             ///< a run folder to continue; empty: a new run
};

class RunState {
 public:
  RunState(PipelineParts& m, const std::atomic<bool>* stop, const std::atomic<bool>* pause,
           const std::atomic<bool>* home)
      : m_(m),
        stop_(stop),
        pause_(pause),
        home_(home),
        limits_(m.cfg.pipeline),
        exploring_(m.policy && m.source->isActive()),
        t_start_(Clock::now()),
        last_progress_(t_start_),
        rec_(m.out_dir, m.cfg) {}

  RunSummary run();

 private:
  bool budgetSpent();
  /// The policy's turn when the robot is idle; false when the run stops.
  bool decide();
  ExplorationState explorationState(NavStatus last_status) const;
  /// The policy's decision on `s`, timed and recorded (decisions.csv, timeline); a goal
  /// becomes the last goal, Done sets the stop reason.
  Decision policyDecision(const ExplorationState& s);
  /// Sends the source to `goal` planning on `map` (null: the navigation map now).
  NavStatus navigateTo(const Goal& goal, const mrpt::poses::CPose2D& robot,
                       const GridMap* map = nullptr);
  /// [pipeline] resume: the recorded frames through the stages and the recorded decisions
  /// retaken by the policy on the states they were taken on, then the source sent where the
  /// recorded run was going. False when the recorded run ended within its log.
  bool replayRecorded();
  /// The operator's turn (run_operator.cpp): requests from the source, pausing (the robot
  /// halted) and resuming as they and pause_ say, the way home when asked; false on a stop.
  bool operatorTurn();
  /// Takes the source's operator requests; false on Stop (the stop reason set).
  bool takeRequests();
  bool homeSignalPending() const { return home_ && home_->load() && !home_signal_taken_; }
  void enterPause();
  void leavePause();
  /// Holds the run (no step, no decision) while paused, until resumed or stopped (a source
  /// that is not live: nothing comes meanwhile).
  void waitWhilePaused();
  /// Sends the robot to the start, `why` (the stop reason's start); `finishes`: the run is
  /// finished when it gets there. False when that failed at once (then the run stops, saying
  /// so).
  bool goHome(const std::string& why, bool finishes, const mrpt::poses::CPose2D& robot);
  /// The robot stopped on its way home: the stop reason says whether it got there.
  bool arrivedHome(NavStatus st);
  bool giveUp(NavStatus status);
  /// One frame through the stages.
  void step(const SensorFrame& frame);
  /// Front-end (and the frame's 3D keyframes); true if the graph changed.
  bool sense(const SensorFrame& frame);
  void optimize();
  /// The maps from the graph; true if the navigation grid changed.
  bool updateMaps(bool graph_changed);
  /// Segmentation and topological graph of the navigation grid; returns its time [ms].
  double segment();
  /// Poses, distance, pose error, the recorder's rows and snapshots.
  void track(const SensorFrame& frame, bool map_changed);
  /// Hands the source the run's estimate (Source::observe).
  void observe(double timestamp, bool final);
  /// Keyframes added since the last optimization are optimized once more at the end, so the
  /// outputs (graph, map, ATE) are those of the whole graph, not of an earlier state of it.
  void finalOptimization();
  void summarize();
  void writeOutputs();
  void finish();
  /// The planner's path home, logged after the outputs are on disk: a slow planner on a large
  /// graph then costs time, never the run's files; an interrupted run skips it.
  void checkPathHome();
  void seriesRow(double pose_error);
  /// The live view's picture, when one is due (or `force`d); the last one to live_view.png.
  void showLive(bool force);
  void progress(bool force);
  double currentPoseError() const { return err_n_ ? planarDistance(*last_truth_, last_est_) : -1; }
  std::size_t loopClosures() const;

  PipelineParts& m_;
  const std::atomic<bool>* stop_;
  const std::atomic<bool>* pause_;
  const std::atomic<bool>* home_;  ///< set: drive back to the start (once)
  const RunLimits limits_;
  const bool exploring_;
  const Clock::time_point t_start_;
  Clock::time_point last_progress_;
  Recorder rec_;
  RunSummary sum_;

  std::size_t next_snapshot_ = 0;
  std::optional<mrpt::poses::CPose2D> gt0_, last_truth_;
  mrpt::poses::CPose2D last_est_;
  double err_sum_ = 0, t0_ = 0, now_t_ = 0;
  long err_n_ = 0, nodes_since_opt_ = 0;
  int failed_in_row_ = 0, idle_decisions_ = 0;
  double idle_since_distance_ = 0;
  /// The last time the explored area grew by progress_min_area: its area, distance, time.
  double progress_area_ = 0, progress_distance_ = 0, progress_time_ = 0;
  bool returning_home_ = false;  ///< the robot drives to the start (policy done, or asked to)
  bool home_finishes_ = false;   ///< arriving there finishes the run (the policy was done)
  double home_from_distance_ = 0;
  std::string home_reason_;  ///< why it drives home, for the stop reason at home
  // The operator's side (run_operator.cpp).
  bool paused_ = false;           ///< no decision: pause_ or an operator's request
  bool operator_paused_ = false;  ///< an operator's Pause not yet resumed
  bool operator_stop_ = false;    ///< an operator's Stop
  double paused_at_ = 0;          ///< now_t_ when the pause began
  std::string home_request_;      ///< an operator's ReturnHome not yet acted on (its origin)
  bool home_signal_taken_ = false;  ///< home_ was acted on
  Goal last_goal_;
  bool have_goal_ = false;
  // Compute time per stage since the last timeseries row, and per call for the summary.
  struct StageMs {
    double frontend = 0, backend = 0, map = 0, segment = 0, policy = 0;
  } stage_;
  std::vector<double> decision_ms_, segment_ms_;
  SegmentationLog seg_log_;
  double last_coverage_ = -1;
  Clock::time_point last_live_{};
};

}  // namespace asf::framework::run
