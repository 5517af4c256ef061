// One run of the pipeline: the loop's state and one method per stage (decide, sense,
// optimize, update maps, segment, track), the final optimization reusing them, and the
// summary.
#include <asf/errors.h>
#include <asf/evaluation/map_views.h>
#include <asf/evaluation/run_report.h>
#include <asf/text.h>
#include <asf/evaluation/trajectory_eval.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <thread>

#include "run_state.h"

namespace asf::framework::run {

RunSummary RunState::run() {
  try {
    const bool go_on = limits_.resume.empty() || replayRecorded();
    while (go_on && !budgetSpent()) {
      if (!operatorTurn()) break;  // an operator's stop
      if (paused_) {
        if (!m_.source->isLive()) {
          waitWhilePaused();
          continue;  // the stop flag first
        }
      } else if (exploring_ && m_.source->status() != NavStatus::Moving && !decide()) {
        break;
      }
      std::optional<SensorFrame> frame = m_.source->next();
      if (!frame) {
        sum_.finished = !exploring_;
        sum_.stop_reason = "source ended";
        break;
      }
      step(*frame);
    }
    finalOptimization();
    if (sum_.steps > 0) observe(t0_ + now_t_, true);
  } catch (const std::exception& e) {
    sum_.stop_reason = std::string("error: ") + e.what();
    if (m_.log) m_.log->endProgress();
    finish();
    throw;
  }
  progress(true);
  if (m_.log) m_.log->endProgress();
  finish();
  checkPathHome();
  return sum_;
}

bool RunState::budgetSpent() {
  // A timeout over `limit` of distance or time since the explored area last grew.
  auto noProgress = [&](double since, double limit, const char* unit, const char* key) {
    if (returning_home_ || paused_ || limit <= 0 || since < limit) return false;
    sum_.stop_reason = "no progress: the explored area grew by less than " +
                       formatSignificant(limits_.progress_min_area, 3) + " m^2 over the last " +
                       formatSignificant(limit, 4) + " " + unit + " (" + key + ")";
    return true;
  };
  if (stop_ && stop_->load()) {
    sum_.stop_reason = "interrupted";
  } else if (limits_.max_steps > 0 && sum_.steps >= limits_.max_steps) {
    sum_.stop_reason = "step budget (" + std::to_string(limits_.max_steps) + ") spent";
  } else if (limits_.max_distance > 0 && sum_.distance_m >= limits_.max_distance) {
    sum_.stop_reason = "distance budget spent";
  } else if (noProgress(sum_.distance_m - progress_distance_, limits_.progress_timeout_m, "m",
                        "progress_timeout_m") ||
             noProgress(now_t_ - progress_time_, limits_.progress_timeout_s, "s",
                        "progress_timeout_s")) {
    // the reason is set
  } else {
    return false;
  }
  if (returning_home_)  // the exploration itself was done, or the operator called it off
    sum_.stop_reason = home_reason_ + "; stopped on the way back to the start: " + sum_.stop_reason;
  return true;
}

bool RunState::giveUp(NavStatus st) {
  failed_in_row_ =
      (st == NavStatus::Unreachable || st == NavStatus::Blocked) ? failed_in_row_ + 1 : 0;
  if (failed_in_row_ >= limits_.max_failed) {
    sum_.stop_reason =
        "the policy's last " + std::to_string(failed_in_row_) + " goals failed; giving up";
    return true;
  }
  // Counts the decisions since the robot last moved 0.1 m (the previous one included).
  if (sum_.distance_m - idle_since_distance_ >= 0.1) {
    idle_since_distance_ = sum_.distance_m;
    idle_decisions_ = 0;
  } else if (sum_.decisions > 0 && ++idle_decisions_ >= limits_.max_idle) {
    sum_.stop_reason = "no progress: the policy's last " + std::to_string(idle_decisions_) +
                       " decisions moved the robot less than 0.1 m";
    return true;
  }
  return false;
}

ExplorationState RunState::explorationState(NavStatus st) const {
  ExplorationState s;
  s.topo = &m_.topo.graph();
  s.robot = m_.frontend->currentPose(m_.graph);
  s.map = m_.navMap().version ? &m_.navMap() : nullptr;
  s.graph = &m_.graph;
  s.marginals = m_.marginals.valid() ? &m_.marginals : nullptr;
  s.planner = m_.planner.instance.get();
  s.time = now_t_;
  s.last_status = st;
  s.last_goal = last_goal_;
  s.segmentation = m_.seg.regions.empty() ? nullptr : &m_.seg;
  s.world_topo = m_.have_world_topo ? &m_.world_topo : nullptr;
  return s;
}

Decision RunState::policyDecision(const ExplorationState& s) {
  const auto t_dec = Clock::now();
  const Decision d = m_.policy->decide(s);
  const double dec_ms = msSince(t_dec);
  stage_.policy += dec_ms;
  decision_ms_.push_back(dec_ms);
  ++sum_.decisions;
  rec_.decision(sum_.steps, s.time, d, s.last_status);
  if (limits_.timeline) {
    const Point2 goal{d.goal.x, d.goal.y};
    rec_.timelineFrame(sum_.decisions, m_.navMap(), m_.seg, m_.topo.graph(), m_.path, s.robot,
                       d.type == Decision::Type::GoTo ? &goal : nullptr, limits_.timeline_max_side);
  }
  if (d.type == Decision::Type::Done) {
    sum_.finished = true;
    sum_.stop_reason = "policy done: " + d.reason;
  } else if (!std::isfinite(d.goal.x) || !std::isfinite(d.goal.y)) {
    throw Error("policy '" + m_.cfg.slots.at("policy")->name() + "' returned a non-finite goal");
  } else {
    m_.logStr(mrpt::system::LVL_DEBUG, "goal (" + std::to_string(d.goal.x) + ", " +
                                           std::to_string(d.goal.y) + "): " + d.reason);
    last_goal_ = d.goal;
    have_goal_ = true;
  }
  return d;
}

NavStatus RunState::navigateTo(const Goal& goal, const mrpt::poses::CPose2D& robot,
                               const GridMap* map) {
  if (!map) map = &m_.navMap();
  NavigationContext ctx;
  ctx.robot_estimate = robot;
  ctx.map = map->version ? map : nullptr;
  return m_.source->navigate(goal, ctx);
}

bool RunState::decide() {
  const NavStatus st = have_goal_ ? m_.source->status() : NavStatus::Idle;
  if (returning_home_) return arrivedHome(st);
  if (giveUp(st)) return false;
  const ExplorationState s = explorationState(st);
  const Decision d = policyDecision(s);
  if (d.type == Decision::Type::Done)
    return limits_.return_home && goHome("policy done: " + d.reason, true, s.robot);
  navigateTo(d.goal, s.robot);
  return true;
}

void RunState::step(const SensorFrame& frame) {
  if (sum_.steps == 0) t0_ = frame.timestamp;
  ++sum_.steps;
  now_t_ = frame.timestamp - t0_;
  const bool changed = sense(frame);
  if (changed) ++nodes_since_opt_;
  if (changed && m_.backend && nodes_since_opt_ >= limits_.optimize_every) optimize();
  const bool map_changed = updateMaps(changed);
  if (map_changed && m_.segmenter && m_.navMap().version % limits_.segment_every == 0) {
    const double ms = segment();
    segment_ms_.push_back(ms);
    seg_log_.add(m_.seg, ms);
  }
  track(frame, map_changed);
  observe(frame.timestamp, false);
}

void RunState::observe(double timestamp, bool final) {
  RunView v;
  v.timestamp = timestamp;
  v.robot = m_.frontend->currentPose(m_.graph);
  v.map = &m_.navMap();
  v.segmentation = m_.seg.regions.empty() ? nullptr : &m_.seg;
  v.topo = &m_.topo.graph();
  v.graph = &m_.graph;
  v.goal = have_goal_ ? &last_goal_ : nullptr;  // the last goal given
  v.final = final;
  v.paused = paused_;
  v.returning_home = returning_home_;
  m_.source->observe(v);
}

bool RunState::sense(const SensorFrame& frame) {
  auto t_stage = Clock::now();
  const std::size_t nodes_before = m_.graph.size();
  const bool changed = m_.frontend->process(frame, m_.graph, m_.marginals);
  stage_.frontend += msSince(t_stage);
  t_stage = Clock::now();
  m_.maps.addKeyframes3d(frame, m_.graph, nodes_before, m_);
  stage_.map += msSince(t_stage);
  return changed;
}

void RunState::optimize() {
  const auto t_stage = Clock::now();
  nodes_since_opt_ = 0;
  m_.backend->optimize(m_.graph);
  if (limits_.want_marginals) m_.marginals = m_.backend->marginals(m_.graph);
  m_.marginals.graph_revision = m_.graph.revision;
  stage_.backend += msSince(t_stage);
  m_.maps.followGraph(m_.graph);
}

bool RunState::updateMaps(bool graph_changed) {
  const auto t_stage = Clock::now();
  const bool map_changed = m_.maps.update(m_.graph, graph_changed);
  if (map_changed) m_.area.update(m_.navMap());  // every version: the change box holds
  stage_.map += msSince(t_stage);
  return map_changed;
}

double RunState::segment() {
  const auto t_stage = Clock::now();
  m_.seg = m_.segmenter->segment(m_.navMap(), m_.seg.regions.empty() ? nullptr : &m_.seg);
  m_.seg.map_version = m_.navMap().version;
  m_.topo.update(m_.seg, m_.navMap(), &m_.graph);
  const double ms = msSince(t_stage);
  stage_.segment += ms;
  return ms;
}

void RunState::track(const SensorFrame& frame, bool map_changed) {
  const mrpt::poses::CPose2D est = m_.frontend->currentPose(m_.graph);
  m_.topo.observeRobot(est.x(), est.y(), now_t_);
  std::optional<mrpt::poses::CPose2D> truth;
  if (frame.ground_truth) {
    if (!gt0_) gt0_ = *frame.ground_truth;
    truth = *frame.ground_truth - *gt0_;  // in the map frame (first pose = origin)
  }
  if (sum_.steps > 1)
    sum_.distance_m += (truth && last_truth_) ? planarDistance(*truth, *last_truth_)
                                              : planarDistance(est, last_est_);
  if (truth) {
    err_sum_ += planarDistance(*truth, est);
    ++err_n_;
  }
  last_truth_ = truth;
  last_est_ = est;
  m_.path.push_back(est);
  rec_.step(
      {sum_.steps, now_t_, est, truth, m_.graph.size(), m_.graph.edges.size(), sum_.distance_m});
  const auto& snapshots = limits_.snapshots;
  for (; next_snapshot_ < snapshots.size() && sum_.distance_m >= snapshots[next_snapshot_];
       ++next_snapshot_)
    rec_.snapshot(snapshots[next_snapshot_], m_.graph, m_.navMap(), m_.seg, m_.topo.graph(),
                  m_.path);
  if (map_changed) seriesRow(truth ? planarDistance(*truth, est) : -1);
  progress(false);
  if (m_.live_view) showLive(false);
}

void RunState::showLive(bool force) {
  const auto now = Clock::now();
  if (!force && std::chrono::duration<double>(now - last_live_).count() < m_.live_period_s) return;
  last_live_ = now;
  const Point2 goal{last_goal_.x, last_goal_.y};
  const evaluation::ViewImage view = evaluation::renderLiveView(
      m_.navMap(), m_.seg, m_.topo.graph(), m_.graph, m_.path, m_.frontend->currentPose(m_.graph),
      have_goal_ ? &goal : nullptr, m_.live_max_side);
  if (view.bgr.empty()) return;
  m_.live_view(view);
  if (force) evaluation::writeViewPng(m_.out_dir + "/live_view.png", view);
}

void RunState::finalOptimization() {
  if (!m_.backend || nodes_since_opt_ == 0 || m_.graph.size() < 2) return;
  optimize();
  // The whole 3D rebuild now: the final segmentation sees the final graph's map.
  m_.maps.completeRebuild();
  if (m_.maps.update(m_.graph, true) && m_.segmenter) segment();
}

std::size_t RunState::loopClosures() const {
  return static_cast<std::size_t>(
      std::count_if(m_.graph.edges.begin(), m_.graph.edges.end(),
                    [](const PoseEdge& e) { return e.kind == EdgeKind::LoopClosure; }));
}

void RunState::seriesRow(double pose_error) {
  Recorder::SeriesRow r;
  r.step = sum_.steps;
  r.time = now_t_;
  r.distance = sum_.distance_m;
  const auto t_area = Clock::now();
  m_.area.update(m_.navMap());
  stage_.map += msSince(t_area);
  if (m_.coverage) {
    last_coverage_ = r.coverage = m_.area.coverage();
    for (int k = 0; k < 5; ++k)
      if (sum_.coverage_distance_m[k] < 0 && r.coverage >= RunSummary::kCoverageMilestones[k]) {
        sum_.coverage_distance_m[k] = r.distance;
        sum_.coverage_time_s[k] = r.time;
      }
  }
  r.explored_area = m_.area.freeArea();
  if (r.explored_area >= progress_area_ + limits_.progress_min_area) {
    progress_area_ = r.explored_area;
    progress_distance_ = r.distance;
    progress_time_ = r.time;
  }
  if (m_.navMap().grid) r.map_information_bits = m_.area.informationBits();
  r.pose_error = pose_error;
  r.loop_closures = loopClosures();
  r.nodes = m_.graph.size();
  r.edges = m_.graph.edges.size();
  r.regions = m_.seg.regions.size();
  r.decisions = sum_.decisions;
  r.ms = {stage_.frontend, stage_.backend, stage_.map, stage_.segment, stage_.policy};
  r.segmentations = seg_log_.total;
  r.incremental_segmentations = seg_log_.incremental;
  r.changed_cells = seg_log_.takeChangedSinceRow();
  rec_.series(r);
  stage_ = {};
}

void RunState::progress(bool force) {
  const auto now = Clock::now();
  if (!force &&
      (limits_.progress_interval <= 0 ||
       std::chrono::duration<double>(now - last_progress_).count() < limits_.progress_interval))
    return;
  last_progress_ = now;
  std::ostringstream os;
  os << std::fixed << std::setprecision(2) << "step " << sum_.steps << "  dist " << sum_.distance_m
     << " m  nodes " << m_.graph.size() << "  edges " << m_.graph.edges.size() << "  regions "
     << m_.seg.regions.size() << "  decisions " << sum_.decisions;
  if (last_coverage_ >= 0)
    os << "  coverage " << std::setprecision(1) << 100 * last_coverage_ << "%"
       << std::setprecision(2);
  if (err_n_) os << "  pose error " << currentPoseError() << " m";
  const double elapsed = std::chrono::duration<double>(now - t_start_).count();
  os << "  (" << std::setprecision(1) << elapsed << " s";
  // A budget set: the share spent and, at this pace, the most time left (a bound: an
  // exploration that finishes stops before its budget).
  double used = 0;
  if (limits_.steps_budget) used = static_cast<double>(sum_.steps) / limits_.max_steps;
  if (limits_.max_distance > 0) used = std::max(used, sum_.distance_m / limits_.max_distance);
  if (used > 0 && used < 1)
    os << ", budget " << std::setprecision(0) << 100 * used
       << "%, <= " << elapsed * (1 - used) / used << " s left";
  os << ")";
  m_.logStr(mrpt::system::LVL_INFO, os.str());
  if (m_.log) m_.log->progress(os.str());
}

void RunState::summarize() {
  sum_.nodes = m_.graph.size();
  sum_.edges = m_.graph.edges.size();
  sum_.regions = m_.seg.regions.size();
  if (err_n_) {
    sum_.mean_pose_error_m = err_sum_ / err_n_;
    sum_.final_pose_error_m = currentPoseError();
  }
  std::vector<mrpt::poses::CPose2D> kf_est, kf_gt;
  for (const PoseNode& n : m_.graph.nodes)
    if (n.ground_truth) {
      kf_est.push_back(n.pose);
      kf_gt.push_back(*n.ground_truth);
    }
  if (kf_est.size() >= 2) {
    const evaluation::TrajectoryError te = evaluation::evaluateMatched(kf_est, kf_gt);
    sum_.ate_rmse_m = te.ate_rmse_m;
    sum_.ate_max_m = te.ate_max_m;
    sum_.ate_poses = te.poses;
    const evaluation::RelativePoseError rpe = evaluation::relativePoseError(kf_est, kf_gt);
    sum_.rpe_trans_rmse_m = rpe.trans_rmse_m;
    sum_.rpe_rot_rmse_deg = rpe.rot_rmse_deg;
  }
  sum_.loop_closures = loopClosures();
  sum_.explored_area_m2 = mapping::freeArea(m_.navMap());
  if (const auto& grid = m_.navMap().grid) {
    sum_.map_cells = static_cast<std::size_t>(grid->getSizeX()) * grid->getSizeY();
    sum_.map_information_bits = mapping::mapInformationBits(m_.navMap());
    sum_.map_entropy_bits = mapping::mapEntropyBits(m_.navMap());
  }
  sum_.map_versions = m_.maps.scanMap().version;
  sum_.map_rebuilds = m_.maps.scanMapRebuilds();
  if (m_.coverage) {
    sum_.coverage = m_.coverage->coverage(m_.navMap());
    sum_.reachable_area_m2 = m_.coverage->reachableArea();
  }
  if (!decision_ms_.empty()) {
    double total = 0;
    for (double v : decision_ms_) total += v;
    sum_.decision_ms_mean = total / decision_ms_.size();
    sum_.decision_ms_max = *std::max_element(decision_ms_.begin(), decision_ms_.end());
  }
  if (!segment_ms_.empty()) {
    std::vector<double> v = segment_ms_;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    sum_.segment_ms_median = v[v.size() / 2];
  }
  seg_log_.summarize(sum_);
  if (m_.policy) sum_.policy = m_.cfg.slots.at("policy")->name();
  sum_.seed = static_cast<long>(m_.cfg.pipeline.getInt("seed"));
}

void RunState::writeOutputs() {
  std::string err;
  // The source's recordings close first, so summary.json says whether one lost anything.
  try {
    if (m_.source) m_.source->endRecording();
  } catch (const std::exception& e) {
    err = std::string("recording: ") + e.what();
  }
  rec_.finish(m_.graph, m_.navMap(), m_.seg, m_.topo.graph(), m_.path, sum_, err);
  if (m_.maps.hasMap3d()) {
    const Recorder::Map3dInfo info = m_.maps.map3dInfo();
    rec_.finishMap3d(m_.maps.map3d(), m_.maps.projected(), m_.cfg.map3d, info, err);
    if (info.keyframes == 0)
      m_.logStr(mrpt::system::LVL_WARN,
                "[pipeline] map3d: no 3D observation reached a keyframe (does the source give "
                "any? e.g. [rawlog] observations3d = true)");
  }
  try {
    evaluation::writeRunReport(m_.out_dir);
  } catch (const std::exception& e) {
    err += std::string(err.empty() ? "" : "; ") + "report.html: " + e.what();
  }
  rec_.finalStatus(sum_, err);
  if (!err.empty()) m_.logStr(mrpt::system::LVL_ERROR, "writing outputs: " + err);
  sum_.output_errors = err;
}

void RunState::finish() {
  if (m_.maps.hasMap3d()) {
    // A rebuild still under way is completed: the outputs show the final graph's map.
    try {
      m_.maps.completeRebuild();
      m_.maps.update(m_.graph, false);
    } catch (const std::exception& e) {
      m_.logStr(mrpt::system::LVL_ERROR, std::string("map3d: ") + e.what());
    }
  }
  summarize();
  seriesRow(currentPoseError());
  if (m_.live_view) {
    try {
      showLive(true);
    } catch (const std::exception& e) {
      m_.logStr(mrpt::system::LVL_ERROR, std::string("live view: ") + e.what());
    }
  }
  sum_.wall_time_s = std::chrono::duration<double>(Clock::now() - t_start_).count();
  writeOutputs();
}

void RunState::checkPathHome() {
  if (!m_.planner || m_.graph.size() <= 1 || (stop_ && stop_->load())) return;
  PlanRequest req;
  req.graph = &m_.graph;
  req.marginals = m_.marginals.valid() ? &m_.marginals : nullptr;
  req.map = m_.navMap().version ? &m_.navMap() : nullptr;
  req.start = static_cast<NodeId>(m_.graph.size() - 1);
  req.goal = 0;
  const PlanResult r = m_.planner->plan(req);
  std::ostringstream os;
  if (r.found)
    os << "planner: path home (node " << req.start << " -> 0): " << r.nodes.size() << " nodes, "
       << r.criterion << " " << r.cost;
  else
    os << "planner: no path home: " << r.reason;
  m_.logStr(mrpt::system::LVL_INFO, os.str());
}

}  // namespace asf::framework::run

namespace asf::framework {

RunSummary runPipeline(PipelineParts& parts, const std::atomic<bool>* stop,
                       const std::atomic<bool>* pause, const std::atomic<bool>* home) {
  return run::RunState(parts, stop, pause, home).run();
}

}  // namespace asf::framework
