// policy_dopt_frontier: frontier exploration where each frontier is scored by the
// D-optimality of the pose graph expected after driving to it (Placed and Castellanos, RA-L
// 2023: edge weights det(Omega)^(1/3), weighted spanning trees), the best one taken. Frontiers,
// goals and blacklisting are the frontier explorer's (libs/exploration); the expected
// graph is expected_pose_graph.h.
#include <asf/exploration/expected_pose_graph.h>
#include <asf/exploration/frontier_search.h>

#include <cmath>
#include <cstdint>
#include <iomanip>
#include <sstream>

namespace {

class DOptFrontierPolicy final : public asf::Policy {
 public:
  void configure(const asf::Params& p, const asf::PluginContext&) override {
    search_.configure(p, *this);
    expected_.node_spacing = p.getDouble("node_spacing");
    expected_.loop_radius = p.getDouble("loop_radius");
    expected_.loop_skip_recent = static_cast<int>(p.getInt("loop_skip_recent"));
    info_radius_ = p.getDouble("info_radius");
    placed_model_ = p.getString("edge_model") == "placed";
  }

  asf::Decision decide(const asf::ExplorationState& s) override {
    return search_.decide(
        s, [&](const std::vector<asf::exploration::FrontierCandidate>& candidates,
               const asf::mapping::Reachability& reach, const std::vector<std::uint8_t>& cells) {
          return choose(s, candidates, reach, cells);
        });
  }

 private:
  static std::string where(const asf::exploration::FrontierCandidate& c) {
    std::ostringstream os;
    os << std::fixed << std::setprecision(2) << c.length << " m long, " << c.distance
       << " m away (frontier cell " << c.target.x << ", " << c.target.y << ")";
    return os.str();
  }

  /// The candidate whose expected graph has the largest ||L_w||_0; ties (and a graph without
  /// edges, before the first keyframes) go to the nearest.
  asf::exploration::FrontierChoice choose(const asf::ExplorationState& s,
                             const std::vector<asf::exploration::FrontierCandidate>& candidates,
                             const asf::mapping::Reachability& reach,
                             const std::vector<std::uint8_t>& cells) const {
    const bool has_edges = s.graph && s.graph->size() >= 2 && !s.graph->edges.empty();
    if (!has_edges || candidates.size() == 1) {
      const std::string why = has_edges ? "the only frontier: "
                                        : "no pose graph yet, nearest of " +
                                              std::to_string(candidates.size()) + " frontiers: ";
      return {0, why + where(candidates.front())};
    }
    const asf::exploration::ExpectedPoseGraph graph(*s.graph, expected_);
    const asf::exploration::AreaFn area = placed_model_ ? areaShares(reach, cells) : asf::exploration::AreaFn{};
    std::size_t best = 0;
    std::vector<asf::exploration::Expectation> expected(candidates.size());
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      expected[i] = graph.afterPath(reach.pathTo(candidates[i].goal), area);
      if (expected[i].d_optimality > expected[best].d_optimality) best = i;
    }
    std::ostringstream why;
    why << "D-optimal of " << candidates.size() << " frontiers: " << std::setprecision(6)
        << expected[best].d_optimality << " (nearest " << expected[0].d_optimality << ", now "
        << graph.present() << "), " << expected[best].nodes << " nodes and " << expected[best].loops
        << " loops expected, " << where(candidates[best]);
    return {best, why.str()};
  }

  /// The unknown and occupied shares of the cells (the search's classification, on the grid
  /// of `reach`) whose centres lie within info_radius of a point; cells off the grid count as
  /// unknown: nothing is known there. Valid while `cells` is.
  asf::exploration::AreaFn areaShares(const asf::mapping::Reachability& reach,
                         const std::vector<std::uint8_t>& cells) const {
    const int W = reach.width(), H = reach.height();
    const double res = reach.resolution(), r = info_radius_;
    const asf::Point2 c0 = reach.cellCenter(0, 0);
    const std::vector<std::uint8_t>* state = &cells;
    return [state, W, H, res, c0, r](const asf::Point2& p) {
      const int cx = static_cast<int>(std::floor((p.x - c0.x) / res + 0.5));
      const int cy = static_cast<int>(std::floor((p.y - c0.y) / res + 0.5));
      const int span = static_cast<int>(std::ceil(r / res));
      int all = 0, unknown = 0, occupied = 0;
      for (int y = cy - span; y <= cy + span; ++y)
        for (int x = cx - span; x <= cx + span; ++x) {
          const double dx = c0.x + x * res - p.x, dy = c0.y + y * res - p.y;
          if (dx * dx + dy * dy > r * r) continue;
          ++all;
          const std::uint8_t c = (x < 0 || y < 0 || x >= W || y >= H)
                                     ? std::uint8_t{asf::kCellUnknown}
                                     : (*state)[static_cast<std::size_t>(y) * W + x];
          unknown += c == asf::kCellUnknown;
          occupied += c == asf::kCellOccupied;
        }
      return all == 0 ? asf::exploration::AreaShares{}
                      : asf::exploration::AreaShares{double(unknown) / all, double(occupied) / all};
    };
  }

  asf::exploration::FrontierSearch search_;
  asf::exploration::ExpectedGraphOptions expected_;
  double info_radius_ = 1;
  bool placed_model_ = true;
};

const asf::KeySpec kKeys[] = {
    asf::mapping::keyRobotRadius("0.2"),
    asf::mapping::keyOccupiedThreshold(),
    asf::mapping::keyUnknownBand(),
    asf::exploration::keyMinFrontierSize(),
    asf::exploration::keyFrontierGoalTolerance(),
    asf::exploration::keySnapRadius(),
    asf::exploration::keyBlacklistRadius(),
    asf::exploration::keyMaxFailuresPerFrontier(),
    asf::keyDouble("node_spacing", "0.5",
                   "The expected graph gets a node every this many metres of the path to a "
                   "frontier (the front-end's keyframe_distance) [m]",
                   0.01, 100),
    asf::keyDouble("loop_radius", "2",
                   "An expected node closes a loop with the nearest old node within this "
                   "distance [m]",
                   0, 100),
    asf::keyEnum("edge_model", "placed", "placed|median",
                 "Weights of the expected edges: the medians of the graph's own edges, scaled "
                 "as the authors' controller does by the unknown (odometry) and occupied "
                 "(loops, with their age) shares of the map within info_radius (placed), or "
                 "the medians alone (median)"),
    asf::keyDouble("info_radius", "1",
                   "Radius of the map's shares around an expected node (the authors' "
                   "info_radius) [m]",
                   0.05, 100),
    asf::keyInt("loop_skip_recent", "20",
                "Expected loops exclude the last this many nodes before the new one (the "
                "front-end's loop_skip_recent)",
                0, 100000),
};

}  // namespace

ASF_PLUGIN(DOptFrontierPolicy, asf::PluginKind::Policy, "dopt_frontier", "1.0.0",
           "Frontier exploration by the D-optimality of the expected pose graph (Placed and "
           "Castellanos 2023: weighted Laplacian, det(Omega)^(1/3) edge weights)",
           asf::ThreadSafety::ThreadCompatible, kKeys)
