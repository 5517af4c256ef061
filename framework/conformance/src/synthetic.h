#pragma once
/// \file synthetic.h
/// Synthetic inputs of the conformance kit, all generated in code (no files) and fully
/// deterministic: laser frames in a SegmentWorld, noisy pose graphs, occupancy grids,
/// topological graphs.
#include <asf/grid_map.h>
#include <asf/pose_graph.h>
#include <asf/mapping/segment_world.h>
#include <asf/sensor_frame.h>
#include <asf/topo_graph.h>

#include <cstdint>
#include <vector>

namespace asf::conformance::detail {

// ---- frontend -------------------------------------------------------------------------

enum class ScanMode {
  All,          ///< every frame has a scan
  SomeMissing,  ///< frames 0, 4, 8, ... have no scan
  None,         ///< odometry only
};

struct FrameSequence {
  std::vector<SensorFrame> frames;
  /// True robot pose after each frame in the map frame (the first pose is the origin).
  std::vector<mrpt::poses::CPose2D> truth;
};

/// A robot turning in place then driving through the door of SegmentWorld::twoRooms(5,4,1),
/// with exact odometry and exact 360-degree scans (sensor 0.1 m ahead of the robot centre).
FrameSequence makeFrameSequence(ScanMode mode);

/// An exact scan of `world` from robot pose `robot` (world frame).
std::shared_ptr<mrpt::obs::CObservation2DRangeScan> makeScan(const mapping::SegmentWorld& world,
                                                             const mrpt::poses::CPose2D& robot);

// ---- backend / planner ----------------------------------------------------------------

/// A loop of `n` nodes on a circle with noisy odometry edges, a few noisy loop closures and
/// the initial guess from composing the odometry (so chi2 > 0). Node 0 at the origin.
PoseGraph makeNoisyLoop(std::uint32_t seed, int n = 20);

/// A 4 x 5 lattice of nodes 0..19 joined by a serpentine odometry chain and a few cross
/// edges, plus nodes 20-21 joined to each other only (a second component).
PoseGraph makePlannerGraph();
/// Plausible marginals for makePlannerGraph (growing along the chain, cross blocks for the
/// ends of every edge, both orders).
Marginals makePlannerMarginals(const PoseGraph& g);

// ---- segmenter / policy ---------------------------------------------------------------

/// Occupancy values (MRPT stores the probability of being free).
constexpr float kFree = 1.0f, kOccupied = 0.0f, kUnknown = 0.5f;
enum class CellClass { Free, Occupied, Unknown };
CellClass classify(float p);

GridMap wrapGrid(std::shared_ptr<mrpt::maps::COccupancyGridMap2D> grid, std::uint64_t version);
/// 4 m x 3 m, every cell unknown.
GridMap makeUnknownMap();
/// A free rectangle 3.8 m x 2.8 m surrounded by walls two cells thick, unknown outside.
GridMap makeRoomMap();
/// The two rooms of SegmentWorld::twoRooms(5,4,1) rasterized at 0.05 m; when `right_known`
/// is false the right room is unknown (only the left room and the door are mapped).
GridMap makeTwoRoomsMap(bool right_known = true);

/// Topological graphs for policies.
TopoGraph makeTopoUnexploredOnly();
/// Two visited rooms joined by a door, no frontier.
TopoGraph makeTopoFinished();
/// Visited left room (current), unvisited right room, two frontier edges.
TopoGraph makeTopoWithFrontiers();

}  // namespace asf::conformance::detail
