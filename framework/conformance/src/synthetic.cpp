#include "synthetic.h"

#include <mrpt/core/Clock.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace asf::conformance::detail {

using mrpt::poses::CPose2D;

// ---- frontend -------------------------------------------------------------------------

namespace {
constexpr std::size_t kRays = 360;
constexpr float kMaxRange = 15.0f;
constexpr double kSensorAhead = 0.1;
}  // namespace

std::shared_ptr<mrpt::obs::CObservation2DRangeScan> makeScan(const mapping::SegmentWorld& world,
                                                             const CPose2D& robot) {
  auto scan = std::make_shared<mrpt::obs::CObservation2DRangeScan>();
  scan->sensorLabel = "conformance_laser";
  // N rays one degree apart covering the full turn without a repeated direction.
  scan->aperture = static_cast<float>(2 * M_PI * (kRays - 1) / kRays);
  scan->rightToLeft = true;
  scan->maxRange = kMaxRange;
  scan->stdError = 0.01f;
  scan->sensorPose = mrpt::poses::CPose3D(kSensorAhead, 0, 0.2, 0, 0, 0);
  scan->resizeScan(kRays);
  const CPose2D sensor = robot + CPose2D(kSensorAhead, 0, 0);
  for (std::size_t i = 0; i < kRays; ++i) {
    const double a = sensor.phi() + scan->getScanAngle(i);
    const double r = world.castRay(sensor.x(), sensor.y(), a, kMaxRange);
    const bool valid = r < kMaxRange;
    scan->setScanRange(i, valid ? static_cast<float>(r) : kMaxRange);
    scan->setScanRangeValidity(i, valid);
  }
  return scan;
}

FrameSequence makeFrameSequence(ScanMode mode) {
  const mapping::SegmentWorld world = mapping::SegmentWorld::twoRooms(5, 4, 1);
  std::vector<CPose2D> poses;
  // Turn in place to the left and back (0.1 rad steps)...
  for (int k = 0; k <= 6; ++k) poses.emplace_back(1.0, 2.0, 0.1 * k);
  for (int k = 5; k >= 0; --k) poses.emplace_back(1.0, 2.0, 0.1 * k);
  // ...then drive through the door into the right room, weaving slightly.
  for (int k = 1; k <= 56; ++k)
    poses.emplace_back(1.0 + 0.125 * k, 2.0 + 0.1 * std::sin(0.2 * k), 0.15 * std::sin(0.3 * k));

  FrameSequence seq;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  cov.diagonal() << 0.005 * 0.005, 0.005 * 0.005, std::pow(0.2 * M_PI / 180, 2);
  for (std::size_t k = 0; k < poses.size(); ++k) {
    SensorFrame f;
    f.timestamp = 100.0 + 0.1 * static_cast<double>(k);
    f.odometry = k == 0 ? CPose2D() : poses[k] - poses[k - 1];
    f.odometry_cov = k == 0 ? Eigen::Matrix3d::Zero().eval() : cov;
    f.ground_truth = poses[k];
    const bool with_scan = mode == ScanMode::All || (mode == ScanMode::SomeMissing && k % 4 != 0);
    if (with_scan) {
      auto scan = makeScan(world, poses[k]);
      scan->timestamp = mrpt::Clock::fromDouble(f.timestamp);
      f.scan = scan;
    }
    seq.frames.push_back(std::move(f));
    seq.truth.push_back(poses[k] - poses[0]);
  }
  return seq;
}

// ---- backend / planner ----------------------------------------------------------------

namespace {

/// Standard normal draws from an mt19937 (Box-Muller: the same on every standard library).
class Gauss {
 public:
  explicit Gauss(std::uint32_t seed) : rng_(seed) {}
  double operator()() {
    const double u1 = (static_cast<double>(rng_()) + 0.5) / 4294967296.0;
    const double u2 = (static_cast<double>(rng_()) + 0.5) / 4294967296.0;
    return std::sqrt(-2 * std::log(u1)) * std::cos(2 * M_PI * u2);
  }

 private:
  std::mt19937 rng_;
};

}  // namespace

