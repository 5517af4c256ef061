// Monte-Carlo place recognition (place_recognition.h): a distinctive room is recognized, a
// featureless corridor is not (ICP slides along it), results are seeded, and the planner
// uses the Monte Carlo values.
#include <asf/planning/expected_uncertainty.h>
#include <asf/planning/place_recognition.h>
#include <asf/studies/recognition_figure.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <cmath>
#include <functional>

namespace {

/// A world of W x H metres whose walls are given by wall(x, y), and a pose graph whose nodes
/// are `poses` with the scans a 270-degree, 361-ray laser of `range` metres takes there.
asf::PoseGraph graphIn(double W, double H, const std::function<bool(double, double)>& wall,
                       const std::vector<mrpt::poses::CPose2D>& poses, double range) {
  mrpt::maps::COccupancyGridMap2D g(0, W, 0, H, 0.05);
  for (unsigned y = 0; y < g.getSizeY(); ++y)
    for (unsigned x = 0; x < g.getSizeX(); ++x)
      g.setCell(x, y, wall(g.idx2x(x), g.idx2y(y)) ? 0.0f : 1.0f);
  asf::PoseGraph pg;
  for (const auto& p : poses) {
    const asf::NodeId id = pg.addNode(p, 0);
    auto s = std::make_shared<mrpt::obs::CObservation2DRangeScan>();
    s->aperture = static_cast<float>(1.5 * M_PI);
    s->maxRange = static_cast<float>(range);
    g.laserScanSimulator(*s, p, 0.5f, 361);
    pg.nodes[id].scan = s;
  }
  return pg;
}

asf::PoseGraph room() {
  // 8 x 6 m room with an L-shaped pillar: corners everywhere, nothing to slide along.
  auto wall = [](double x, double y) {
    const bool border = x < 0.2 || y < 0.2 || x > 7.8 || y > 5.8;
    const bool pillar = (x > 3.0 && x < 3.6 && y > 2.0 && y < 4.0) || (x > 3.0 && x < 4.6 && y > 2.0 && y < 2.6);
    return border || pillar;
  };
  std::vector<mrpt::poses::CPose2D> poses;
  for (double x : {1.5, 2.5, 5.5, 6.5})
    for (double y : {1.2, 4.8}) poses.emplace_back(x, y, 0.3);
  return graphIn(8, 6, wall, poses, 10.0);
}

asf::PoseGraph corridor() {
  // 40 x 2 m corridor, nodes in the middle third: with a 6 m laser the ends are out of sight,
  // two parallel walls are all there is.
  auto wall = [](double, double y) { return y < 0.2 || y > 1.8; };
  std::vector<mrpt::poses::CPose2D> poses;
  for (double x = 14; x <= 26; x += 1.0) poses.emplace_back(x, 1.0, 0.0);
  return graphIn(40, 2, wall, poses, 6.0);
}

TEST(PlaceRecognition, DistinctiveRoomIsRecognizedAFeaturelessCorridorIsNot) {
  asf::planning::RecognitionMcOptions o;
  o.samples = 30;
  const asf::PoseGraph r = room();
  const asf::PoseGraph c = corridor();
  double p_room = 0, p_corr = 0;
  for (asf::NodeId n : {0u, 3u, 5u}) p_room += asf::planning::recognitionProbability(r, n, o) / 3;
  for (asf::NodeId n : {4u, 6u, 8u}) p_corr += asf::planning::recognitionProbability(c, n, o) / 3;
  RecordProperty("p_room", std::to_string(p_room));
  RecordProperty("p_corridor", std::to_string(p_corr));
  EXPECT_GT(p_room, 0.8);
  // Along the corridor nothing corrects the guess's x: about the share of guesses already
  // within success_xy of the node (0.1 of 0.3 m each way: 1/3), far below the room.
  EXPECT_LT(p_corr, 0.6);
  EXPECT_LT(p_corr + 0.3, p_room);
}

TEST(PlaceRecognition, SeededPerNodeAndDegenerateCases) {
  asf::planning::RecognitionMcOptions o;
  o.samples = 12;
  const asf::PoseGraph r = room();
  const double a = asf::planning::recognitionProbability(r, 2, o);
  EXPECT_EQ(asf::planning::recognitionProbability(r, 2, o), a) << "same seed, same node: same value";
  const double step = 1.0 / 12;
  EXPECT_NEAR(std::fmod(a, step), 0.0, 1e-9) << "a count of successes over 12 samples";
  // No scan, or nobody else to recognize the place against: 0.
  asf::PoseGraph alone = r;
  alone.nodes.resize(1);
  EXPECT_EQ(asf::planning::recognitionProbability(alone, 0, o), 0.0);
  asf::PoseGraph noscan = r;
  noscan.nodes[1].scan.reset();
  EXPECT_EQ(asf::planning::recognitionProbability(noscan, 1, o), 0.0);
  EXPECT_EQ(asf::planning::recognitionProbability(r, 999, o), 0.0);
}

TEST(PlaceRecognition, TrialHoldsTheSamplesBehindTheProbability) {
  asf::planning::RecognitionMcOptions o;
  o.samples = 16;
  const asf::PoseGraph c = corridor();
  const asf::planning::RecognitionTrial t = asf::planning::recognitionTrial(c, 6, o);
  EXPECT_EQ(t.p, asf::planning::recognitionProbability(c, 6, o)) << "the same draws";
  ASSERT_EQ(t.samples.size(), 16u);
  std::size_t ok = 0;
  for (const auto& s : t.samples) {
    ok += s.success;
    // Every guess inside the window around the node; a success within the thresholds.
    const auto& n = c.nodes[6].pose;
    if (s.aligned) {
      EXPECT_LE(std::abs(s.guess.x() - n.x()), o.half_x + 1e-12);
      EXPECT_LE(std::abs(s.guess.y() - n.y()), o.half_y + 1e-12);
      EXPECT_LE(std::abs(s.guess.phi() - n.phi()), o.half_phi + 1e-12);
    }
    const double dxy = std::hypot(s.result.x() - n.x(), s.result.y() - n.y());
    EXPECT_EQ(s.success, dxy <= o.success_xy &&
                             std::abs(mrpt::math::wrapToPi(s.result.phi() - n.phi())) <=
                                 o.success_phi);
  }
  EXPECT_DOUBLE_EQ(t.p, static_cast<double>(ok) / 16);
  EXPECT_FALSE(t.map_points.empty());
  EXPECT_FALSE(t.scan_points.empty());
  // The figure: one dot per sample in the error panel, the title, the probability.
  const std::string svg = asf::studies::recognitionScatterSvg(t, c.nodes[6], o, "corridor node 6");
  EXPECT_NE(svg.find("corridor node 6"), std::string::npos);
  EXPECT_NE(svg.find("p_recognition = " + std::to_string(ok) + " / 16"), std::string::npos);
  std::size_t dots = 0;
  for (std::size_t at = 0; (at = svg.find("r='3'", at)) != std::string::npos; ++at) ++dots;
  EXPECT_EQ(dots, 16u);
  // Thread count does not change the values.
  const auto one = asf::planning::recognitionProbabilities(c, o, 1);
  const auto two = asf::planning::recognitionProbabilities(c, o, 2);
  EXPECT_EQ(one, two);
  EXPECT_EQ(one[6], t.p);
}

TEST(PlaceRecognition, WrittenFileReadsBack) {
  const std::string f = testing::TempDir() + "/asf_recognition.txt";
  asf::planning::writeRecognitionProbabilities(f, {{0, 0.25}, {7, 1.0}});
  const auto back = asf::planning::readRecognitionProbabilities(f);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_DOUBLE_EQ(back.at(0), 0.25);
  EXPECT_DOUBLE_EQ(back.at(7), 1.0);
}

}  // namespace
