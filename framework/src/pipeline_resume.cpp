// [pipeline] resume: a recorded run replayed through the stages, its decisions retaken by
// the policy, and the source sent where it was going (run_state.h).
#include <asf/errors.h>
#include <asf/io/recorded_run.h>

#include <cmath>
#include <filesystem>

#include "run_state.h"

namespace asf::framework::run {

bool RunState::replayRecorded() {
  const std::string& dir = limits_.resume;
  const std::string source = m_.cfg.slots.at("source")->name();
  const Params& sp = m_.cfg.plugin_params.at(source);
  if (!sp.has("resume_from") || sp.getString("resume_from") != dir)
    throw ConfigError("[pipeline] resume = " + dir + ": the source '" + source +
                      "' must continue that folder's recording (" + source +
                      ".resume_from = the same folder; asf run --resume sets both)");
  const std::vector<io::RecordedDecision> recorded =
      io::readRecordedDecisions((std::filesystem::path(dir) / "decisions.csv").string());
  std::size_t next = 0;
  GridMap goal_map;
  bool ended = false;  // the recorded run ended (or this one was stopped) within the log
  // The decisions recorded before the next frame, retaken by the policy on the same state.
  const auto retake = [&] {
    for (; !ended && next < recorded.size() && recorded[next].step <= sum_.steps; ++next) {
      const io::RecordedDecision& r = recorded[next];
      if (r.step < sum_.steps) continue;  // a row out of order: not this run's
      if (giveUp(r.previous)) return void(ended = true);
      const Decision d = policyDecision(explorationState(r.previous));
      ++sum_.replayed_decisions;
      const bool same =
          d.type == Decision::Type::Done
              ? r.done
              : !r.done && std::abs(d.goal.x - r.goal_x) <= 1e-4 * (1 + std::abs(r.goal_x)) &&
                    std::abs(d.goal.y - r.goal_y) <= 1e-4 * (1 + std::abs(r.goal_y));
      if (!same && sum_.replayed_decisions_differing++ == 0)
        m_.logStr(
            mrpt::system::LVL_WARN,
            "resume: the decision retaken at step " + std::to_string(r.step) +
                " differs from the recorded one (the replayed estimates differ): " + d.reason);
      goal_map = m_.navMap();  // what the recorded run's navigation planned on
      if (d.type == Decision::Type::Done) {
        if (!limits_.return_home) return void(ended = true);
        home_reason_ =
            "policy done: " + d.reason;  // the recorded frames that follow are the way home
        home_finishes_ = true;
        returning_home_ = true;
        home_from_distance_ = sum_.distance_m;
      }
    }
  };
  sum_.resumed_from = dir;
  m_.logStr(mrpt::system::LVL_INFO, "resume: replaying " + dir);
  const std::string name = sp.has("record_name") ? sp.getString("record_name") : source;
  const std::string base = (std::filesystem::path(dir) / name).string();
  io::forEachRecordedFrame(base, [&](SensorFrame& f) {
    if (stop_ && stop_->load()) ended = true;
    if (ended || (retake(), ended)) return;
    step(f);
  });
  retake();
  sum_.resumed_after_steps = sum_.steps;
  m_.logStr(mrpt::system::LVL_INFO,
            "resume: " + std::to_string(sum_.steps) + " recorded steps and " +
                std::to_string(sum_.replayed_decisions) + " decisions replayed (" +
                std::to_string(sum_.replayed_decisions_differing) + " differing); continuing");
  if (stop_ && stop_->load()) sum_.stop_reason = "interrupted";
  if (ended) return false;
  sum_.finished = false;  // a replayed Done on the way home: finished when home
  const mrpt::poses::CPose2D robot = m_.frontend->currentPose(m_.graph);
  if (returning_home_) {
    Goal home;
    home.x = m_.graph.nodes.front().pose.x();
    home.y = m_.graph.nodes.front().pose.y();
    last_goal_ = home;
  }
  if (have_goal_) navigateTo(last_goal_, robot, &goal_map);  // where the recorded run was going
  return true;
}

}  // namespace asf::framework::run