PoseGraph makeNoisyLoop(std::uint32_t seed, int n) {
  Gauss gauss(seed);
  const double radius = 4, st = 0.05, sr = 0.02;
  std::vector<CPose2D> truth;
  const auto circle = [&](int i) {
    const double t = 2 * M_PI * i / n;
    return CPose2D(radius * std::cos(t), radius * std::sin(t), t + M_PI / 2);
  };
  for (int i = 0; i < n; ++i) truth.push_back(circle(i) - circle(0));

  Eigen::Matrix3d info = Eigen::Matrix3d::Zero();
  info.diagonal() << 1 / (st * st), 1 / (st * st), 1 / (sr * sr);
  const auto measure = [&](int from, int to, EdgeKind kind) {
    const CPose2D m = truth[to] - truth[from];
    PoseEdge e;
    e.from = static_cast<NodeId>(from);
    e.to = static_cast<NodeId>(to);
    const double dx = st * gauss(), dy = st * gauss(), dphi = sr * gauss();
    e.mean = CPose2D(m.x() + dx, m.y() + dy, m.phi() + dphi);
    e.information = info;
    e.kind = kind;
    return e;
  };

  PoseGraph g;
  std::vector<PoseEdge> odo;
  for (int i = 0; i + 1 < n; ++i) odo.push_back(measure(i, i + 1, EdgeKind::Odometry));
  CPose2D p;
  g.addNode(p, 0.0);
  for (int i = 0; i + 1 < n; ++i) {
    p = p + odo[i].mean;
    g.addNode(p, i + 1.0);
  }
  for (const auto& e : odo) g.addEdge(e);
  g.addEdge(measure(n - 1, 0, EdgeKind::LoopClosure));
  g.addEdge(measure(n / 2, 0, EdgeKind::LoopClosure));
  g.addEdge(measure(n / 4, 3 * n / 4, EdgeKind::LoopClosure));
  g.revision = 1;
  return g;
}

PoseGraph makePlannerGraph() {
  PoseGraph g;
  for (int r = 0; r < 5; ++r)
    for (int k = 0; k < 4; ++k) {
      const int c = r % 2 == 0 ? k : 3 - k;
      g.addNode(CPose2D(c, r, r % 2 == 0 ? 0 : M_PI), r * 4.0 + k);
    }
  g.addNode(CPose2D(10, 0, 0), 20);
  g.addNode(CPose2D(11, 0, 0), 21);
  Eigen::Matrix3d info = Eigen::Matrix3d::Zero();
  info.diagonal() << 100, 100, 400;
  const auto link = [&](NodeId a, NodeId b, EdgeKind kind) {
    PoseEdge e;
    e.from = a;
    e.to = b;
    e.mean = g.nodes[b].pose - g.nodes[a].pose;
    e.information = info;
    e.kind = kind;
    g.addEdge(e);
  };
  for (NodeId i = 0; i + 1 < 20; ++i) link(i, i + 1, EdgeKind::Odometry);
  for (auto [a, b] : {std::pair<NodeId, NodeId>{7, 0}, {11, 4}, {15, 8}, {19, 12}, {6, 1},
                      {14, 9}})
    link(a, b, EdgeKind::LoopClosure);
  link(20, 21, EdgeKind::Odometry);
  g.revision = 1;
  return g;
}

Marginals makePlannerMarginals(const PoseGraph& g) {
  Marginals m;
  for (std::size_t i = 0; i < g.size(); ++i) {
    Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
    const double s = i < 20 ? static_cast<double>(i) : 20.0;
    c.diagonal() << 0.01 * s, 0.01 * s, 0.001 * s;
    m.node.push_back(c);
  }
  for (const auto& e : g.edges) {
    const Eigen::Matrix3d c =
        0.5 * m.node[e.from].diagonal().cwiseMin(m.node[e.to].diagonal()).asDiagonal();
    m.cross[{e.from, e.to}] = c;
    m.cross[{e.to, e.from}] = c.transpose();
  }
  m.graph_revision = g.revision;
  return m;
}

// ---- grids ----------------------------------------------------------------------------

CellClass classify(float p) {
  if (p > 0.6f) return CellClass::Free;
  if (p < 0.4f) return CellClass::Occupied;
  return CellClass::Unknown;
}

GridMap wrapGrid(std::shared_ptr<mrpt::maps::COccupancyGridMap2D> grid, std::uint64_t version) {
  GridMap m;
  m.changed.extend(grid->getXMin(), grid->getYMin());
  m.changed.extend(grid->getXMax(), grid->getYMax());
  m.grid = std::move(grid);
  m.version = version;
  m.rebuilt = true;
  return m;
}

