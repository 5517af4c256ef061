#pragma once
// Path planning for a driving robot on the *estimated* occupancy grid (the simulator's own
// navigation, and asf's when it drives a robot with velocity commands): A* over an
// 8-connected grid, obstacles inflated by the robot radius, unknown space blocked or costly.
// Cells are classified by asf::cellStateOf (grid_map.h), the definition the policies'
// reachability uses too. What differs on purpose: this planner samples the map onto its own
// grid around start and goal, lets unknown cells be crossed at a cost (a robot drives into
// what its scans have not covered yet), and lets a robot closer than its radius to an
// obstacle leave only through cells no closer to obstacles than where it stands.
#include <asf/geometry.h>

#include <string>
#include <vector>

namespace mrpt::maps {
class COccupancyGridMap2D;
}
namespace mrpt::obs {
class CObservation2DRangeScan;
}
namespace mrpt::poses {
class CPose2D;
}

namespace asf::navigation {

struct NavOptions {
  double robot_radius = 0.2;      ///< cells closer than this to an obstacle are lethal [m]
  double inflation_margin = 0.1;  ///< beyond the radius, cost rises towards obstacles [m]
  double occupied_threshold = 0.65;  ///< p(occupied) above this is an obstacle
  double unknown_band = 0.02;     ///< |p - 0.5| below this is unknown
  bool unknown_blocked = false;   ///< unknown cells are obstacles (else costly)
  double unknown_cost = 4.0;      ///< cost factor of a step through unknown space
  double default_resolution = 0.05;  ///< grid cell size when there is no map [m]
  double border = 1.0;            ///< free room added around start and goal [m]
};

struct NavPlan {
  bool found = false;
  std::vector<Point2> waypoints;  ///< start excluded, goal (or the cell reached) last
  double length = 0;              ///< metres along the waypoints
  std::string reason;             ///< why not found
  std::size_t expanded = 0;       ///< A* nodes expanded
};

/// Plans from `start` to any free cell within `tolerance` of `goal`. `map` may be null (no
/// map yet: everything unknown). A robot closer than its radius to an obstacle may still
/// leave: cells within the radius of the start that are no closer to obstacles than the
/// start are passable.
/// `obstacles` (map frame) are marked occupied on top of the map: the latest scan's
/// endpoints, which are right relative to the robot even where the map has drifted.
NavPlan planPath(const mrpt::maps::COccupancyGridMap2D* map, const Point2& start,
                 const Point2& goal, double tolerance, const NavOptions& options,
                 const std::vector<Point2>& obstacles = {});

/// The valid rays' endpoints of `scan` taken by a robot at `robot` (map frame): the obstacles
/// around it as it senses them now, right relative to it even where the estimated map has
/// drifted (a local obstacle layer, as navigation stacks have), for planPath's `obstacles`.
std::vector<Point2> scanEndpoints(const mrpt::obs::CObservation2DRangeScan& scan,
                                  const mrpt::poses::CPose2D& robot);

}  // namespace asf::navigation
