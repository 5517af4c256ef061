// policy_tigre: TIGRE (thesis ch. 6), Tarry's maze search on the on-line topological graph.
//
// At the region the robot is in: leave by an edge not yet traversed outward from it, the
// entrance edge only as a last resort; among the allowed edges prefer those to visited
// regions (loop closing) over the others, then the nearest. Stop when no edge of the graph
// is left untraversed (Fraenkel-style count), frontier edges included.
#include <asf/graph/routes.h>
#include <asf/policy.h>
#include <asf/mapping/reachability.h>
#include <asf/text.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

using asf::Point2;
using asf::RegionId;
using EdgeKey = std::pair<RegionId, RegionId>;  // (lower, higher) or (region, kUnexplored)

EdgeKey keyOf(const asf::TopoEdge& e) {
  if (e.frontier()) return {e.a, asf::kUnexplored};
  return e.a < e.b ? EdgeKey{e.a, e.b} : EdgeKey{e.b, e.a};
}

double dist(const Point2& a, const Point2& b) { return std::hypot(a.x - b.x, a.y - b.y); }

std::string edgeName(const EdgeKey& k) {
  return k.second == asf::kUnexplored
             ? "frontier of region " + std::to_string(k.first)
             : "edge " + std::to_string(k.first) + "-" + std::to_string(k.second);
}

class TigrePolicy final : public asf::Policy {
 public:
  void configure(const asf::Params& p, const asf::PluginContext& ctx) override {
    reach_opt_ = asf::mapping::reachabilityOptionsFrom(p);
    tolerance_ = p.getDouble("goal_tolerance");
    region_tolerance_ = p.getDouble("region_tolerance");
    snap_ = p.getDouble("snap_radius");
    blacklist_radius_ = p.getDouble("blacklist_radius");
    max_edge_failures_ = static_cast<int>(p.getInt("max_edge_failures"));
    const std::string next_goal = p.getString("next_goal");
    next_goal_ = next_goal == "centre"       ? NextGoal::Centre
                 : next_goal == "centre_new" ? NextGoal::CentreNew
                 : next_goal == "entry"      ? NextGoal::Entry
                                             : NextGoal::None;
    entry_depth_ = p.getDouble("entry_depth");
    options_ = asf::graph::TarryOptions::modified();
    options_.loop_closing_first = p.getBool("loop_closing_first");
    options_.nearest_first = p.getString("ties") == "nearest";
    relocate_ = p.getBool("relocate");
    max_waits_ = static_cast<int>(p.getInt("max_waits"));
    rng_.seed(static_cast<std::mt19937::result_type>(ctx.seed));
    failures_.clear();
    chosen_.clear();
    tries_.clear();
    frontier_blacklist_.clear();
    pending_.reset();
    last_.reset();
    waits_ = 0;
    failure_streak_ = 0;
  }

  asf::Decision decide(const asf::ExplorationState& s) override {
    learnFromLastGoal(s);
    const asf::TopoGraph& topo = *s.topo;
    const Point2 robot{s.robot.x(), s.robot.y()};
    if (!s.map || !s.map->grid || topo.nodes.size() <= 1) return wait(robot, "no regions yet");
    const asf::mapping::Reachability reach =
        asf::mapping::Reachability::compute(*s.map, robot, reach_opt_);

    if (auto d = enterPendingRegion(s, reach)) return *d;
    const RegionId here = topo.current;
    // Not inside any region (the start, or the region vanished): the nearest one.
    if (here <= 0 || !topo.node(here)) return toNearestRegion(s, reach, robot);
    waits_ = 0;

    EdgeCounts n;
    const std::vector<Option> options = edgeOptions(topo, reach, n);
    if (n.untraversed == 0) {
      std::ostringstream why;
      why << "every edge traversed";
      if (n.given_up) why << " except " << n.given_up << " given up after failures";
      why << " (" << topo.edges.size() << " edges)";
      // Said, not hidden: frontiers the map still has where no untried goal is reachable.
      if (n.frontiers_left)
        why << "; " << n.frontiers_left << " frontier" << (n.frontiers_left > 1 ? "s" : "")
            << " left, tried or out of reach";
      return asf::Decision::done(why.str());
    }
    if (auto d = tarryStep(topo, options, here)) return *d;
    if (!relocate_)  // the thesis' Algorithm 4: no valid edge here ends the exploration
      return asf::Decision::done("region " + std::to_string(here) +
                                 ": no edge left by Tarry's rule; " +
                                 std::to_string(n.untraversed) +
                                 " untraversed elsewhere (relocate = false)");
    return relocate(topo, options, n.untraversed, here);
  }