namespace {

template <class F>
GridMap rasterize(double x0, double x1, double y0, double y1, F cellValue) {
  auto grid = std::make_shared<mrpt::maps::COccupancyGridMap2D>(
      static_cast<float>(x0), static_cast<float>(x1), static_cast<float>(y0),
      static_cast<float>(y1), 0.05f);
  grid->fill(kUnknown);
  for (int cy = 0; cy < static_cast<int>(grid->getSizeY()); ++cy)
    for (int cx = 0; cx < static_cast<int>(grid->getSizeX()); ++cx)
      grid->setCell(cx, cy, cellValue(grid->idx2x(cx), grid->idx2y(cy)));
  return wrapGrid(grid, 1);
}

double pointSegmentDistance(double px, double py, const mapping::Segment& s) {
  const double ex = s.b.x - s.a.x, ey = s.b.y - s.a.y;
  const double len2 = ex * ex + ey * ey;
  double t = len2 > 0 ? ((px - s.a.x) * ex + (py - s.a.y) * ey) / len2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(px - (s.a.x + t * ex), py - (s.a.y + t * ey));
}

}  // namespace

GridMap makeUnknownMap() {
  return rasterize(0, 4, 0, 3, [](double, double) { return kUnknown; });
}

GridMap makeRoomMap() {
  return rasterize(-0.5, 4.5, -0.5, 3.5, [](double x, double y) {
    if (x > 0 && x < 3.8 && y > 0 && y < 2.8) return kFree;
    if (x > -0.1 && x < 3.9 && y > -0.1 && y < 2.9) return kOccupied;
    return kUnknown;
  });
}

GridMap makeTwoRoomsMap(bool right_known) {
  const mapping::SegmentWorld world = mapping::SegmentWorld::twoRooms(5, 4, 1);
  return rasterize(-0.5, 10.5, -0.5, 4.5, [&](double x, double y) {
    if (!right_known && x > 5.5) return kUnknown;
    double d = 1e9;
    for (const auto& s : world.walls()) d = std::min(d, pointSegmentDistance(x, y, s));
    if (d < 0.06) return kOccupied;
    if (x > 0 && x < 10 && y > 0 && y < 4) return kFree;
    return kUnknown;
  });
}

// ---- topological graphs ---------------------------------------------------------------

namespace {
TopoNode topoNode(RegionId r, double cx, double cy, double area, bool visited) {
  TopoNode n;
  n.region = r;
  n.centroid = {cx, cy};
  n.area = area;
  n.visited = visited;
  return n;
}
TopoEdge topoEdge(RegionId a, RegionId b, double mx, double my, double width) {
  TopoEdge e;
  e.a = a;
  e.b = b;
  e.midpoint = {mx, my};
  e.width = width;
  return e;
}
}  // namespace

TopoGraph makeTopoUnexploredOnly() {
  TopoGraph t;
  t.nodes.push_back(topoNode(kUnexplored, 0, 0, 0, false));
  t.current = 0;
  return t;
}

TopoGraph makeTopoFinished() {
  TopoGraph t;
  t.nodes.push_back(topoNode(kUnexplored, 0, 0, 0, false));
  t.nodes.push_back(topoNode(1, 2.5, 2, 20, true));
  t.nodes.push_back(topoNode(2, 7.5, 2, 20, true));
  t.nodes.back().entrance_edge = 0;
  t.edges.push_back(topoEdge(1, 2, 5, 2, 1));
  t.edges.back().traversals.push_back(Traversal{true, 10.0});
  t.current = 2;
  return t;
}

TopoGraph makeTopoWithFrontiers() {
  TopoGraph t;
  t.nodes.push_back(topoNode(kUnexplored, 0, 0, 0, false));
  t.nodes.push_back(topoNode(1, 2.5, 2, 20, true));
  t.nodes.push_back(topoNode(2, 7.5, 2, 20, false));
  t.edges.push_back(topoEdge(1, 2, 5, 2, 1));
  t.edges.push_back(topoEdge(1, kUnexplored, 2.5, 3.6, 1.0));
  t.edges.push_back(topoEdge(2, kUnexplored, 9.5, 2.0, 1.5));
  t.current = 1;
  return t;
}

}  // namespace asf::conformance::detail
