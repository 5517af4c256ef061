// Tests of the icp_graph front-end on sim2d runs: ICP edges against the true relative poses,
// trajectory error against the odometry front-end under heavy odometry noise, frames without
// scans, the quality gate (scans from different places, a featureless corridor), and a loop
// closure in a square ring corridor corrected by the dense_gn back-end.
#include <asf/backend.h>
#include <asf/errors.h>
#include <asf/frontend.h>
#include <asf/framework/registry.h>
#include <asf/source.h>
#include <gtest/gtest.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <Eigen/Dense>
#include <cmath>
#include <filesystem>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "../scan_matcher.h"

namespace {

using mrpt::poses::CPose2D;
using KV = std::map<std::string, std::string>;
namespace fs = std::filesystem;

std::shared_ptr<const asf::framework::PluginInfo> plugin(const std::string& file) {
  static std::map<std::string, std::shared_ptr<const asf::framework::PluginInfo>> cache;
  auto& p = cache[file];
  if (!p) p = asf::framework::Registry::loadFile(std::string(ASF_TEST_PLUGIN_DIR) + "/" + file);
  return p;
}

template <class T>
asf::framework::PluginHandle<T> make(const std::string& file, const std::string& name, KV kv,
                          std::uint64_t seed = 1) {
  auto info = plugin(file);
  auto h = asf::framework::Registry::create<T>(info);
  h->setMinLoggingLevel(mrpt::system::LVL_ERROR);
  asf::PluginContext ctx;
  ctx.seed = seed;
  h->configure(asf::Params::fromSpecs(name, info->descriptor->keys, info->descriptor->num_keys, kv),
               ctx);
  return h;
}

asf::framework::PluginHandle<asf::Frontend> icpGraph(const KV& kv = {}) {
  return make<asf::Frontend>("frontend_icp_graph.so", "icp_graph", kv);
}
asf::framework::PluginHandle<asf::Frontend> odometry(const KV& kv = {}) {
  return make<asf::Frontend>("frontend_odometry.so", "odometry", kv);
}

/// Drives sim2d through `goals` (world frame). Navigation is given the true pose (re-planned
/// every 20 steps) so that heavy odometry noise does not steer the robot into walls.
std::vector<asf::SensorFrame> simulate(KV kv, const std::vector<std::pair<double, double>>& goals,
                                       std::uint64_t seed = 1) {
  kv.emplace("record", "false");
  auto src = make<asf::Source>("source_sim2d.so", "sim2d", kv, seed);
  std::vector<asf::SensorFrame> frames;
  frames.push_back(*src->next());
  const CPose2D start = *frames.front().ground_truth;
  for (const auto& [gx, gy] : goals) {
    asf::Goal g;  // in the map frame: the true start pose is its origin
    const CPose2D local = CPose2D() - start + CPose2D(gx, gy, 0);
    g.x = local.x();
    g.y = local.y();
    g.tolerance = 0.2;
    asf::NavStatus st = asf::NavStatus::Moving;
    for (int leg = 0; leg < 1000 && st == asf::NavStatus::Moving; ++leg) {
      asf::NavigationContext ctx;
      ctx.robot_estimate = CPose2D() - start + *frames.back().ground_truth;
      st = src->navigate(g, ctx);
      for (int k = 0; k < 20 && st == asf::NavStatus::Moving; ++k) {
        auto f = src->next();
        if (!f) break;
        frames.push_back(*f);
        st = src->status();
      }
    }
    EXPECT_EQ(st, asf::NavStatus::Reached)
        << "goal " << gx << ", " << gy << " status " << static_cast<int>(st);
  }
  return frames;
}

/// Feeds frames to a front-end, optionally optimizing with dense_gn after every new node
/// (with marginals, as asf::framework::Pipeline does).
asf::PoseGraph run(asf::Frontend& fe, const std::vector<asf::SensorFrame>& frames,
                   asf::Backend* be = nullptr) {
  asf::PoseGraph g;
  asf::Marginals m;
  for (const auto& f : frames) {
    if (fe.process(f, g, m) && be) {
      be->optimize(g);
      m = be->marginals(g);
      m.graph_revision = g.revision;
    }
  }
  return g;
}

/// Pose of node k's ground truth in the map frame (the first node's true pose is the origin).
CPose2D truthInMap(const asf::PoseGraph& g, std::size_t k) {
  return CPose2D() - *g.nodes[0].ground_truth + *g.nodes[k].ground_truth;
}

double nodeError(const asf::PoseGraph& g, std::size_t k) {
  const CPose2D t = truthInMap(g, k);
  return std::hypot(g.nodes[k].pose.x() - t.x(), g.nodes[k].pose.y() - t.y());
}

double meanNodeError(const asf::PoseGraph& g) {
  double s = 0;
  for (std::size_t k = 0; k < g.size(); ++k) s += nodeError(g, k);
  return s / static_cast<double>(g.size());
}

std::size_t countKind(const asf::PoseGraph& g, asf::EdgeKind k) {
  std::size_t n = 0;
  for (const auto& e : g.edges) n += e.kind == k;
  return n;
}

/// Error of an edge's mean against the true relative pose of its nodes: (metres, radians).
std::pair<double, double> edgeError(const asf::PoseGraph& g, const asf::PoseEdge& e) {
  const CPose2D t = CPose2D() - *g.nodes[e.from].ground_truth + *g.nodes[e.to].ground_truth;
  return {std::hypot(e.mean.x() - t.x(), e.mean.y() - t.y()),
          std::abs(mrpt::math::wrapToPi(e.mean.phi() - t.phi()))};
}

const KV kNoisyRoom = {{"room_width", "8"},   {"room_height", "6"}, {"laser_fov_deg", "270"},
                       {"laser_rays", "271"}, {"odo_a1", "0.05"},   {"odo_a2", "0.005"},
                       {"odo_a3", "5"},       {"odo_a4", "0.2"}};
const std::vector<std::pair<double, double>> kRoomTour = {{6, 1}, {6, 4.5}, {2, 4.5},
                                                          {2, 2}, {5, 3},   {1.5, 1}};

// Writes a square ring corridor (14 m x 14 m outside, 2.5 m wide) with small pillars along
// the walls so that ICP is constrained along the corridor. Returns the PNG's path.
std::string ringWorld() {
  const fs::path file = fs::temp_directory_path() / "asf_test_icp_graph_ring.png";
  const double res = 0.05, size = 14.5;
  const int n = static_cast<int>(size / res);
  cv::Mat img(n, n, CV_8UC1, cv::Scalar(255));
  auto box = [&](double x0, double y0, double x1, double y1) {
    const int c0 = static_cast<int>(x0 / res), c1 = static_cast<int>(x1 / res);
    const int r0 = n - 1 - static_cast<int>(y1 / res), r1 = n - 1 - static_cast<int>(y0 / res);
    cv::rectangle(img, cv::Point(c0, r0), cv::Point(c1, r1), cv::Scalar(0), cv::FILLED);
  };
  box(0, 0, 14.5, 0.25);  // outer walls
  box(0, 14.25, 14.5, 14.5);
  box(0, 0, 0.25, 14.5);
  box(14.25, 0, 14.5, 14.5);
  box(2.75, 2.75, 11.75, 11.75);  // inner block
  // Pillars on the outer wall, irregularly spaced and sized.
  const double at[] = {1.7, 4.1, 5.3, 7.9, 10.2, 12.6};
  for (int k = 0; k < 6; ++k) {
    const double a = at[k], w = 0.2 + 0.05 * k;
    box(a, 0.25, a + w, 0.55);                  // bottom wall
    box(13.95, a, 14.25, a + w);                // right wall
    box(14.5 - a - w, 13.95, 14.5 - a, 14.25);  // top wall
    box(0.25, 14.5 - a - w, 0.55, 14.5 - a);    // left wall
  }
  cv::imwrite(file.string(), img);
  return file.string();
}

// ------------------------------------------------------------------------ scan matcher

/// A short drive up the ring world's left corridor (scans of another place than the room).
std::vector<asf::SensorFrame> ringCorridorDrive() {
  return simulate({{"map_image", ringWorld()},
                   {"resolution", "0.05"},
                   {"start_x", "1.4"},
                   {"start_y", "7"},
                   {"laser_fov_deg", "270"},
                   {"laser_rays", "271"}},
                  {{1.4, 8}}, 5);
}

// Both coarse aligners (MRPT's CICP and our point-to-line Gauss-Newton), from guesses as far
// off as the loop verification's perturbed ones (0.3 m, 10 degrees) and beyond.
TEST(IcpGraphMatcher, RecoversAKnownOffsetBetweenTwoScansOfARoom) {
  auto frames = simulate({{"laser_fov_deg", "270"}, {"laser_rays", "271"}, {"range_sigma", "0"}},
                         {{2.0, 1.0}});
  ASSERT_GT(frames.size(), 15u);
  const auto& a = frames.front();
  const auto& b = frames[15];
  ASSERT_TRUE(a.scan && b.scan);
  const CPose2D truth = CPose2D() - *a.ground_truth + *b.ground_truth;
  const auto ca = asf::icp_graph::Cloud::fromScan(*a.scan);
  const auto cb = asf::icp_graph::Cloud::fromScan(*b.scan);
  using asf::icp_graph::IcpMethod;
  for (IcpMethod method : {IcpMethod::MrptLm, IcpMethod::PointToLine})
    for (const CPose2D& off : {CPose2D(0.15, -0.1, 0.05), CPose2D(0.3, 0.3, 0.1745),
                               CPose2D(-0.3, 0.3, -0.1745), CPose2D(0.4, -0.3, 0.2)}) {
      SCOPED_TRACE(std::string(method == IcpMethod::MrptLm ? "CICP" : "point-to-line") +
                   " from an offset of " + off.asString());
      asf::icp_graph::IcpOptions o;
      o.method = method;
      const auto m = asf::icp_graph::match(ca, cb, truth + off, o);
      ASSERT_TRUE(m.ran) << m.reason;
      // CICP ends 11 mm off from the 10-degree guesses, point-to-line within 1 mm.
      EXPECT_NEAR(m.pose.x(), truth.x(), 0.015);
      EXPECT_NEAR(m.pose.y(), truth.y(), 0.015);
      EXPECT_NEAR(mrpt::math::wrapToPi(m.pose.phi() - truth.phi()), 0, 0.005);
      EXPECT_LT(static_cast<int>(m.iterations), o.max_iterations) << "converged";
      EXPECT_GT(m.goodness, 0.8);
      EXPECT_GT(m.inlier_ratio, 0.8);
      // Noise-free ranges, but ray-cast on a 4 cm grid: residuals of a couple of centimetres.
      EXPECT_LT(m.rmse, 0.03);
      EXPECT_TRUE(m.cov.allFinite());
      EXPECT_GT(m.cov.determinant(), 0);
    }
}

// The goodness is CICP's correspondence ratio for both aligners: the share of the decimated
// points with a reference point within the final distance; a scan against itself has all of
// them, against a scan of another place few.
TEST(IcpGraphMatcher, GoodnessCountsTheCorrespondencesAtTheFinalDistance) {
  auto frames = simulate({{"laser_fov_deg", "270"}, {"laser_rays", "271"}, {"range_sigma", "0"}},
                         {{2.0, 1.0}});
  const auto ring = ringCorridorDrive();
  const auto room = asf::icp_graph::Cloud::fromScan(*frames.front().scan);
  const auto other = asf::icp_graph::Cloud::fromScan(*ring.front().scan);
  using asf::icp_graph::IcpMethod;
  for (IcpMethod method : {IcpMethod::MrptLm, IcpMethod::PointToLine}) {
    asf::icp_graph::IcpOptions o;
    o.method = method;
    EXPECT_DOUBLE_EQ(asf::icp_graph::match(room, room, CPose2D(), o).goodness, 1.0);
    EXPECT_LT(asf::icp_graph::match(room, other, CPose2D(), o).goodness, 0.5);
  }
}

// Thinning replaces the points of each square (cells aligned with the frame's origin,
// negative coordinates included) by their mean, in the order the squares first occur, and
// drops the caches built before: the kd-tree and MRPT's map answer for the thinned points.
TEST(IcpGraphMatcher, ThinningKeepsTheMeanOfEachCell) {
  auto c = asf::icp_graph::Cloud::fromPoints({0.01f, 0.04f, 0.06f, -0.01f, -0.04f, 0.011f, 0.3f},
                                             {0.01f, 0.02f, 0.01f, 0.01f, 0.01f, -0.02f, 0.3f});
  float d2 = 0;
  EXPECT_EQ(c.nearest(0.04f, 0.02f, d2), 1u);  // builds the kd-tree before thinning
  EXPECT_EQ(c.map().size(), 7u);
  c.thin(0.05);
  // Cells (0,0) <- points 0 and 1, (1,0) <- 2, (-1,0) <- 3 and 4, (0,-1) <- 5, (6,6) <- 6.
  const std::vector<double> x{0.025, 0.06, -0.025, 0.011, 0.3}, y{0.015, 0.01, 0.01, -0.02, 0.3};
  ASSERT_EQ(c.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_NEAR(c.xs()[i], x[i], 1e-6) << i;
    EXPECT_NEAR(c.ys()[i], y[i], 1e-6) << i;
  }
  EXPECT_EQ(c.nearest(0.04f, 0.02f, d2), 0u) << "the kd-tree of the thinned points";
  EXPECT_NEAR(d2, 0.015 * 0.015 + 0.005 * 0.005, 1e-7);
  EXPECT_EQ(c.map().size(), 5u);
  c.thin(0);  // off
  EXPECT_EQ(c.size(), 5u);
}

// ------------------------------------------------------------------------ front-end

TEST(IcpGraphFrontend, IcpEdgesAreCloserToTheTruthThanOdometry) {
  const auto frames = simulate(kNoisyRoom, kRoomTour, 2);
  for (const char* method : {"mrpt_lm", "point_to_line"}) {
    SCOPED_TRACE(method);
    auto fe = icpGraph({{"loop_closure", "false"}, {"icp_method", method}});
    const auto g = run(*fe, frames);
    ASSERT_GT(g.size(), 20u);
    // Integrated odometry at each frame time, to get the odometry increment of every edge.
    std::map<double, CPose2D> odo;
    CPose2D acc;
    for (std::size_t k = 0; k < frames.size(); ++k) {
      if (k) acc = acc + frames[k].odometry;
      odo[frames[k].timestamp] = acc;
    }
    double icp_t = 0, icp_r = 0, odo_t = 0, odo_r = 0, chi2 = 0;
    int n = 0;
    for (const auto& e : g.edges) {
      if (e.kind != asf::EdgeKind::ScanMatch) continue;
      const auto [et, er] = edgeError(g, e);
      asf::PoseEdge oe = e;
      oe.mean = CPose2D() - odo.at(g.nodes[e.from].timestamp) + odo.at(g.nodes[e.to].timestamp);
      const auto [ot, orr] = edgeError(g, oe);
      icp_t += et, icp_r += er, odo_t += ot, odo_r += orr;
      // Normalized error of the ICP edge under its own information (g2o error convention).
      asf::PoseGraph two;
      two.addNode(CPose2D());
      two.addNode(CPose2D() - *g.nodes[e.from].ground_truth + *g.nodes[e.to].ground_truth);
      asf::PoseEdge te = e;
      te.from = 0, te.to = 1;
      two.addEdge(te);
      chi2 += two.chi2();
      ++n;
    }
    ASSERT_GT(n, static_cast<int>(g.edges.size()) * 8 / 10) << "most edges should be ICP edges";
    icp_t /= n, icp_r /= n, odo_t /= n, odo_r /= n, chi2 /= n;
    std::cout << method << ": mean edge error over " << n << " ICP edges: ICP " << icp_t << " m, "
              << icp_r << " rad; odometry " << odo_t << " m, " << odo_r << " rad; mean chi2 "
              << chi2 << " (3 if the covariance is right)\n";
    EXPECT_LT(icp_t, 0.3 * odo_t);
    EXPECT_LT(icp_r, 0.3 * odo_r);
    // The information is neither wildly over- nor under-confident.
    EXPECT_GT(chi2, 0.3);
    EXPECT_LT(chi2, 12);
  }
}

TEST(IcpGraphFrontend, HeavyOdometryNoiseTrajectoryErrorIsFarBelowTheOdometryFrontEnds) {
  const auto frames = simulate(kNoisyRoom, kRoomTour, 3);
  auto fi = icpGraph({{"loop_closure", "false"}});
  auto fo = odometry();
  const auto gi = run(*fi, frames), go = run(*fo, frames);
  const double ei = meanNodeError(gi), eo = meanNodeError(go);
  std::cout << "mean node error: icp_graph " << ei << " m, odometry " << eo << " m; final "
            << nodeError(gi, gi.size() - 1) << " vs " << nodeError(go, go.size() - 1) << "\n";
  EXPECT_LT(ei, 0.25 * eo);
  EXPECT_LT(ei, 0.1);
}

TEST(IcpGraphFrontend, FramesWithoutScansGetOdometryEdges) {
  auto frames = simulate(kNoisyRoom, {{6, 1}, {6, 4}}, 4);
  // Drop the scans of a stretch: keyframes there have none and get odometry edges.
  for (std::size_t k = 40; k < 80 && k < frames.size(); ++k) frames[k].scan.reset();
  auto fe = icpGraph();
  const auto g = run(*fe, frames);
  ASSERT_GT(g.size(), 8u);
  std::size_t without = 0;
  for (const auto& e : g.edges) {
    if (!g.nodes[e.to].scan || !g.nodes[e.from].scan) {
      if (!g.nodes[e.to].scan) {
        EXPECT_EQ(e.kind, asf::EdgeKind::Odometry) << e.from << " -> " << e.to;
        ++without;
      }
    }
    EXPECT_TRUE(e.information.allFinite());
    EXPECT_GT(e.information.determinant(), 0);
  }
  EXPECT_GT(countKind(g, asf::EdgeKind::ScanMatch), 3u);
  EXPECT_GE(without, 1u);
  EXPECT_EQ(g.revision, g.size() + countKind(g, asf::EdgeKind::LoopClosure));
  // A frame without a scan as the very first frame is fine too.
  auto fe2 = icpGraph();
  asf::PoseGraph g2;
  asf::Marginals m;
  asf::SensorFrame f0 = frames.front();
  f0.scan.reset();
  EXPECT_TRUE(fe2->process(f0, g2, m));
  for (std::size_t k = 1; k < frames.size(); ++k) fe2->process(frames[k], g2, m);
  EXPECT_GT(g2.size(), 8u);
  EXPECT_EQ(g2.edges.front().kind, asf::EdgeKind::Odometry);
}

TEST(IcpGraphFrontend, QualityGateRejectsScansFromDifferentPlaces) {
  // Scans of two different worlds: each pair is a "keyframe" whose scan does not belong to the
  // previous one (the reference is the previous keyframe alone: a submap would hold the
  // scan of the same world two keyframes back). The gate must keep the odometry edge.
  const auto room = simulate(kNoisyRoom, {{6, 1}}, 5);
  const auto ring = ringCorridorDrive();
  for (const char* method : {"mrpt_lm", "point_to_line"}) {
    SCOPED_TRACE(method);
    auto fe =
        icpGraph({{"loop_closure", "false"}, {"submap_keyframes", "1"}, {"icp_method", method}});
    asf::PoseGraph g;
    asf::Marginals m;
    asf::SensorFrame f = room.front();
    fe->process(f, g, m);
    for (int k = 0; k < 6; ++k) {
      asf::SensorFrame s = (k % 2 ? room : ring)[k % 2 ? 10 : 5];
      s.odometry = CPose2D(0.6, 0, 0);
      s.odometry_cov = Eigen::Vector3d(1e-3, 1e-3, 1e-3).asDiagonal();
      EXPECT_TRUE(fe->process(s, g, m));
    }
    ASSERT_EQ(g.edges.size(), 6u);
    for (const auto& e : g.edges) {
      EXPECT_EQ(e.kind, asf::EdgeKind::Odometry) << e.from << " -> " << e.to;
      EXPECT_NEAR(e.mean.x(), 0.6, 1e-9);
    }
  }
}

TEST(IcpGraphFrontend, QualityGateRejectsAFeaturelessCorridor) {
  // Two parallel walls, the ends beyond the laser's range: nothing fixes the position along
  // the corridor, so the alignment is ill-conditioned and the odometry edge is kept.
  const auto frames = simulate({{"room_width", "60"},
                                {"room_height", "2"},
                                {"start_x", "20"},
                                {"laser_max_range", "4"},
                                {"laser_fov_deg", "270"},
                                {"laser_rays", "271"}},
                               {{26, 1}}, 6);
  for (const char* method : {"mrpt_lm", "point_to_line"}) {
    auto fe = icpGraph({{"loop_closure", "false"}, {"icp_method", method}});
    const auto g = run(*fe, frames);
    ASSERT_GT(g.edges.size(), 8u);
    EXPECT_EQ(countKind(g, asf::EdgeKind::ScanMatch), 0u) << method;
  }
}

TEST(IcpGraphFrontend, LoopClosureInARingCorridorCorrectsTheDrift) {
  // Round the ring once (start on the left corridor, heading north) and a few metres on.
  const KV sim = {{"map_image", ringWorld()},
                  {"resolution", "0.05"},
                  {"start_x", "1.4"},
                  {"start_y", "3"},
                  {"start_phi_deg", "90"},
                  {"laser_fov_deg", "360"},
                  {"laser_rays", "360"},
                  {"laser_max_range", "6"},
                  {"odo_a1", "0.05"},
                  {"odo_a3", "4"},
                  {"odo_a4", "0.2"},
                  // The drive this test was calibrated on (no extra path margin): the input
                  // of a front-end test does not follow the navigator's defaults.
                  {"nav_safety_margin", "0"}};
  const auto frames =
      simulate(sim, {{1.4, 13}, {13.1, 13.1}, {13.1, 1.4}, {1.4, 1.4}, {1.4, 3}, {1.4, 7}}, 7);
  auto be2 = make<asf::Backend>("backend_dense_gn.so", "dense_gn", {});
  auto without = icpGraph({{"loop_closure", "false"}});
  const auto gn = run(*without, frames, be2.instance.get());
  // ICP from perturbed guesses (the default), the same with our point-to-line aligner, and the
  // correlative search with pairwise confirmation (configs/slam_carmen.ini).
  for (const KV& loops_by : {KV{}, KV{{"icp_method", "point_to_line"}},
                             KV{{"loop_search", "correlative"}, {"loop_confirm", "true"}}}) {
    SCOPED_TRACE(loops_by.empty() ? "icp" : loops_by.begin()->second);
    auto be = make<asf::Backend>("backend_dense_gn.so", "dense_gn", {});
    auto with = icpGraph(loops_by);
    const auto gw = run(*with, frames, be.instance.get());
    const std::size_t loops = countKind(gw, asf::EdgeKind::LoopClosure);
    const double ew = nodeError(gw, gw.size() - 1), en = nodeError(gn, gn.size() - 1);
    std::cout << gw.size() << " nodes, " << loops << " loop closures; final pose error " << ew
              << " m with, " << en << " m without; mean " << meanNodeError(gw) << " vs "
              << meanNodeError(gn) << "\n";
    EXPECT_GE(loops, 1u);
    EXPECT_EQ(countKind(gn, asf::EdgeKind::LoopClosure), 0u);
    // Every accepted closure joins nodes that really are near each other.
    for (const auto& e : gw.edges)
      if (e.kind == asf::EdgeKind::LoopClosure) {
        const auto [lt, lr] = edgeError(gw, e);
        EXPECT_LT(lt, 0.1) << e.from << " -> " << e.to;
        EXPECT_LT(lr, 0.02) << e.from << " -> " << e.to;
      }
    EXPECT_LT(ew, 0.5 * en);
  }
}

TEST(IcpGraphFrontend, OldKeyframesNearbyCutTheDriftOfAReturnTrip) {
  // Up the ring's left corridor and back along it (closures on, optimized after every node).
  // With submap_radius each returning keyframe is matched against the outbound scans of the
  // same place and tied to them by an edge, so the return trip keeps the outbound estimate
  // instead of integrating new drift between closures.
  const KV sim = {{"map_image", ringWorld()}, {"resolution", "0.05"},
                  {"start_x", "1.4"},         {"start_y", "2"},
                  {"start_phi_deg", "90"},    {"laser_fov_deg", "270"},
                  {"laser_rays", "271"},      {"laser_max_range", "6"},
                  {"odo_a1", "0.05"},         {"odo_a3", "4"},
                  {"odo_a4", "0.2"}};
  // Both verify loop closures at every returning keyframe (loop_skip_linked off): the
  // comparison is of the ICP reference. (With the default, one closure per re-entry, the
  // last-keyframes-only run's mean error drops from 0.14 to 0.10 m, the other's rises from
  // 0.061 to 0.068 m; final errors 0.016 and 0.0015 m.)
  const auto frames = simulate(sim, {{1.4, 12.5}, {1.4, 2}}, 11);
  auto recent = icpGraph({{"loop_skip_linked", "false"}});
  auto nearby = icpGraph(
      {{"submap_radius", "2"}, {"submap_nearby_keyframes", "8"}, {"loop_skip_linked", "false"}});
  auto be1 = make<asf::Backend>("backend_dense_gn.so", "dense_gn", {});
  auto be2 = make<asf::Backend>("backend_dense_gn.so", "dense_gn", {});
  const auto gr = run(*recent, frames, be1.instance.get());
  const auto gn = run(*nearby, frames, be2.instance.get());
  const double er = nodeError(gr, gr.size() - 1), en = nodeError(gn, gn.size() - 1);
  std::cout << gn.size() << " nodes, " << countKind(gn, asf::EdgeKind::ScanMatch) << " vs "
            << countKind(gr, asf::EdgeKind::ScanMatch) << " ICP edges; final pose error " << en
            << " m with old keyframes nearby, " << er << " m with the last keyframes only; mean "
            << meanNodeError(gn) << " vs " << meanNodeError(gr) << "\n";
  EXPECT_GT(countKind(gn, asf::EdgeKind::ScanMatch), countKind(gr, asf::EdgeKind::ScanMatch));
  EXPECT_LT(en, 0.5 * er);
  EXPECT_LT(meanNodeError(gn), 0.5 * meanNodeError(gr));
}

}  // namespace