 private:
  struct Option {
    int index = -1;
    EdgeKey key;
    Point2 goal;
    double cost = asf::mapping::Reachability::kUnreachable;
    bool untraversed = false;
  };
  struct Attempt {
    EdgeKey key;
    bool frontier = false;
    Point2 goal;
  };
  struct Pending {
    EdgeKey key;
    RegionId region = 0;       ///< to enter
    Point2 border;             ///< the goal on the border, reached first
    bool was_visited = false;  ///< `region` had been visited when the edge was chosen
  };
  enum class NextGoal { Centre, CentreNew, Entry, None };
  struct EdgeCounts {
    int untraversed = 0;     ///< edges with a goal, frontiers included
    int given_up = 0;        ///< after max_edge_failures
    int frontiers_left = 0;  ///< frontiers without a reachable goal away from those tried
  };

  /// Phase 2 of an edge crossing: into the next region, unless already there.
  std::optional<asf::Decision> enterPendingRegion(const asf::ExplorationState& s,
                                                  const asf::mapping::Reachability& reach) {
    const asf::TopoGraph& topo = *s.topo;
    if (pending_ && s.last_status == asf::NavStatus::Reached && topo.current != pending_->region) {
      const Pending p = *pending_;
      pending_.reset();
      std::optional<Point2> anchor;
      // centre_new: a region seen before needs no second look from its centre.
      if (next_goal_ == NextGoal::Entry || (next_goal_ == NextGoal::CentreNew && p.was_visited)) {
        // A little beyond the border, towards the region's centre: enough to be inside.
        if (const asf::TopoNode* n = topo.node(p.region)) {
          const double d = dist(p.border, n->centroid);
          const double f = d > entry_depth_ ? entry_depth_ / d : 1.0;
          anchor = Point2{p.border.x + f * (n->centroid.x - p.border.x),
                          p.border.y + f * (n->centroid.y - p.border.y)};
        }
      }
      if (const auto g = regionGoal(s, reach, p.region, anchor)) {
        last_ = Attempt{p.key, false, *g};
        // A tight tolerance: the robot must stand in the region, not near it.
        return asf::Decision::goTo({g->x, g->y, region_tolerance_},
                                   "into region " + std::to_string(p.region) +
                                       (anchor ? " (entry)" : " (centre)") + " across " +
                                       edgeName(p.key));
      }
    }
    pending_.reset();
    return std::nullopt;
  }

  /// The robot is in no region: to the nearest reachable one.
  asf::Decision toNearestRegion(const asf::ExplorationState& s,
                                const asf::mapping::Reachability& reach, const Point2& robot) {
    double best = asf::mapping::Reachability::kUnreachable;
    std::optional<Point2> goal;
    RegionId target = 0;
    for (const auto& n : s.topo->nodes) {
      if (n.region == asf::kUnexplored) continue;
      const auto g = regionGoal(s, reach, n.region);
      if (g && reach.distanceTo(*g) < best) {
        best = reach.distanceTo(*g);
        goal = g;
        target = n.region;
      }
    }
    if (!goal) return wait(robot, "outside every region and none reachable");
    last_ = Attempt{{target, target}, false, *goal};
    return go(*goal, "not inside a region: to region " + std::to_string(target) + " (" +
                         asf::formatFixed(best, 2) + " m)");
  }

  /// Every edge of the graph not given up: where its goal is and whether it is still
  /// untraversed (counted in `n`, with the given-up edges and the frontiers without a goal).
  std::vector<Option> edgeOptions(const asf::TopoGraph& topo,
                                  const asf::mapping::Reachability& reach, EdgeCounts& n) {
    std::vector<Option> options;
    for (std::size_t i = 0; i < topo.edges.size(); ++i) {
      const asf::TopoEdge& e = topo.edges[i];
      const EdgeKey k = keyOf(e);
      // A region edge chosen again and again but never registered as traversed (the robot
      // crosses elsewhere, the border is thin) is given up like a failing one.
      if (failures_[k] >= failureBudget(e) ||
          (!e.frontier() && e.traversals.empty() && chosen_[k] >= max_edge_failures_ + 1)) {
        ++n.given_up;
        continue;
      }
      Option o;
      o.index = static_cast<int>(i);
      o.key = k;
      if (e.frontier()) {
        if (!frontierGoal(e, reach, o)) {
          ++n.frontiers_left;
          continue;
        }
      } else {
        regionEdgeGoal(e, reach, o);
      }
      if (o.untraversed) ++n.untraversed;
      options.push_back(o);
    }
    return options;
  }

