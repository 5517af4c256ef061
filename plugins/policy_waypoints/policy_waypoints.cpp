// policy_waypoints: a scripted route, not an explorer. Sends the robot to fixed waypoints in
// order, skipping those it cannot reach; optionally loops.
#include <asf/policy.h>
#include <asf/text.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace {

class WaypointsPolicy final : public asf::Policy {
 public:
  void configure(const asf::Params& p, const asf::PluginContext&) override {
    tolerance_ = p.getDouble("tolerance");
    loop_ = p.getBool("loop");
    wp_.clear();
    const std::string text = p.getString("waypoints");
    std::size_t start = 0;
    int item = 0;
    while (start <= text.size()) {
      std::size_t end = text.find(';', start);
      if (end == std::string::npos) end = text.size();
      const std::string s = asf::trim(text.substr(start, end - start));
      start = end + 1;
      ++item;
      if (s.empty()) continue;
      std::string spaced = s;
      for (char& c : spaced)
        if (c == ',') c = ' ';
      std::istringstream in(spaced);
      std::vector<double> v;
      std::string tok;
      while (in >> tok) {
        char* e = nullptr;
        errno = 0;
        const double d = std::strtod(tok.c_str(), &e);
        if (e != tok.c_str() + tok.size() || errno != 0 || !std::isfinite(d))
          p.fail("waypoints", "waypoint " + std::to_string(item) + " '" + s + "': '" + tok +
                                  "' is not a finite number");
        v.push_back(d);
      }
      if (v.size() != 2)
        p.fail("waypoints", "waypoint " + std::to_string(item) + " '" + s +
                                "': expected two numbers 'x y', got " + std::to_string(v.size()));
      wp_.push_back({v[0], v[1], tolerance_});
    }
    if (wp_.empty()) MRPT_LOG_WARN_STREAM("no waypoints given: the policy is done at once");
    next_ = 0;
    pending_ = finished_ = false;
    visited_ = skipped_ = round_reached_ = 0;
  }

  asf::Decision decide(const asf::ExplorationState& s) override {
    if (wp_.empty()) return asf::Decision::done("no waypoints");
    if (finished_) return done_;
    if (pending_) {
      switch (s.last_status) {
        case asf::NavStatus::Reached:
          ++visited_;
          ++round_reached_;
          advance();
          break;
        case asf::NavStatus::Unreachable:
        case asf::NavStatus::Blocked:
          MRPT_LOG_WARN_STREAM("skipping waypoint " << next_ + 1 << " (" << wp_[next_].x << ", "
                                                    << wp_[next_].y
                                                    << "): " << asf::navStatusName(s.last_status));
          ++skipped_;
          advance();
          break;
        case asf::NavStatus::Idle:
        case asf::NavStatus::Moving:
          break;  // no outcome yet: ask for the same waypoint again
      }
      if (finished_) return done_;
    }
    pending_ = true;
    const asf::Goal& g = wp_[next_];
    std::ostringstream why;
    why << "waypoint " << next_ + 1 << " of " << wp_.size() << " (" << g.x << ", " << g.y << ")";
    return asf::Decision::goTo(g, why.str());
  }

 private:
  void advance() {
    pending_ = false;
    if (++next_ < wp_.size()) return;
    next_ = 0;
    if (loop_ && round_reached_ > 0) {
      round_reached_ = 0;
      return;
    }
    finished_ = true;
    std::ostringstream why;
    if (loop_)
      why << "loop stopped: no waypoint reached in a full round (" << wp_.size()
          << " skipped in a row)";
    else
      why << "visited " << visited_ << " of " << wp_.size() << " waypoints (" << skipped_
          << " skipped)";
    done_ = asf::Decision::done(why.str());
  }

  std::vector<asf::Goal> wp_;
  double tolerance_ = 0.3;
  bool loop_ = false;
  std::size_t next_ = 0;
  bool pending_ = false, finished_ = false;
  int visited_ = 0, skipped_ = 0, round_reached_ = 0;
  asf::Decision done_;
};

const asf::KeySpec kKeys[] = {
    asf::keyString("waypoints", "",
                   "Route 'x y; x y; ...' in the map frame [m]; empty: done at once"),
    asf::keyDouble("tolerance", "0.3", "A waypoint is reached within this distance [m]", 0.01, 100),
    asf::keyBool("loop", "false", "Start over after the last waypoint"),
};

}  // namespace

ASF_PLUGIN(WaypointsPolicy, asf::PluginKind::Policy, "waypoints", "1.0.0",
           "Scripted route: fixed waypoints in order, unreachable ones skipped (not an explorer)",
           asf::ThreadSafety::ThreadCompatible, kKeys)
