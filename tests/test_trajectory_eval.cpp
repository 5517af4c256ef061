// Trajectory accuracy (asf/evaluation/trajectory_eval.h) and `asf ate`: the alignment recovers a
// known rigid transform, the ATE equals hand-computed values, and bad files name their line.
#include <asf/errors.h>
#include <asf/evaluation/trajectory_eval.h>
#include <gtest/gtest.h>
#include <mrpt/core/bits_math.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "test_util.h"

using asf_test::has;
using mrpt::poses::CPose2D;
namespace fs = std::filesystem;

namespace {

fs::path tempFile(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / "asf_test_trajectory_eval";
  fs::create_directories(dir);
  std::ofstream(dir / name) << text;
  return dir / name;
}

std::vector<CPose2D> randomPath(std::mt19937& rng, int n) {
  std::normal_distribution<double> step(0.0, 0.3);
  std::vector<CPose2D> p{CPose2D()};
  for (int i = 1; i < n; ++i) p.push_back(p.back() + CPose2D(0.5, step(rng), step(rng)));
  return p;
}

}  // namespace

TEST(TrajectoryEval, AlignmentRecoversAKnownRigidTransform) {
  std::mt19937 rng(7);
  const auto truth = randomPath(rng, 50);
  const CPose2D T(3.0, -2.0, 0.7);
  std::vector<CPose2D> est;
  for (const auto& p : truth) est.push_back(CPose2D() - T + p);  // est = T^-1 * truth
  const CPose2D A = asf::evaluation::alignSE2(est, truth);
  EXPECT_NEAR(A.x(), T.x(), 1e-9);
  EXPECT_NEAR(A.y(), T.y(), 1e-9);
  EXPECT_NEAR(A.phi(), T.phi(), 1e-12);
  const auto r = asf::evaluation::evaluateMatched(est, truth);
  EXPECT_LT(r.ate_rmse_m, 1e-9);
  EXPECT_LT(r.rot_rmse_deg, 1e-9);
  // Without alignment the error is that of the transform itself.
  EXPECT_GT(asf::evaluation::evaluateMatched(est, truth, false).ate_rmse_m, 1.0);
}

TEST(TrajectoryEval, HandComputedErrors) {
  // Errors (0, +1) and (0, -1) on a straight line along x: the best rigid fit is the identity
  // (symmetric about the line), RMSE 1, heading errors 0.
  const std::vector<CPose2D> truth{CPose2D(0, 0, 0), CPose2D(2, 0, 0)};
  const std::vector<CPose2D> est{CPose2D(0, 1, 0), CPose2D(2, -1, 0)};
  const auto raw = asf::evaluation::evaluateMatched(est, truth, false);
  EXPECT_NEAR(raw.ate_rmse_m, 1.0, 1e-12);
  EXPECT_NEAR(raw.ate_max_m, 1.0, 1e-12);
  // Aligned: rotating the estimate by -45 degrees about its centre puts both on the x axis,
  // at (1 -+ sqrt(2), 0): errors |1 - sqrt(2)| each.
  const auto al = asf::evaluation::evaluateMatched(est, truth);
  EXPECT_NEAR(al.ate_rmse_m, std::sqrt(2.0) - 1, 1e-12);
  EXPECT_NEAR(al.alignment.phi(), M_PI / 4, 1e-12);
  EXPECT_NEAR(al.rot_rmse_deg, 45.0, 1e-9);
  ASSERT_EQ(al.errors_m.size(), 2u);
  EXPECT_NEAR(al.errors_m[0], std::sqrt(2.0) - 1, 1e-12);
}