  /// The nearest reachable cell of a frontier, away from the frontier goals tried; false if
  /// there is none.
  bool frontierGoal(const asf::TopoEdge& e, const asf::mapping::Reachability& reach,
                    Option& o) const {
    std::vector<Point2> cells;
    for (const Point2& c : e.border)
      if (!blacklisted(c)) cells.push_back(c);
    double d = 0;
    Point2 g;
    if (cells.empty() || reach.closest(cells, snap_, &g, &d) < 0) return false;
    o.goal = g;
    o.cost = d;
    o.untraversed = true;
    return true;
  }

  /// A reachable cell at the border's midpoint, else on the border; unreachable cost if none.
  void regionEdgeGoal(const asf::TopoEdge& e, const asf::mapping::Reachability& reach,
                      Option& o) const {
    o.untraversed = e.traversals.empty();
    const double half = 0.5 * e.width + snap_;
    std::optional<Point2> g = reach.nearestReachable(e.midpoint, half);
    if (!g) {
      Point2 gc;
      if (reach.closest(e.border, snap_, &gc) < 0) {
        o.cost = asf::mapping::Reachability::kUnreachable;
      } else {
        g = gc;
      }
    }
    if (g) {
      o.goal = *g;
      o.cost = reach.distanceTo(*g);
    }
  }

  /// Tarry's rule at the current region; nothing when no edge of it is left.
  std::optional<asf::Decision> tarryStep(const asf::TopoGraph& topo,
                                         const std::vector<Option>& options, RegionId here) {
    const asf::TopoNode* node = topo.node(here);
    std::vector<asf::graph::TarryCandidate> cands;
    for (std::size_t j = 0; j < options.size(); ++j) {
      const Option& o = options[j];
      const asf::TopoEdge& e = topo.edges[o.index];
      if (e.a != here && e.b != here) continue;
      if (!std::isfinite(o.cost)) continue;  // no reachable goal for it now
      asf::graph::TarryCandidate c;
      c.edge = static_cast<int>(j);
      c.traversed_outward = !e.frontier() && topo.outwardTraversals(o.index, here) > 0;
      if (!e.frontier() && stuck(o.key, here, topo.outwardTraversals(o.index, here)))
        c.traversed_outward = true;  // chosen again and again without ever crossing
      c.entrance = node->entrance_edge == o.index;
      if (!e.frontier()) {
        const asf::TopoNode* other = topo.node(e.a == here ? e.b : e.a);
        c.leads_to_visited = other && other->visited;
      }
      c.cost = o.cost;
      cands.push_back(c);
    }
    const int pick = asf::graph::tarryChoose(cands, options_, rng_);
    if (pick < 0) return std::nullopt;
    const Option& o = options[pick];
    const asf::TopoEdge& e = topo.edges[o.index];
    const bool entrance = node->entrance_edge == o.index;
    std::string why = "region " + std::to_string(here) + ": " + edgeName(o.key);
    if (e.frontier()) {
      why += " (" + asf::formatFixed(o.cost, 2) + " m)";
      last_ = Attempt{o.key, true, o.goal};
      return go(o.goal, why);
    }
    const RegionId next = e.a == here ? e.b : e.a;
    const asf::TopoNode* other = topo.node(next);
    why += entrance                    ? " (entrance edge, last resort"
           : (other && other->visited) ? " (link to visited region"
                                       : " (to unvisited region";
    why += ", " + asf::formatFixed(o.cost, 2) + " m)";
    last_ = Attempt{o.key, false, o.goal};
    ++chosen_[o.key];
    noteTry(o.key, here, topo.outwardTraversals(o.index, here));
    if (next_goal_ != NextGoal::None)
      pending_ = Pending{o.key, next, o.goal, other && other->visited};
    return go(o.goal, why + ": border");
  }

