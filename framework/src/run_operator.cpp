// The run's operator side: pause and resume (SIGUSR1, or requests through the source), an
// operator's stop, and the way home (when the policy is done with return_home, or asked).
#include <asf/text.h>

#include <thread>
#include <utility>

#include "run_state.h"

namespace asf::framework::run {

bool RunState::operatorTurn() {
  if (!takeRequests()) return false;
  if (homeSignalPending()) {
    home_signal_taken_ = true;
    home_request_ = "SIGUSR2";
  }
  const bool want = operator_paused_ || (pause_ && pause_->load());
  if (want && !paused_) enterPause();
  if (!want && paused_) leavePause();
  if (!home_request_.empty()) {
    const std::string from = std::exchange(home_request_, "");
    if (!exploring_) {
      m_.logStr(mrpt::system::LVL_WARN,
                "return home (" + from + "): the source does not drive; ignored");
    } else if (!returning_home_ && !m_.graph.empty()) {
      const auto robot = m_.frontend->currentPose(m_.graph);
      if (!goHome("the operator asked to return home (" + from + ")", false, robot)) return false;
    }
  }
  return true;
}

bool RunState::takeRequests() {
  using Kind = OperatorRequest::Kind;
  for (OperatorRequest r = m_.source->takeOperatorRequest(); r.kind != Kind::None;
       r = m_.source->takeOperatorRequest()) {
    switch (r.kind) {
      case Kind::Pause:
        operator_paused_ = true;
        m_.logStr(mrpt::system::LVL_INFO, "pause requested (" + r.from + ")");
        break;
      case Kind::Resume:
        operator_paused_ = false;
        m_.logStr(mrpt::system::LVL_INFO, "resume requested (" + r.from + ")");
        break;
      case Kind::ReturnHome:
        operator_paused_ = false;
        home_request_ = r.from;
        break;
      case Kind::Stop:
        operator_stop_ = true;
        sum_.stop_reason = "stopped by the operator (" + r.from + ")";
        if (returning_home_) sum_.stop_reason = home_reason_ + "; " + sum_.stop_reason;
        break;
      case Kind::None:
        break;
    }
  }
  return !operator_stop_;
}

// A live robot is halted and the run goes on mapping; any other source is held between two
// steps and goes on afterwards as if it had not been paused.
void RunState::enterPause() {
  paused_ = true;
  paused_at_ = now_t_;
  if (m_.source->isLive()) m_.source->halt();  // the robot stops where it is
  m_.logStr(mrpt::system::LVL_INFO, "paused at step " + std::to_string(sum_.steps));
  rec_.status("paused");
}

void RunState::leavePause() {
  paused_ = false;
  progress_time_ += now_t_ - paused_at_;  // a pause is no lack of progress
  m_.logStr(mrpt::system::LVL_INFO, "resumed at step " + std::to_string(sum_.steps));
  rec_.status("running");
  if (!m_.source->isLive()) return;
  // The halted goal: the way home is taken up again; anything else the policy decides anew.
  if (returning_home_) navigateTo(last_goal_, m_.frontend->currentPose(m_.graph));
  else have_goal_ = false;
}

void RunState::waitWhilePaused() {
  while (!(stop_ && stop_->load()) && takeRequests()) {
    if (!operator_paused_ && !(pause_ && pause_->load()) && home_request_.empty() &&
        !homeSignalPending())
      return;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

bool RunState::goHome(const std::string& why, bool finishes, const mrpt::poses::CPose2D& robot) {
  if (m_.graph.empty()) return false;
  Goal g;
  g.x = m_.graph.nodes.front().pose.x();
  g.y = m_.graph.nodes.front().pose.y();
  home_reason_ = why;
  home_finishes_ = finishes;
  returning_home_ = true;
  home_from_distance_ = sum_.distance_m;
  m_.logStr(mrpt::system::LVL_INFO, why + ": returning to the start (" + formatSignificant(g.x, 4) +
                                        ", " + formatSignificant(g.y, 4) + ")");
  last_goal_ = g;
  have_goal_ = true;
  const NavStatus st = navigateTo(g, robot);
  if (st == NavStatus::Unreachable || st == NavStatus::Blocked) return arrivedHome(st);
  return true;
}

bool RunState::arrivedHome(NavStatus st) {
  const double d = sum_.distance_m - home_from_distance_;
  sum_.finished = home_finishes_;
  sum_.stop_reason = home_reason_ +
                     (st == NavStatus::Reached ? "; back at the start ("
                                               : std::string("; did not get back to the start (") +
                                                     navStatusName(st) + ", ") +
                     formatSignificant(d, 4) + " m driven to it)";
  return false;
}

}  // namespace asf::framework::run