TEST(TrajectoryEval, RelativePoseErrorByHand) {
  // A straight line of 1 m steps; the estimate's third step is 1.1 m: one pair off by 0.1 m.
  const std::vector<CPose2D> truth{CPose2D(0, 0, 0), CPose2D(1, 0, 0), CPose2D(2, 0, 0),
                                   CPose2D(3, 0, 0)};
  std::vector<CPose2D> est{CPose2D(0, 0, 0), CPose2D(1, 0, 0), CPose2D(2, 0, 0),
                           CPose2D(3.1, 0, 0)};
  auto r = asf::evaluation::relativePoseError(est, truth);
  EXPECT_EQ(r.pairs, 3u);
  EXPECT_NEAR(r.trans_rmse_m, std::sqrt(0.01 / 3), 1e-12);
  EXPECT_NEAR(r.trans_max_m, 0.1, 1e-12);
  EXPECT_NEAR(r.rot_rmse_deg, 0, 1e-12);
  // Over two steps both pairs that include the long step see it.
  r = asf::evaluation::relativePoseError(est, truth, 2);
  EXPECT_EQ(r.pairs, 2u);
  EXPECT_NEAR(r.trans_rmse_m, std::sqrt(0.01 / 2), 1e-12);
  // A heading error of 0.1 rad at pose 1 (position right): the first pair's motion turns by
  // 0.1 rad, and the second's, seen from the turned pose, goes 1 m at -0.1 rad.
  est = truth;
  est[1] = CPose2D(1, 0, 0.1);
  r = asf::evaluation::relativePoseError(est, truth);
  const double t2 = std::pow(std::cos(0.1) - 1, 2) + std::pow(std::sin(0.1), 2);
  EXPECT_NEAR(r.trans_rmse_m, std::sqrt(t2 / 3), 1e-12);
  EXPECT_NEAR(r.rot_rmse_deg, mrpt::RAD2DEG(std::sqrt(2 * 0.01 / 3)), 1e-9);
  EXPECT_THROW(asf::evaluation::relativePoseError(est, truth, 4), asf::Error);
  EXPECT_THROW(asf::evaluation::relativePoseError(est, truth, 0), asf::Error);
}

TEST(TrajectoryEval, RelativePoseErrorIgnoresTheFrameAndEarlierDrift) {
  std::mt19937 rng(5);
  const std::vector<CPose2D> truth = randomPath(rng, 50);
  // The whole estimate in another frame: no relative error at all, an ATE without alignment.
  std::vector<CPose2D> est;
  const CPose2D frame(3, -2, 0.7);
  for (const auto& p : truth) est.push_back(frame + p);
  EXPECT_LT(asf::evaluation::relativePoseError(est, truth).trans_rmse_m, 1e-9);
  EXPECT_GT(asf::evaluation::evaluateMatched(est, truth, false).ate_rmse_m, 1.0);
  // One wrong step (0.2 m sideways at pose 10, everything after it carried along): the ATE
  // sees it at every later pose, the RPE at the one pair that contains it.
  est = truth;
  for (std::size_t i = 10; i < est.size(); ++i)
    est[i] = truth[9] + CPose2D(0, 0.2, 0) + (truth[i] - truth[9]);
  const auto r = asf::evaluation::relativePoseError(est, truth);
  EXPECT_NEAR(r.trans_max_m, 0.2, 1e-9);
  EXPECT_NEAR(r.trans_rmse_m, 0.2 / std::sqrt(49.0), 1e-9);
}

TEST(TrajectoryEval, MatchesByTimeAndCountsUnmatched) {
  std::vector<asf::io::GroundTruthPose> gt;
  for (int i = 0; i <= 10; ++i) gt.push_back({100.0 + i, CPose2D(i, 0, 0)});
  // t = 100.5 interpolates to x = 0.5 (gaps of 1 s, max_gap 2 s); t = 99 and t = 200 are
  // outside the ground truth.
  const std::vector<asf::evaluation::TimedPose> est{
      {100.5, CPose2D(0.5, 0.2, 0)}, {103, CPose2D(3, 0.2, 0)}, {99, CPose2D()}, {200, CPose2D()}};
  const auto r = asf::evaluation::evaluateTrajectory(est, gt, 2.0, false);
  EXPECT_EQ(r.poses, 2u);
  EXPECT_EQ(r.unmatched, 2u);
  EXPECT_NEAR(r.ate_rmse_m, 0.2, 1e-9);
  ASSERT_EQ(r.times.size(), 2u);
  EXPECT_EQ(r.times[1], 103);
  EXPECT_TRUE(has(asf_test::errorOf<asf::Error>([&] {
                    asf::evaluation::evaluateTrajectory({{50, CPose2D()}}, gt);
                  }),
                  "no estimated pose has a ground-truth match"));
}