  /// Nothing left here, but edges elsewhere are untraversed (the graph changed under the
  /// walk): to the nearest of them.
  asf::Decision relocate(const asf::TopoGraph& topo, const std::vector<Option>& options,
                         int untraversed, RegionId here) {
    const Option* best = nullptr;
    for (const Option& o : options)
      if (o.untraversed && std::isfinite(o.cost) && (!best || o.cost < best->cost)) best = &o;
    if (!best) {
      std::ostringstream why;
      why << untraversed << " untraversed edges left, none reachable";
      return asf::Decision::done(why.str());
    }
    last_ = Attempt{best->key, topo.edges[best->index].frontier(), best->goal};
    const asf::TopoEdge& e = topo.edges[best->index];
    if (!e.frontier()) ++chosen_[best->key];
    if (!e.frontier() && next_goal_ != NextGoal::None) {
      // Cross it away from the side the robot comes from.
      const RegionId far = e.a == topo.current ? e.b : e.a;
      const asf::TopoNode* n = topo.node(far);
      pending_ = Pending{best->key, far, best->goal, n && n->visited};
    }
    return go(best->goal, "region " + std::to_string(here) + " done; relocating to " +
                              edgeName(best->key) + " (" + asf::formatFixed(best->cost, 2) + " m)");
  }

  asf::Decision go(const Point2& g, const std::string& why) {
    return asf::Decision::goTo({g.x, g.y, tolerance_}, why);
  }

  /// Stand still one step (the goal is the robot's position) while the map and graph grow.
  asf::Decision wait(const Point2& robot, const std::string& why) {
    if (++waits_ > max_waits_)
      return asf::Decision::done(why + " after " + std::to_string(max_waits_) + " waits");
    last_.reset();
    return go(robot, "waiting: " + why);
  }

  /// What the outcome of the previous goal teaches: failures count against its edge, and
  /// a frontier the robot reached or could not reach is not chosen again there.
  void learnFromLastGoal(const asf::ExplorationState& s) {
    if (!last_) return;
    const Attempt a = *last_;
    const bool failed =
        s.last_status == asf::NavStatus::Unreachable || s.last_status == asf::NavStatus::Blocked;
    // Goals failing one after the other, whatever the edge, say the robot is stuck rather
    // than the edges unreachable: beyond the third such failure, edges are not blamed (the
    // host stops a run whose goals keep failing, [pipeline] max_failed_goals).
    failure_streak_ = failed ? failure_streak_ + 1 : 0;
    if (failed && failure_streak_ <= 3) ++failures_[a.key];
    if (failed) {
      pending_.reset();
      MRPT_LOG_WARN_STREAM(edgeName(a.key) << ": goal (" << asf::formatFixed(a.goal.x, 2) << ", "
                                           << asf::formatFixed(a.goal.y, 2) << ") "
                                           << asf::navStatusName(s.last_status) << " ("
                                           << failures_[a.key] << " failures)");
    }
    if (a.frontier && (failed || s.last_status == asf::NavStatus::Reached))
      frontier_blacklist_.push_back(a.goal);
    if (!pending_) last_.reset();
  }

  /// Attempts to leave `from` by an edge, against its outward traversals when the first of
  /// them was made: a choice repeated without a new traversal does not lead anywhere.
  void noteTry(const EdgeKey& k, RegionId from, int outward) {
    Tries& t = tries_[{k, from}];
    if (t.count == 0 || t.outward != outward) t = {0, outward};
    ++t.count;
  }
  bool stuck(const EdgeKey& k, RegionId from, int outward) const {
    auto it = tries_.find({k, from});
    return it != tries_.end() && it->second.outward == outward &&
           it->second.count > max_edge_failures_;
  }

  /// Failures an edge may have before it is given up: max_edge_failures; for a frontier,
  /// that many per blacklist disc across its width (each failed goal rules out one disc of
  /// it, so a long frontier is not given up for two bad spots).
  int failureBudget(const asf::TopoEdge& e) const {
    if (!e.frontier() || blacklist_radius_ <= 0) return max_edge_failures_;
    const double discs = std::floor(e.width / (2 * blacklist_radius_));
    return max_edge_failures_ * static_cast<int>(std::clamp(discs, 1.0, 1000.0));
  }

  bool blacklisted(const Point2& p) const {
    for (const Point2& b : frontier_blacklist_)
      if (dist(p, b) < blacklist_radius_) return true;
    return false;
  }