namespace {

// Writes an open hall (50 m x 40 m, a few pillars far apart) for a CARMEN-era laser: 181
// rays over 180 degrees, so at 15 m the returns are 26 cm apart. Returns the PNG's path.
std::string hallWorld() {
  const fs::path file = fs::temp_directory_path() / "asf_test_icp_graph_hall.png";
  const double res = 0.05;
  const int w = static_cast<int>(50 / res), h = static_cast<int>(40 / res);
  cv::Mat img(h, w, CV_8UC1, cv::Scalar(255));
  auto box = [&](double x0, double y0, double x1, double y1) {
    cv::rectangle(img, cv::Point(static_cast<int>(x0 / res), h - 1 - static_cast<int>(y1 / res)),
                  cv::Point(static_cast<int>(x1 / res), h - 1 - static_cast<int>(y0 / res)),
                  cv::Scalar(0), cv::FILLED);
  };
  box(0, 0, 50, 0.2);
  box(0, 39.8, 50, 40);
  box(0, 0, 0.2, 40);
  box(49.8, 0, 50, 40);
  const double pillars[][2] = {{10, 8}, {24, 31}, {38, 9}, {12, 30}, {40, 27}};
  for (const auto& p : pillars) box(p[0], p[1], p[0] + 0.6, p[1] + 0.6);
  cv::imwrite(file.string(), img);
  return file.string();
}

TEST(IcpGraphFrontend, OpenHallLikelihoodMatchKeepsWhatIcpGoodnessRefuses) {
  // Far, sparse walls: most points of a scan have no reference point within CICP's final
  // correspondence distance, so its goodness stays below icp_min_goodness although the
  // alignment is right. icp_low_goodness = odometry keeps the odometry edge there; likelihood
  // searches the scan in the submap's likelihood field and keeps the scan match.
  const KV sim = {{"map_image", hallWorld()}, {"resolution", "0.05"},   {"start_x", "16"},
                  {"start_y", "20"},          {"laser_fov_deg", "180"}, {"laser_rays", "181"},
                  {"laser_max_range", "40"},  {"range_sigma", "0.03"},  {"odo_a1", "0.05"},
                  {"odo_a2", "0.005"},        {"odo_a3", "5"},          {"odo_a4", "0.2"}};
  const auto frames = simulate(sim, {{22, 19}, {28, 21}, {34, 20}, {34, 14}}, 12);
  auto odo_fb = icpGraph({{"loop_closure", "false"}});
  auto lik_fb = icpGraph({{"loop_closure", "false"}, {"icp_low_goodness", "likelihood"}});
  const auto go = run(*odo_fb, frames), gl = run(*lik_fb, frames);
  ASSERT_EQ(go.edges.size(), gl.edges.size());
  ASSERT_GT(go.edges.size(), 20u);
  const std::size_t n = go.edges.size(), icp_o = countKind(go, asf::EdgeKind::ScanMatch),
                    icp_l = countKind(gl, asf::EdgeKind::ScanMatch);
  double err_o = 0, err_l = 0, rot_o = 0, rot_l = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const auto [to, ro] = edgeError(go, go.edges[k]);
    const auto [tl, rl] = edgeError(gl, gl.edges[k]);
    err_o += to / n, rot_o += ro / n, err_l += tl / n, rot_l += rl / n;
    // A kept scan match is a right one (to within the hall's weak direction: along a far wall).
    if (gl.edges[k].kind == asf::EdgeKind::ScanMatch) {
      EXPECT_LT(tl, 0.3) << "edge " << k;
      EXPECT_LT(rl, 0.02) << "edge " << k;
    }
  }
  std::cout << n << " edges; ICP edges " << icp_o << " (odometry fallback), " << icp_l
            << " (likelihood); mean edge error " << err_o << " m / " << rot_o << " rad vs " << err_l
            << " m / " << rot_l << " rad; mean node error " << meanNodeError(go) << " vs "
            << meanNodeError(gl) << " m\n";
  EXPECT_LT(icp_o, n / 2) << "the hall should defeat the goodness gate";
  EXPECT_GT(icp_l, n * 9 / 10);
  EXPECT_LT(rot_l, 0.5 * rot_o);
  EXPECT_LT(meanNodeError(gl), 0.5 * meanNodeError(go));
}

}  // namespace
