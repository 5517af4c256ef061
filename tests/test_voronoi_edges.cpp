// The generalized Voronoi graph of an occupancy grid and the virtual edges it adds to a pose
// graph in a partially explored map (thesis section 3.6): the GVG of hand-made grids, the
// virtual edge between two corridors joined only through a mapped room, no virtual edge
// through occupied or unknown cells or through a wall, planning through virtual edges
// (distance x det(E[C]) against the library's own evaluation of the explicit candidates)
// and `asf plan --voronoi`.
#include <asf/errors.h>
#include <asf/planning/expected_uncertainty.h>
#include <asf/io/occupancy_io.h>
#include <asf/planning/voronoi_graph.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "test_util.h"

namespace {

using asf::NodeId;
using Eigen::Matrix3d;
using mrpt::poses::CPose2D;
namespace planning = asf::planning;

/// A grid of w x h metres at `res`, all occupied, painted with boxes of p(free).
struct Canvas {
  double w, h, res;
  std::shared_ptr<mrpt::maps::COccupancyGridMap2D> grid;
  Canvas(double w_, double h_, double res_) : w(w_), h(h_), res(res_) {
    grid = std::make_shared<mrpt::maps::COccupancyGridMap2D>(0.f, float(w), 0.f, float(h),
                                                             float(res));
    grid->fill(0.0f);
  }
  /// Cells whose centre lies in [x0, x1] x [y0, y1] get p(free) = p.
  Canvas& box(double x0, double y0, double x1, double y1, float p = 1.0f) {
    for (unsigned cy = 0; cy < grid->getSizeY(); ++cy)
      for (unsigned cx = 0; cx < grid->getSizeX(); ++cx) {
        const double x = (cx + 0.5) * res, y = (cy + 0.5) * res;
        if (x >= x0 && x <= x1 && y >= y0 && y <= y1) grid->setCell(cx, cy, p);
      }
    return *this;
  }
  asf::GridMap map() const {
    asf::GridMap m;
    m.grid = grid;
    m.version = 1;
    return m;
  }
};

std::string drawSkeleton(const planning::Gvg& g) {
  std::ostringstream s;
  for (int cy = g.height - 1; cy >= 0; --cy) {
    for (int cx = 0; cx < g.width; ++cx) s << (g.skeleton[cy * g.width + cx] ? '#' : '.');
    s << "\n";
  }
  s << g.vertices.size() << " vertices, " << g.edges.size() << " edges\n";
  for (const auto& v : g.vertices)
    s << "  vertex (" << v.position.x() << ", " << v.position.y() << ") degree " << v.degree
      << "\n";
  return s.str();
}

// ---------------------------------------------------------------------------------------
// The GVG

TEST(Voronoi, PlusShapedCorridorHasOneJunctionAndFourBranches) {
  // Arms 1 m wide, from the centre (5, 5) to 1 m from the map's border.
  Canvas c(10, 10, 0.1);
  c.box(1, 4.5, 9, 5.5).box(4.5, 1, 5.5, 9);
  const planning::Gvg g = planning::computeGvg(c.map(), {0.65, 0.1});
  const std::string pic = drawSkeleton(g);
  ASSERT_EQ(g.junctions(), 1u) << pic;
  ASSERT_EQ(g.ends(), 4u) << pic;
  ASSERT_EQ(g.vertices.size(), 5u) << pic;
  ASSERT_EQ(g.edges.size(), 4u) << pic;
  const auto& j = *std::find_if(g.vertices.begin(), g.vertices.end(),
                                [](const planning::Gvg::Vertex& v) { return v.degree >= 3; });
  EXPECT_EQ(j.degree, 4) << pic;
  EXPECT_NEAR(j.position.x(), 5, 0.15) << pic;
  EXPECT_NEAR(j.position.y(), 5, 0.15) << pic;
  // Each branch runs from the junction to its arm's end (4 m minus about the half width).
  for (const auto& e : g.edges) {
    EXPECT_GT(e.length, 3.0) << pic;
    EXPECT_LT(e.length, 4.1) << pic;
    const auto& end = g.vertices[g.vertices[e.a].degree == 1 ? e.a : e.b];
    const double r = std::hypot(end.position.x() - 5, end.position.y() - 5);
    EXPECT_GT(r, 3.0) << pic;
    // On the arm's centre line.
    EXPECT_LT(std::min(std::abs(end.position.x() - 5), std::abs(end.position.y() - 5)), 0.15)
        << pic;
  }
}

TEST(Voronoi, TwoRoomsWithADoorAreOnePathThroughTheDoor) {
  // Rooms [1, 5] x [1, 5] and [5.2, 9.2] x [1, 5]; the wall between them has a 1 m door.
  Canvas c(10.2, 6, 0.1);
  c.box(1, 1, 5, 5).box(5.2, 1, 9.2, 5).box(5, 2.5, 5.2, 3.5);
  const planning::Gvg g = planning::computeGvg(c.map(), {0.65, 0.1});
  const std::string pic = drawSkeleton(g);
  ASSERT_EQ(g.edges.size(), 1u) << pic;
  EXPECT_EQ(g.junctions(), 0u) << pic;
  EXPECT_EQ(g.ends(), 2u) << pic;
  // Through the door.
  bool door = false;
  for (int cell : g.edges[0].cells) {
    const auto p = g.cellCentre(cell);
    if (p.x() > 5 && p.x() < 5.2) {
      door = true;
      EXPECT_NEAR(p.y(), 3, 0.1) << pic;
    }
  }
  EXPECT_TRUE(door) << pic;
  // A door narrower than twice the clearance closes the passage: two separate pieces.
  const planning::Gvg closed = planning::computeGvg(c.map(), {0.65, 0.6});
  EXPECT_GE(closed.edges.size(), 2u) << drawSkeleton(closed);
  for (const auto& e : closed.edges)
    EXPECT_EQ(closed.vertices[e.a].position.x() < 5.1, closed.vertices[e.b].position.x() < 5.1)
        << drawSkeleton(closed);
  for (int cell = 0; cell < closed.width * closed.height; ++cell)
    if (closed.skeleton[cell]) {
      const auto p = closed.cellCentre(cell);
      EXPECT_FALSE(p.x() > 4.5 && p.x() < 5.7) << drawSkeleton(closed);
    }
}

TEST(Voronoi, ErrorsNameTheProblem) {
  asf::GridMap none;
  EXPECT_TRUE(asf_test::has(asf_test::errorOf<asf::Error>([&] { planning::computeGvg(none); }),
                            "no grid"));
  Canvas c(4, 4, 0.1);
  EXPECT_TRUE(asf_test::has(
      asf_test::errorOf<asf::Error>([&] { planning::computeGvg(c.map(), {1.5, 0.1}); }),
      "free_threshold"));
  planning::VirtualEdgeOptions o;
  o.detour = 0.5;
  asf::PoseGraph g;
  EXPECT_TRUE(asf_test::has(
      asf_test::errorOf<asf::Error>([&] { planning::computeVirtualEdges(g, c.map(), o); }), "detour"));
}

// ---------------------------------------------------------------------------------------
// Virtual edges

/// Two parallel corridors A (y in [1, 2.2]) and B (y in [8, 9.2]), x in [1, 21], joined in
/// the east by a corridor C (x in [19.8, 21]) the robot drove, and in the west by a room R
/// ([3, 7] x [2.2, 8]) it only saw. The robot drove A east, C north, B west.
struct TwoCorridors {
  Canvas canvas{22, 10.4, 0.1};
  asf::PoseGraph g;
  asf::Marginals m;
  NodeId a5 = 0, b5 = 0;  ///< the nodes at x = 5 on A and B
  std::vector<NodeId> driven;  ///< a5 -> b5 along the pose graph
  explicit TwoCorridors(float room = 1.0f) {
    canvas.box(1, 1, 21, 2.2).box(1, 8, 21, 9.2).box(19.8, 1, 21, 9.2);
    canvas.box(3, 2.2, 7, 8, room);
    std::vector<std::pair<double, double>> xy;
    for (int x = 2; x <= 20; ++x) xy.emplace_back(x, 1.6);
    for (int k = 0; k <= 7; ++k) xy.emplace_back(20.4, 1.6 + k);
    for (int x = 20; x >= 2; --x) xy.emplace_back(x, 8.6);
    const asf::mapping::OdometryNoiseModel model;
    for (std::size_t i = 0; i < xy.size(); ++i) {
      const std::size_t j = i + 1 < xy.size() ? i + 1 : i;
      const std::size_t k = i + 1 < xy.size() ? i : i - 1;
      const double phi = std::atan2(xy[j].second - xy[k].second, xy[j].first - xy[k].first);
      g.addNode(CPose2D(xy[i].first, xy[i].second, phi));
      if (xy[i] == std::pair<double, double>{5, 1.6}) a5 = NodeId(i);
      if (xy[i] == std::pair<double, double>{5, 8.6}) b5 = NodeId(i);
    }
    for (std::size_t i = 1; i < xy.size(); ++i) {
      asf::PoseEdge e;
      e.from = NodeId(i - 1);
      e.to = NodeId(i);
      e.mean = g.nodes[i].pose - g.nodes[i - 1].pose;
      e.information = asf::edgeInformation(e.mean, model.covariance(e.mean),
                                            Matrix3d::Identity() * 1e-12);
      g.addEdge(e);
    }
    for (NodeId v = a5; v <= b5; ++v) driven.push_back(v);
    for (std::size_t i = 0; i < g.size(); ++i)
      m.node.push_back(Eigen::Vector3d(4e-4, 4e-4, 1e-4).asDiagonal());
  }
  double x(NodeId v) const { return g.nodes[v].pose.x(); }
  double y(NodeId v) const { return g.nodes[v].pose.y(); }
};

TEST(VoronoiEdges, CorridorsJoinedOnlyThroughAMappedRoomGetAVirtualEdge) {
  TwoCorridors w;
  const planning::VirtualEdges ve = planning::computeVirtualEdges(w.g, w.canvas.map());
  const std::string pic = drawSkeleton(ve.gvg);
  EXPECT_EQ(ve.attached, w.g.size()) << pic;
  ASSERT_EQ(ve.edges.size(), 1u) << pic;
  const planning::VirtualEdge& e = ve.edges[0];
  // From A's node at x = 5 (the room's axis) to B's.
  EXPECT_EQ(e.a, w.a5) << "(" << w.x(e.a) << ", " << w.y(e.a) << ")\n" << pic;
  EXPECT_EQ(e.b, w.b5) << "(" << w.x(e.b) << ", " << w.y(e.b) << ")\n" << pic;
  // Along the room's skeleton: 7 m between the corridor axes, a little more with the legs.
  EXPECT_GT(e.length, 6.9);
  EXPECT_LT(e.length, 9.0);  // the GVG bends where the room opens on the corridors
  EXPECT_LE(e.skeleton_length, e.length);
  // The covariance is the odometry model's for that length, turned towards b (north: the
  // forward variance lands on y in a's frame... a heads east, b is at +90 deg).
  const asf::mapping::OdometryNoiseModel model;
  CPose2D d = w.g.nodes[e.b].pose - w.g.nodes[e.a].pose;
  d.normalizePhi();
  const Matrix3d c0 = model.covariance(CPose2D(e.length, 0, d.phi()));
  const double bearing = std::atan2(d.y(), d.x());
  Matrix3d R = Matrix3d::Identity();
  R.topLeftCorner<2, 2>() << std::cos(bearing), -std::sin(bearing), std::sin(bearing),
      std::cos(bearing);
  EXPECT_LE((e.covariance_ab - R * c0 * R.transpose()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_GT(e.covariance_ab(2, 2), 0);
  // A stricter detour factor than the 38 m drive / 7 m shortcut drops it.
  planning::VirtualEdgeOptions strict;
  strict.detour = 6;
  EXPECT_EQ(planning::computeVirtualEdges(w.g, w.canvas.map(), strict).edges.size(), 0u);
}

TEST(VoronoiEdges, DriveInIncrementsComposesTheModelPerIncrement) {
  TwoCorridors w;
  planning::VirtualEdgeOptions o;
  o.odometry_step = 0.5;
  const planning::VirtualEdges ve = planning::computeVirtualEdges(w.g, w.canvas.map(), o);
  ASSERT_EQ(ve.edges.size(), 1u);
  const planning::VirtualEdge& e = ve.edges[0];
  // n equal increments, the turn (here a half turn: B is driven west) spread over them.
  // Heading variances add: n x the increment's, exactly. The position variances add up
  // (each increment's turned into the drive's frame, a rotation keeps the trace) plus the
  // lever arms of the heading errors: the trace is at least n x the increment's.
  const double n = std::ceil(e.length / 0.5);
  CPose2D d = w.g.nodes[e.b].pose - w.g.nodes[e.a].pose;
  d.normalizePhi();
  const Matrix3d ci = o.odometry.covariance(CPose2D(e.length / n, 0, d.phi() / n));
  const double bearing = std::atan2(d.y(), d.x());
  Matrix3d R = Matrix3d::Identity();
  R.topLeftCorner<2, 2>() << std::cos(bearing), -std::sin(bearing), std::sin(bearing),
      std::cos(bearing);
  const Matrix3d own = R.transpose() * e.covariance_ab * R;  // back in the drive's frame
  EXPECT_NEAR(own(2, 2), n * ci(2, 2), 1e-12);
  EXPECT_GT(own(0, 0) + own(1, 1), n * (ci(0, 0) + ci(1, 1)));
  // Far below the one-increment drive of the same length (the model's std grows with the
  // increment): the heading variance by about n.
  const planning::VirtualEdges one = planning::computeVirtualEdges(w.g, w.canvas.map());
  ASSERT_EQ(one.edges.size(), 1u);
  EXPECT_LT(e.covariance_ab(2, 2), one.edges[0].covariance_ab(2, 2) / (0.5 * n));
  // An increment longer than the drive is the one-increment drive.
  o.odometry_step = 100;
  const planning::VirtualEdges big = planning::computeVirtualEdges(w.g, w.canvas.map(), o);
  EXPECT_EQ(big.edges[0].covariance_ab, one.edges[0].covariance_ab);
  o.odometry_step = -1;
  EXPECT_THROW(planning::computeVirtualEdges(w.g, w.canvas.map(), o), asf::Error);
}

TEST(VoronoiEdges, NoVirtualEdgeThroughOccupiedOrUnknownCells) {
  for (float room : {0.0f, 0.5f}) {  // the room occupied, then unknown
    TwoCorridors w(room);
    const planning::VirtualEdges ve = planning::computeVirtualEdges(w.g, w.canvas.map());
    EXPECT_TRUE(ve.edges.empty()) << "room p(free) " << room << ": " << ve.edges.size()
                                  << " virtual edges\n"
                                  << drawSkeleton(ve.gvg);
    // The skeleton stays in free cells with the clearance.
    for (int cell = 0; cell < ve.gvg.width * ve.gvg.height; ++cell)
      if (ve.gvg.skeleton[cell]) {
        const auto p = ve.gvg.cellCentre(cell);
        EXPECT_FALSE(p.x() > 2.9 && p.x() < 7.1 && p.y() > 2.4 && p.y() < 7.8)
            << p.transpose();
      }
  }
  // A thin wall between two corridors: nodes within the attach radius of the
  // other corridor's GVG do not attach across it, and no virtual edge crosses it.
  Canvas c(12, 4.2, 0.1);
  c.box(1, 1, 11, 2).box(1, 2.2, 11, 3.2);  // a 0.2 m wall: y in (2, 2.2)
  asf::PoseGraph g;
  for (int x = 2; x <= 10; ++x) g.addNode(CPose2D(x, 1.5, 0));
  for (int x = 2; x <= 10; ++x) g.addNode(CPose2D(x, 2.7, 0));
  for (NodeId i = 1; i < g.size(); ++i) {
    if (i == 9) continue;  // the two rows are not joined
    asf::PoseEdge e;
    e.from = i - 1;
    e.to = i;
    e.mean = g.nodes[i].pose - g.nodes[i - 1].pose;
    g.addEdge(e);
  }
  planning::VirtualEdgeOptions o;
  o.attach_radius = 3.0;
  o.gvg.clearance = 0.1;
  const planning::VirtualEdges ve = planning::computeVirtualEdges(g, c.map(), o);
  for (const auto& e : ve.edges)
    EXPECT_EQ(e.a / 9, e.b / 9) << e.a << " - " << e.b << "\n" << drawSkeleton(ve.gvg);
  for (NodeId v = 0; v < g.size(); ++v) {
    ASSERT_GE(ve.attach_cell[v], 0);
    const double cy = ve.gvg.cellCentre(ve.attach_cell[v]).y();
    EXPECT_EQ(cy > 2.1, v >= 9) << v << " attached at y " << cy;
  }
}

// ---------------------------------------------------------------------------------------
// Planning through virtual edges

struct Costs {
  double long_cost, short_cost;
};

/// The oracle: distance x det(E[C]) of the two explicit candidates, by the library's own
/// evaluation (makePathModel, evaluatePath, pathLength).
Costs oracle(const TwoCorridors& w, const std::vector<planning::VirtualEdge>& ve,
             const planning::CriterionOptions& o) {
  auto cost = [&](const std::vector<NodeId>& p) {
    const planning::PathModel model = planning::makePathModel(w.g, &w.m, p, &ve);
    return planning::pathLength(model) *
           planning::evaluatePath(planning::Criterion::ExpectedUncertainty, model, o).cost;
  };
  return {cost(w.driven), cost({w.a5, w.b5})};
}

TEST(VoronoiEdges, PlanTakesTheShortcutOnlyWhenItsExpectedCostIsLower) {
  TwoCorridors w;
  const asf::GridMap map = w.canvas.map();
  asf::PlanRequest req;
  req.graph = &w.g;
  req.marginals = &w.m;
  req.map = &map;
  req.start = w.a5;
  req.goal = w.b5;
  planning::CriterionOptions o;
  o.reloc.p_recognition = 0;  // a featureless building: odometry only
  o.reloc.use_cross = false;
  planning::PathSearchOptions s;

  // Without virtual edges: the long driven route, the only one.
  auto r = planning::planBest(req, planning::Criterion::ExpectedUncertainty, o, s);
  ASSERT_TRUE(r.found) << r.reason;
  EXPECT_EQ(r.nodes, w.driven);
  EXPECT_EQ(r.criterion, "det(E[C])");

  // With them: the shortcut, cheaper by the oracle.
  s.voronoi_edges = true;
  std::string note;
  r = planning::planBest(req, planning::Criterion::ExpectedUncertainty, o, s, &note);
  ASSERT_TRUE(r.found) << r.reason;
  const auto ve = planning::computeVirtualEdges(w.g, map, s.voronoi).edges;
  ASSERT_EQ(ve.size(), 1u);
  Costs k = oracle(w, ve, o);
  ASSERT_LT(k.short_cost, k.long_cost);  // the scenario: the shortcut is better
  EXPECT_EQ(r.nodes, (std::vector<NodeId>{w.a5, w.b5})) << note;
  EXPECT_NEAR(r.cost, k.short_cost, 1e-9 * k.short_cost);
  EXPECT_EQ(r.criterion, "distance*det(E[C])");
  EXPECT_TRUE(note.empty()) << note;  // virtual edges found: nothing to warn about
  // Its E[C] is pure odometry: start marginal propagated by the virtual covariance (no
  // relocalization on a virtual step, even with certain recognition).
  planning::CriterionOptions certain = o;
  certain.reloc.p_recognition = 1;
  const planning::PathModel sm = planning::makePathModel(w.g, &w.m, {w.a5, w.b5}, &ve);
  ASSERT_TRUE(sm.isVirtual(1));
  EXPECT_EQ(sm.motion_cov[1], ve[0].covariance_ab);
  EXPECT_NEAR(planning::pathLength(sm), ve[0].length, 1e-12);
  const Matrix3d ec = planning::evaluatePath(planning::Criterion::ExpectedUncertainty, sm, certain).expected;
  const planning::RelocProbFn never = [](const planning::RelocQuery&) { return 0.0; };
  EXPECT_LE((ec - planning::expectedCovarianceBruteForce(sm, never)).cwiseAbs().maxCoeff(), 1e-15);
  // ... while on a real edge certain recognition gives the goal's marginal.
  EXPECT_FALSE(planning::makePathModel(w.g, &w.m, {w.a5, w.a5 + 1}).isVirtual(1));
  // Without the virtual edges the shortcut is no path.
  EXPECT_THROW(planning::makePathModel(w.g, &w.m, {w.a5, w.b5}), asf::Error);

  // A huge odometry covariance on the shortcut: the long route again, as the oracle says.
  s.voronoi.covariance_scale = 1e4;
  r = planning::planBest(req, planning::Criterion::ExpectedUncertainty, o, s);
  ASSERT_TRUE(r.found) << r.reason;
  const auto ve_huge = planning::computeVirtualEdges(w.g, map, s.voronoi).edges;
  ASSERT_EQ(ve_huge.size(), 1u);
  k = oracle(w, ve_huge, o);
  ASSERT_GT(k.short_cost, k.long_cost);
  EXPECT_EQ(r.nodes, w.driven);
  EXPECT_NEAR(r.cost, k.long_cost, 1e-9 * k.long_cost);

  // No map: pose-graph edges only, and the note says so.
  req.map = nullptr;
  s.voronoi.covariance_scale = 1;
  r = planning::planBest(req, planning::Criterion::ExpectedUncertainty, o, s, &note);
  ASSERT_TRUE(r.found);
  EXPECT_EQ(r.nodes, w.driven);
  EXPECT_TRUE(asf_test::has(note, "no map")) << note;
}

TEST(VoronoiEdges, AlgorithmOneSkipsVirtualStepsLikeTheBruteForce) {
  TwoCorridors w;
  const auto ve = planning::computeVirtualEdges(w.g, w.canvas.map()).edges;
  ASSERT_EQ(ve.size(), 1u);
  // a5-1 .. a5 -> b5 .. b5-2 (b5 - 1 is east of b5 on B): a virtual step in the middle.
  const std::vector<NodeId> p{w.a5 - 1, w.a5, w.b5, w.b5 - 1, w.b5 - 2};
  const planning::PathModel model = planning::makePathModel(w.g, &w.m, p, &ve);
  ASSERT_TRUE(model.isVirtual(2));
  std::size_t asked_at_virtual = 0;
  const planning::RelocProbFn half = [&](const planning::RelocQuery& q) {
    if (q.t == 2) ++asked_at_virtual;
    return 0.5;
  };
  const auto fast = planning::expectedCovariance(model, half);
  const Matrix3d slow = planning::expectedCovarianceBruteForce(model, half);
  EXPECT_LE((fast.mean - slow).cwiseAbs().maxCoeff(), 1e-12 * slow.cwiseAbs().maxCoeff());
  EXPECT_EQ(asked_at_virtual, 0u);
  EXPECT_EQ(fast.prob[2], 0.0);  // never relocalized on arriving by the virtual edge
}

TEST(VoronoiEdges, AsfPlanVoronoi) {
  TwoCorridors w;
  const auto dir = std::filesystem::temp_directory_path() / "asf_test_voronoi";
  std::filesystem::create_directories(dir);
  const std::string g2o = (dir / "corridors.g2o").string();
  {
    std::ofstream f(g2o);
    f.precision(17);
    for (const auto& n : w.g.nodes)
      f << "VERTEX_SE2 " << n.id << " " << n.pose.x() << " " << n.pose.y() << " " << n.pose.phi()
        << "\n";
    for (const auto& e : w.g.edges) {
      const Matrix3d& I = e.information;
      f << "EDGE_SE2 " << e.from << " " << e.to << " " << e.mean.x() << " " << e.mean.y() << " "
        << e.mean.phi() << " " << I(0, 0) << " " << I(0, 1) << " " << I(0, 2) << " " << I(1, 1)
        << " " << I(1, 2) << " " << I(2, 2) << "\n";
    }
  }
  // The map as an image (row 0 = top, free 255).
  {
    const auto& grid = *w.canvas.grid;
    const int W = int(grid.getSizeX()), H = int(grid.getSizeY());
    std::ofstream f(dir / "map.pgm", std::ios::binary);
    f << "P5\n" << W << " " << H << "\n255\n";
    for (int row = 0; row < H; ++row)
      for (int col = 0; col < W; ++col)
        f.put(static_cast<char>(grid.getCell(col, H - 1 - row) > 0.9 ? 255 : 0));
  }
  // PGM is read by the image reader as well; the command takes any image.
  const std::string map = (dir / "map.pgm").string();
  const std::string base = "plan --graph " + g2o + " --start " + std::to_string(w.a5) +
                           " --goal " + std::to_string(w.b5) +
                           " --set p_recognition=0 --set use_cross=false --json";
  auto r = asf_test::runHost(base + " --map " + map + " --resolution 0.1", false);
  ASSERT_EQ(r.code, 0) << r.out;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["path"].get<std::vector<NodeId>>().size(), w.driven.size()) << r.out;
  r = asf_test::runHost(base + " --map " + map + " --resolution 0.1 --voronoi", false);
  ASSERT_EQ(r.code, 0) << r.out;
  j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["path"].get<std::vector<NodeId>>(), (std::vector<NodeId>{w.a5, w.b5})) << r.out;
  EXPECT_EQ(j["criterion"], "distance*det(E[C])") << r.out;
  EXPECT_EQ(j["virtual_edges"], 1) << r.out;
  EXPECT_EQ(j["virtual_steps"].size(), 1u) << r.out;
  // Table 3.2: the best path along the graph and the shortest through unexplored space,
  // each with length, det E[C] and their product; the chosen one is the cheaper here.
  const auto& cmp = j["comparison"];
  ASSERT_FALSE(cmp["graph"].is_null()) << r.out;
  ASSERT_FALSE(cmp["unexplored"].is_null()) << r.out;
  for (const char* k : {"graph", "unexplored"})
    EXPECT_DOUBLE_EQ(cmp[k]["cost"].get<double>(), cmp[k]["distance"].get<double>() *
                                                       cmp[k]["expected_uncertainty"].get<double>())
        << k;
  EXPECT_EQ(cmp["graph"]["virtual_steps"], 0);
  EXPECT_EQ(cmp["unexplored"]["path"], j["path"]);
  EXPECT_LT(cmp["unexplored"]["cost"].get<double>(), cmp["graph"]["cost"].get<double>());
  EXPECT_EQ(cmp["graph"]["path"].size(), w.driven.size());
  EXPECT_NEAR(cmp["graph"]["distance"].get<double>(), 38, 1.0) << "A east, C north, B west";
  // The same map as a map_server YAML: resolution and origin from it, the same plan.
  {
    asf::GridMap m = w.canvas.map();
    asf::io::writeOccupancyMap(m, (dir / "occ").string());
  }
  r = asf_test::runHost(base + " --map " + (dir / "occ.yaml").string() + " --voronoi", false);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(nlohmann::json::parse(r.out)["path"], j["path"]) << r.out;
  // The same through --set, and errors naming what is missing.
  r = asf_test::runHost(base + " --map " + map + " --resolution 0.1 --set voronoi_edges=true",
                        false);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(nlohmann::json::parse(r.out)["path"].size(), 2u) << r.out;
  r = asf_test::runHost(base + " --voronoi");
  EXPECT_NE(r.code, 0);
  EXPECT_TRUE(asf_test::has(r.out, "--map")) << r.out;
  r = asf_test::runHost(base + " --set voronoi_edges=true");
  EXPECT_NE(r.code, 0);
  EXPECT_TRUE(asf_test::has(r.out, "voronoi_edges")) << r.out;
  r = asf_test::runHost(base + " --map " + map + " --resolution 0.1 --voronoi --planner shortest");
  EXPECT_NE(r.code, 0);
  EXPECT_TRUE(asf_test::has(r.out, "voronoi_edges")) << r.out;
  r = asf_test::runHost(base + " --map " + map +
                        " --resolution 0.1 --voronoi --set voronoi_detour=0.5");
  EXPECT_NE(r.code, 0);
  EXPECT_TRUE(asf_test::has(r.out, "voronoi_detour")) << r.out;
}

}  // namespace