  /// A reachable cell of region r near `anchor` (default: its centroid, which may lie outside
  /// a non-convex region or too close to a wall).
  std::optional<Point2> regionGoal(const asf::ExplorationState& s,
                                   const asf::mapping::Reachability& reach, RegionId r,
                                   std::optional<Point2> anchor = std::nullopt) const {
    const asf::TopoNode* n = s.topo->node(r);
    if (!n) return std::nullopt;
    const Point2 target = anchor ? *anchor : n->centroid;
    if (s.segmentation && s.segmentation->labels.atPoint(target.x, target.y) == r &&
        reach.reachable(target))
      return target;
    if (!s.segmentation) return reach.nearestReachable(target, 1.0);
    const asf::LabelImage& L = s.segmentation->labels;
    double best = std::numeric_limits<double>::infinity();
    std::optional<Point2> goal;
    for (int cy = 0; cy < L.height; ++cy)
      for (int cx = 0; cx < L.width; ++cx) {
        if (L.at(cx, cy) != r) continue;
        const Point2 c{L.origin_x + (cx + 0.5) * L.resolution,
                       L.origin_y + (cy + 0.5) * L.resolution};
        const double d = dist(c, target);
        if (d < best && reach.reachable(c)) {
          best = d;
          goal = c;
        }
      }
    return goal;
  }

  asf::mapping::ReachabilityOptions reach_opt_;
  asf::graph::TarryOptions options_;
  double tolerance_ = 0.3, region_tolerance_ = 0.1, snap_ = 0.5, blacklist_radius_ = 0.5;
  int max_edge_failures_ = 2, max_waits_ = 20, waits_ = 0, failure_streak_ = 0;
  NextGoal next_goal_ = NextGoal::CentreNew;
  bool relocate_ = true;
  double entry_depth_ = 0.6;
  std::mt19937 rng_;
  std::map<EdgeKey, int> failures_, chosen_;
  struct Tries {
    int count = 0, outward = 0;
  };
  std::map<std::pair<EdgeKey, RegionId>, Tries> tries_;
  std::vector<Point2> frontier_blacklist_;
  std::optional<Pending> pending_;
  std::optional<Attempt> last_;
};

const asf::KeySpec kKeys[] = {
    asf::mapping::keyRobotRadius("0.25"),
    asf::mapping::keyOccupiedThreshold(),
    asf::mapping::keyUnknownBand(),
    asf::keyDouble("goal_tolerance", "0.3", "A goal is reached within this distance [m]", 0.01,
                   5.0),
    asf::keyDouble("region_tolerance", "0.1",
                   "Tolerance of the goal inside the next region (small: the robot must enter "
                   "it) [m]",
                   0.01, 5.0),
    asf::keyDouble("snap_radius", "0.5",
                   "A border or frontier cell may be replaced by a reachable cell this close [m]",
                   0.0, 5.0),
    asf::keyDouble("blacklist_radius", "0.5",
                   "Frontier cells this close to a frontier goal already tried are not chosen "
                   "again [m]",
                   0.0, 10.0),
    asf::keyInt("max_edge_failures", "2",
                "An edge whose goals failed (unreachable/blocked) this often is given up; a "
                "frontier this often per 2 x blacklist_radius of its width",
                1, 100),
    asf::keyEnum("next_goal", "centre_new", "centre|centre_new|entry|none",
                 "After the border of a region edge: on to the next region's centre (thesis), "
                 "to the centre only of a region not visited before (else entry), just inside "
                 "it (entry_depth beyond the border), or no second goal"),
    asf::keyDouble("entry_depth", "0.6",
                   "next_goal = entry: how far beyond the border, towards the centre [m]", 0.0,
                   10.0),
    asf::keyBool("loop_closing_first", "true",
                 "Prefer edges to visited regions (loop closing) over the others (thesis' "
                 "tie-break; false: plain Tarry with nearest-first)"),
    asf::keyEnum("ties", "nearest", "nearest|random",
                 "Among the edges Tarry's rule and loop closing leave equal: the nearest, or "
                 "one drawn from the seed (thesis sec. 6.2.2: Tarry's random choice)"),
    asf::keyBool("relocate", "true",
                 "When Tarry's rule leaves no edge of the current region but edges elsewhere "
                 "are untraversed (the graph changed under the walk), drive to the nearest of "
                 "them; false: the exploration ends there, as the thesis' Algorithm 4 does"),
    asf::keyInt("max_waits", "20", "Steps to wait for a map with regions before giving up", 1,
                100000),
};

}  // namespace

ASF_PLUGIN(TigrePolicy, asf::PluginKind::Policy, "tigre", "1.0.0",
           "TIGRE: Tarry's maze search on the topological graph, entrance edge last, loop "
           "closing first, stop when every edge is traversed",
           asf::ThreadSafety::ThreadCompatible, kKeys)