TEST(TrajectoryEval, ReadsTextAndRejectsBadLinesWithTheirNumber) {
  const auto ok =
      tempFile("ok.txt", "# comment\n% other comment\n\n1.5 1 2 0.1 extra\n2.5 3 4 0.2\n");
  const auto t = asf::evaluation::readTrajectory(ok.string());
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].t, 1.5);
  EXPECT_EQ(t[1].pose.y(), 4);
  const auto bad = tempFile("bad.txt", "1 2 3 4\n5 6 nan 8\n");
  const std::string msg =
      asf_test::errorOf<asf::InputError>([&] { asf::evaluation::readTrajectory(bad.string()); });
  EXPECT_TRUE(has(msg, "bad.txt:2")) << msg;
  EXPECT_TRUE(has(
      asf_test::errorOf<asf::InputError>([] { asf::evaluation::readTrajectory("/nonexistent/x"); }),
      "cannot open"));
}

TEST(TrajectoryEval, AteCommandAlignsAndWritesPerPoseErrors) {
  // Ground truth on a circle; the estimate is the same path turned and shifted, on a circle
  // 0.1 m wider: the aligned ATE is 0.1.
  std::ostringstream g, e;
  g << std::setprecision(17);
  e << std::setprecision(17);
  const CPose2D T(-1, 5, 2.0);
  for (int i = 0; i < 40; ++i) {
    const double a = 2 * M_PI * i / 40;  // a whole circle: the fit is the centre, exactly
    const CPose2D p(5 * std::cos(a), 5 * std::sin(a), a + M_PI / 2);
    g << 10 + i << ' ' << p.x() << ' ' << p.y() << ' ' << p.phi() << '\n';
    const CPose2D q = T + CPose2D(5.1 * std::cos(a), 5.1 * std::sin(a), a + M_PI / 2);
    e << 10 + i << ' ' << q.x() << ' ' << q.y() << ' ' << q.phi() << '\n';
  }
  const auto gf = tempFile("gt.txt", g.str()), ef = tempFile("est.txt", e.str());
  const auto errs = fs::temp_directory_path() / "asf_test_trajectory_eval" / "errors.txt";
  const auto r = asf_test::runHost(
      "ate " + ef.string() + " " + gf.string() + " --json -e " + errs.string(), false);
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["poses"], 40);
  EXPECT_NEAR(j["ate_rmse_m"].get<double>(), 0.1, 1e-9);
  EXPECT_LT(j["rot_rmse_deg"].get<double>(), 1e-6);
  std::ifstream ef2(errs);
  std::string line;
  std::getline(ef2, line);
  EXPECT_TRUE(has(line, "after SE(2) alignment")) << line;
  int n = 0;
  double t = 0, err = 0;
  while (ef2 >> t >> err) {
    EXPECT_NEAR(err, 0.1, 1e-6) << "pose at t = " << t;
    ++n;
  }
  EXPECT_EQ(n, 40);
  // A frame-index estimate needs --frame-times; a missing file is a clear error.
  const auto bad = asf_test::runHost("ate /nonexistent.txt " + gf.string());
  EXPECT_EQ(bad.code, 1);
  EXPECT_TRUE(has(bad.out, "/nonexistent.txt: cannot open trajectory")) << bad.out;
  // Issue 51, item 7: coordinates whose squares overflow give no "ATE RMSE inf m" and exit 0.
  const auto huge = tempFile("huge.txt", "10 0 0 0\n11 1e200 0 0\n12 2 0 0\n");
  const auto inf = asf_test::runHost("ate " + huge.string() + " " + gf.string());
  EXPECT_EQ(inf.code, 1) << inf.out;
  EXPECT_TRUE(has(inf.out, "huge.txt against")) << inf.out;
  EXPECT_TRUE(has(inf.out, "not a finite number")) << inf.out;
  EXPECT_FALSE(has(inf.out, "inf m")) << inf.out;
  // Issue 51, item 4: the per-pose errors to a full disk are an error, not exit 0.
  if (fs::is_character_file("/dev/full")) {
    const auto full = asf_test::runHost("ate " + ef.string() + " " + gf.string() + " -e /dev/full");
    EXPECT_EQ(full.code, 1) << full.out;
    EXPECT_TRUE(has(full.out, "/dev/full: cannot write the pose errors")) << full.out;
    EXPECT_TRUE(fs::is_character_file("/dev/full"));
  }
}
