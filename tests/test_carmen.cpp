// The CARMEN converter (libs/io/src/carmen.cpp): a small exact log, PARAM lines, ODOM
// lines, ROBOTLASER1, bad lines, synthesized odometry, the quirks of real corrected logs
// (angles in radians, negative and constant timestamps), intel-corrected, the command.
#include <asf/errors.h>
#include <asf/io/rawlog_io.h>
#include <asf/io/carmen.h>
#include <gtest/gtest.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "convert_test_util.h"
#include "test_util.h"

namespace fs = std::filesystem;
namespace cv = asf::io;
using asf_test::errorOf;
using asf_test::has;
using asf_test::readFrames;
using asf_test::readText;
using asf_test::TempDir;
using asf_test::writeText;
using mrpt::poses::CPose2D;

namespace {

std::string ranges180(double base, int invalid_at = -1) {
  std::string s = "180";
  for (int i = 0; i < 180; ++i)
    s += " " + (i == invalid_at ? std::string("81.83")
                : i == 5        ? std::string("0")
                                : cv::fixed(base + 0.01 * i, 2));
  return s;
}

// Three FLASER lines (the third stamped before the second), ODOM lines, other messages.
std::string smallCarmen(const std::string& params = "") {
  return "# CARMEN Logfile\n"
         "# message formats defined: PARAM SYNC ODOM FLASER RLASER TRUEPOS\n" +
         params +
         "ODOM 0 0 0 0 0 0 10.0 host 10.0\n"
         "FLASER " +
         ranges180(1.0, 7) +
         " 1 2 0.5 1 2 0.5 10.5 host 10.5\n"
         "NEFF 12\n"
         "ODOM 0.1 0 0 0 0 0 10.6 host 10.6\n"
         "FLASER " +
         ranges180(2.0) +
         " 1.5 2 0.5 0.9 2.1 0.4 11.0 host 11.0\n"
         "TRUEPOS 1 2 3 4 5 6 11.1 host 11.1\n"
         "FLASER " +
         ranges180(3.0) + " 2 2.5 1 1 2.2 0.6 10.9 host 10.9\n";
}

cv::CarmenToRawlogOptions carmenOpts(const std::string& in, const std::string& out) {
  cv::CarmenToRawlogOptions o;
  o.input = in;
  o.output = out;
  return o;
}

}  // namespace

TEST(Carmen, SmallFlaserLogExactValues) {
  TempDir tmp;
  writeText(tmp / "s.log", smallCarmen());
  auto o = carmenOpts(tmp / "s.log", tmp / "s.rawlog");
  o.gt_output = tmp / "s.gt.txt";
  o.timestamps = cv::CarmenToRawlogOptions::Timestamps::Log;  // one of two steps goes back
  const auto rep = cv::carmenToRawlog(o);
  EXPECT_EQ(rep.lines, 9u);
  EXPECT_EQ(rep.scans, 3u);
  EXPECT_EQ(rep.odometry, 3u);  // from the FLASER lines
  EXPECT_EQ(rep.gt_poses, 3u);
  EXPECT_EQ(rep.rays, 180u);
  EXPECT_DOUBLE_EQ(rep.aperture_deg, 180.0);
  EXPECT_EQ(rep.laser_message, "FLASER");
  EXPECT_EQ(rep.raised_timestamps, 1u);
  EXPECT_EQ(rep.ignored.at("ODOM"), 2u);
  EXPECT_EQ(rep.ignored.at("NEFF"), 1u);
  EXPECT_EQ(rep.ignored.at("TRUEPOS"), 1u);

  const auto f = readFrames(tmp / "s.rawlog");
  ASSERT_EQ(f.size(), 3u);
  EXPECT_NEAR(f[0].timestamp, 10.5, 1e-9);
  EXPECT_NEAR(f[1].timestamp, 11.0, 1e-9);
  EXPECT_NEAR(f[2].timestamp, 11.000001, 1e-9);  // 10.9 moved just after 11.0
  const auto& s = *f[0].scan;
  EXPECT_EQ(s.sensorLabel, "FLASER");
  EXPECT_EQ(s.getScanSize(), 180u);
  EXPECT_FLOAT_EQ(s.aperture, static_cast<float>(M_PI));
  EXPECT_TRUE(s.rightToLeft);
  EXPECT_FLOAT_EQ(s.maxRange, 80.0f);
  EXPECT_FLOAT_EQ(s.getScanRange(0), 1.0f);
  EXPECT_FLOAT_EQ(s.getScanRange(179), 2.79f);
  EXPECT_FALSE(s.getScanRangeValidity(5));  // 0
  EXPECT_FALSE(s.getScanRangeValidity(7));  // 81.83: SICK "no echo"
  EXPECT_TRUE(s.getScanRangeValidity(6));
  EXPECT_DOUBLE_EQ(s.sensorPose.x(), 0.0);
  // Odometry from the FLASER odom fields: (0.9, 2.1, 0.4) seen from (1, 2, 0.5).
  const CPose2D d1 = CPose2D(0.9, 2.1, 0.4) - CPose2D(1, 2, 0.5);
  EXPECT_NEAR(f[1].odometry.x(), d1.x(), 1e-12);
  EXPECT_NEAR(f[1].odometry.y(), d1.y(), 1e-12);
  EXPECT_NEAR(f[1].odometry.phi(), -0.1, 1e-12);

  const auto gt = asf::io::readGroundTruth(tmp / "s.gt.txt");
  ASSERT_EQ(gt.size(), 3u);
  EXPECT_NEAR(gt[0].t, 10.5, 1e-9);
  EXPECT_DOUBLE_EQ(gt[0].pose.x(), 1.0);
  EXPECT_DOUBLE_EQ(gt[0].pose.y(), 2.0);
  EXPECT_DOUBLE_EQ(gt[0].pose.phi(), 0.5);
  EXPECT_DOUBLE_EQ(gt[1].pose.x(), 1.5);
  EXPECT_NEAR(gt[2].t, 11.000001, 1e-9);
  EXPECT_DOUBLE_EQ(gt[2].pose.phi(), 1.0);
}

TEST(Carmen, ParamsApertureOffsetAndRange) {
  TempDir tmp;
  // MRPT's rule: n times laser_front_laser_resolution (0.5 deg by default there, so 180 rays
  // come out as 90 degrees).
  writeText(tmp / "res.log", smallCarmen("PARAM laser_front_laser_resolution 0.5 nohost 0\n"));
  EXPECT_DOUBLE_EQ(cv::carmenToRawlog(carmenOpts(tmp / "res.log", tmp / "a.rawlog")).aperture_deg,
                   90.0);
  auto o = carmenOpts(tmp / "res.log", tmp / "a.rawlog");
  o.fov_deg = 180;  // the command line wins
  EXPECT_DOUBLE_EQ(cv::carmenToRawlog(o).aperture_deg, 180.0);
  writeText(tmp / "fov.log", smallCarmen("PARAM laser_front_laser_fov 90 nohost 0\n"
                                         "PARAM laser_front_laser_resolution 0.5 nohost 0\n"));
  const auto rf = cv::carmenToRawlog(carmenOpts(tmp / "fov.log", tmp / "a.rawlog"));
  EXPECT_DOUBLE_EQ(rf.aperture_deg, 90.0);
  for (const auto& w : rf.warnings)  // 90 deg and 180 x 0.5 deg agree
    EXPECT_FALSE(has(w, "PARAM")) << w;

  // Laser 0.2 m ahead of the robot centre; maximum range 2.5 m.
  writeText(tmp / "off.log", smallCarmen("PARAM robot_frontlaser_offset 0.2 nohost 0\n"
                                         "PARAM robot_front_laser_max 2.5 nohost 0\n"));
  o = carmenOpts(tmp / "off.log", tmp / "off.rawlog");
  o.gt_output = tmp / "off.gt.txt";
  cv::carmenToRawlog(o);
  const auto f = readFrames(tmp / "off.rawlog");
  ASSERT_EQ(f.size(), 3u);
  EXPECT_DOUBLE_EQ(f[0].scan->sensorPose.x(), 0.2);
  EXPECT_FLOAT_EQ(f[0].scan->maxRange, 2.5f);
  EXPECT_TRUE(f[0].scan->getScanRangeValidity(149));   // 2.49 m
  EXPECT_FALSE(f[0].scan->getScanRangeValidity(150));  // 2.50 m
  const auto gt = asf::io::readGroundTruth(tmp / "off.gt.txt");
  EXPECT_NEAR(gt[0].pose.x(), 1 - 0.2 * std::cos(0.5), 1e-9);
  EXPECT_NEAR(gt[0].pose.y(), 2 - 0.2 * std::sin(0.5), 1e-9);
}

TEST(Carmen, OdomLinesMode) {
  TempDir tmp;
  writeText(tmp / "s.log", smallCarmen());
  auto o = carmenOpts(tmp / "s.log", tmp / "s.rawlog");
  o.odometry = cv::CarmenToRawlogOptions::Odometry::OdomLines;
  const auto rep = cv::carmenToRawlog(o);
  EXPECT_EQ(rep.odometry, 2u);
  EXPECT_EQ(rep.ignored.count("ODOM"), 0u);
  const auto f = readFrames(tmp / "s.rawlog");
  ASSERT_EQ(f.size(), 3u);
  // Scan 1 at 11.0: last ODOM at or before it is (0.1, 0, 0); scan 0 had (0, 0, 0).
  EXPECT_NEAR(f[1].odometry.x(), 0.1, 1e-12);
  EXPECT_NEAR(f[2].odometry.norm(), 0.0, 1e-12);

  // ODOM lines going back in time are dropped and counted.
  writeText(tmp / "b.log", "FLASER " + ranges180(1.0) + " 1 2 0.5 1 2 0.5 10.5 host 10.5\n" +
                               "ODOM 1 2 0.5 0 0 0 0 pippo 0\nODOM 1 2 0.5 0 0 0 10.6 h 10.6\n");
  o = carmenOpts(tmp / "b.log", tmp / "b.rawlog");
  o.odometry = cv::CarmenToRawlogOptions::Odometry::OdomLines;
  const auto rb = cv::carmenToRawlog(o);
  EXPECT_EQ(rb.odom_dropped, 1u);
  EXPECT_EQ(rb.odometry, 1u);
}

TEST(Carmen, RobotLaser1Lines) {
  TempDir tmp;
  // 181 readings from -90 deg, 1 deg apart, max 50 m, 2 remissions; laser 0.1 m ahead of a
  // robot at (3, 4, 90 deg).
  std::string ranges = "181";
  for (int i = 0; i < 181; ++i) ranges += i == 10 ? " 60" : " 1.5";
  const auto line = [&](double t, double y) {
    std::ostringstream s;
    s.precision(10);
    s << "ROBOTLASER1 0 -1.5707963268 3.1415926536 0.0174532925 50 0.01 0 " << ranges
      << " 2 0.5 0.6 3 " << y + 0.1 << " 1.5707963268 3 " << y << " 1.5707963268 0.2 0 0.5 0.3 0 "
      << t << " host " << t << "\n";
    return s.str();
  };
  writeText(tmp / "r.log", line(5.0, 4.0) + line(5.5, 4.2) + "FLASER " + ranges180(1.0) +
                               " 1 2 0.5 1 2 0.5 10.5 host 10.5\n");
  auto o = carmenOpts(tmp / "r.log", tmp / "r.rawlog");
  o.gt_output = tmp / "r.gt.txt";
  const auto rep = cv::carmenToRawlog(o);
  EXPECT_EQ(rep.laser_message, "ROBOTLASER1");
  EXPECT_EQ(rep.scans, 2u);
  EXPECT_EQ(rep.ignored.at("FLASER"), 1u);  // the other laser message: not mixed in
  EXPECT_EQ(rep.rays, 181u);
  EXPECT_NEAR(rep.aperture_deg, 180.0, 1e-6);
  const auto f = readFrames(tmp / "r.rawlog");
  ASSERT_EQ(f.size(), 2u);
  const auto& s = *f[0].scan;
  EXPECT_NEAR(s.sensorPose.x(), 0.1, 1e-9);
  EXPECT_NEAR(s.sensorPose.y(), 0.0, 1e-9);
  EXPECT_NEAR(s.sensorPose.yaw(), 0.0, 1e-9);
  EXPECT_FLOAT_EQ(s.maxRange, 50.0f);
  EXPECT_FALSE(s.getScanRangeValidity(10));
  EXPECT_TRUE(s.getScanRangeValidity(11));
  EXPECT_NEAR(f[1].odometry.x(), 0.2, 1e-9);  // robot moved 0.2 m ahead (heading +y)
  EXPECT_NEAR(f[1].odometry.y(), 0.0, 1e-9);
  const auto gt = asf::io::readGroundTruth(tmp / "r.gt.txt");
  ASSERT_EQ(gt.size(), 2u);
  EXPECT_NEAR(gt[1].pose.y(), 4.2, 1e-9);
}

TEST(Carmen, BadLinesAndNonLogs) {
  TempDir tmp;
  std::string text = smallCarmen();
  // Line 7 (the second FLASER) loses its last range.
  const auto p = text.find("FLASER", text.find("FLASER 180") + 1);
  const auto q = text.find(" 3.79 ", p);
  ASSERT_NE(q, std::string::npos);
  text.erase(q, 5);
  writeText(tmp / "bad.log", text);
  auto o = carmenOpts(tmp / "bad.log", tmp / "bad.rawlog");
  const std::string e = errorOf<asf::InputError>([&] { cv::carmenToRawlog(o); });
  EXPECT_TRUE(has(e, tmp / "bad.log:7: FLASER with 180 readings has 191 fields")) << e;
  EXPECT_TRUE(has(e, "got 190")) << e;
  EXPECT_FALSE(fs::exists(tmp / "bad.rawlog"));
  o.skip_bad_lines = true;
  const auto rep = cv::carmenToRawlog(o);
  EXPECT_EQ(rep.bad_lines, 1u);
  EXPECT_EQ(rep.first_bad_line, 7u);
  EXPECT_EQ(rep.scans, 2u);

  writeText(tmp / "nolaser.log", "PARAM a b\nODOM 0 0 0 0 0 0 1 h 1\n");
  EXPECT_TRUE(has(errorOf<asf::InputError>([&] {
                    cv::carmenToRawlog(carmenOpts(tmp / "nolaser.log", tmp / "x.rawlog"));
                  }),
                  "no FLASER or ROBOTLASER1 line"));
  writeText(tmp / "badparam.log", "PARAM robot_front_laser_max lots\n");
  EXPECT_TRUE(has(errorOf<asf::InputError>([&] {
                    cv::carmenToRawlog(carmenOpts(tmp / "badparam.log", tmp / "x.rawlog"));
                  }),
                  "badparam.log:1: PARAM robot_front_laser_max: value 'lots' is not a number"));
}

TEST(Carmen, SyntheticOdometryIsSeededAndDeterministic) {
  TempDir tmp;
  writeText(tmp / "s.log", smallCarmen());
  auto o = carmenOpts(tmp / "s.log", tmp / "a.rawlog");
  o.odometry = cv::CarmenToRawlogOptions::Odometry::Synthetic;
  o.seed = 5;
  cv::carmenToRawlog(o);
  o.output = tmp / "b.rawlog";
  cv::carmenToRawlog(o);
  o.output = tmp / "c.rawlog";
  o.seed = 6;
  cv::carmenToRawlog(o);
  EXPECT_EQ(readText(tmp / "a.rawlog"), readText(tmp / "b.rawlog"));
  const auto a = readFrames(tmp / "a.rawlog"), c = readFrames(tmp / "c.rawlog");
  ASSERT_EQ(a.size(), 3u);
  EXPECT_NE(a[1].odometry.x(), c[1].odometry.x());
  // Noise around the logged increment (0.5 m ahead at heading 0.5 rad, no turn).
  const CPose2D d = CPose2D(1.5, 2, 0.5) - CPose2D(1, 2, 0.5);
  EXPECT_NEAR(a[1].odometry.x(), d.x(), 0.1);
  EXPECT_NEAR(a[1].odometry.y(), d.y(), 0.1);
  EXPECT_GT(std::abs(a[1].odometry.x() - d.x()) + std::abs(a[1].odometry.y() - d.y()), 0);
}

// ------------------------------------------------- quirks of the real corrected logs

namespace {
/// True if one of the report's warnings contains `text` (else prints them all).
::testing::AssertionResult warned(const cv::CarmenToRawlogReport& r, const std::string& text) {
  std::string all;
  for (const auto& w : r.warnings) {
    if (has(w, text)) return ::testing::AssertionSuccess();
    all += "\n  " + w;
  }
  return ::testing::AssertionFailure()
         << "no warning contains \"" << text << "\"; warnings:" << all;
}

/// A FLASER line at x (y = 0, heading 0) stamped `stamp` (its text, as in the log).
std::string flaser(double x, const std::string& stamp) {
  std::ostringstream s;
  s << "FLASER " << ranges180(2.0) << " " << x << " 0 0 " << x << " 0 0 " << stamp << " pippo "
    << stamp << "\n";
  return s.str();
}
}  // namespace

TEST(CarmenQuirks, FovInRadiansIsReadAsRadiansWithAWarning) {
  TempDir tmp;
  // csail-corrected: "PARAM laser_front_laser_fov 3.14159" (CARMEN's unit is degrees).
  writeText(tmp / "rad.log", smallCarmen("PARAM laser_front_laser_fov 3.14159 b21 1.0\n"));
  const auto r = cv::carmenToRawlog(carmenOpts(tmp / "rad.log", tmp / "a.rawlog"));
  EXPECT_NEAR(r.aperture_deg, 179.9998, 1e-3);
  EXPECT_TRUE(warned(r, tmp / "rad.log:3: PARAM laser_front_laser_fov 3.14159 is implausible "
                              "in degrees (CARMEN's unit): read as radians, 180 deg"));
  // A resolution in radians: 180 rays 0.0087266 deg apart would span 1.6 deg.
  writeText(tmp / "res.log", smallCarmen("PARAM laser_front_laser_resolution 0.00872665 h 0\n"));
  const auto rr = cv::carmenToRawlog(carmenOpts(tmp / "res.log", tmp / "a.rawlog"));
  EXPECT_NEAR(rr.aperture_deg, 90.0, 1e-4);
  EXPECT_TRUE(warned(rr,
                     "res.log:3: PARAM laser_front_laser_resolution 0.00872665 deg would "
                     "put 180 rays in 1.5708 deg: read as radians"));
  // Nonsense is ignored, and a fov the resolution contradicts is said.
  writeText(tmp / "big.log", smallCarmen("PARAM laser_front_laser_fov 500 h 0\n"));
  const auto rb = cv::carmenToRawlog(carmenOpts(tmp / "big.log", tmp / "a.rawlog"));
  EXPECT_DOUBLE_EQ(rb.aperture_deg, 180.0);
  EXPECT_TRUE(warned(rb,
                     "big.log:3: PARAM laser_front_laser_fov 500 is not a field of view in "
                     "(0, 360] deg: ignored"));
  writeText(tmp / "two.log", smallCarmen("PARAM laser_front_laser_fov 180 h 0\n"
                                         "PARAM laser_front_laser_resolution 0.5 h 0\n"));
  const auto rt = cv::carmenToRawlog(carmenOpts(tmp / "two.log", tmp / "a.rawlog"));
  EXPECT_DOUBLE_EQ(rt.aperture_deg, 180.0);
  EXPECT_TRUE(warned(rt,
                     "two.log:3: PARAM laser_front_laser_fov (180 deg) and "
                     "laser_front_laser_resolution (0.5 deg x 180 rays = 90 deg) disagree: "
                     "the fov is used"));
}

TEST(CarmenQuirks, NegativeTimestampsAreStampedByOrderOrRejected) {
  TempDir tmp;
  // infinite-corridor-corrected: negative stamps, then 4294967296 (a wrapped -1) for all.
  writeText(tmp / "neg.log", flaser(1, "-0.445999") + flaser(2, "-0.913") +
                                 flaser(3, "4.29497e+09") + flaser(4, "4.29497e+09"));
  auto o = carmenOpts(tmp / "neg.log", tmp / "a.rawlog");
  o.gt_output = tmp / "a.gt.txt";
  const auto r = cv::carmenToRawlog(o);
  EXPECT_EQ(r.scans, 4u);
  EXPECT_TRUE(r.stamped_by_order);
  EXPECT_EQ(r.stamps_bad, 2u);
  EXPECT_EQ(r.stamps_not_increasing, 1u);
  EXPECT_DOUBLE_EQ(r.scan_period_s, 1.0) << "no steady step to take";
  EXPECT_EQ(r.raised_timestamps, 0u);
  EXPECT_EQ(r.warnings.size(), 1u);
  EXPECT_TRUE(warned(r,
                     "neg.log: of 4 laser timestamps, 2 are not a time in seconds (first: "
                     "line 1, '-0.445999'), 1 are not after the one before: scans stamped "
                     "from the log's order, 1 s apart"));
  const auto f = readFrames(tmp / "a.rawlog");
  ASSERT_EQ(f.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(f[i].timestamp, i + 1.0, 1e-9);
  const auto gt = asf::io::readGroundTruth(tmp / "a.gt.txt");
  ASSERT_EQ(gt.size(), 4u);
  EXPECT_NEAR(gt[3].t, 4.0, 1e-9) << "the ground truth carries the same stamps";

  o.timestamps = cv::CarmenToRawlogOptions::Timestamps::Log;  // as the log says: refused
  const std::string e = errorOf<asf::InputError>([&] { cv::carmenToRawlog(o); });
  EXPECT_TRUE(has(e, "neg.log:1: ipc_timestamp '-0.445999' is not a time in seconds")) << e;
}

TEST(CarmenQuirks, ConstantTimestampsAreStampedByOrder) {
  TempDir tmp;
  // orebro-corrected: every laser line stamped 0; csail: 1.13486e+09 (6 digits) for all.
  writeText(tmp / "c.log", flaser(1, "1.13486e+09") + "ODOM 0 0 0 0 0 0 5 h 5\n" +
                               flaser(2, "1.13486e+09") + flaser(3, "1.13486e+09"));
  auto o = carmenOpts(tmp / "c.log", tmp / "a.rawlog");
  o.scan_period_s = 0.2;
  o.odometry = cv::CarmenToRawlogOptions::Odometry::OdomLines;
  const auto r = cv::carmenToRawlog(o);
  EXPECT_TRUE(r.stamped_by_order);
  EXPECT_EQ(r.stamps_bad, 0u);
  EXPECT_EQ(r.stamps_not_increasing, 2u);
  EXPECT_DOUBLE_EQ(r.scan_period_s, 0.2);
  EXPECT_EQ(r.odometry, 1u);
  EXPECT_EQ(r.odom_dropped, 0u) << "ODOM lines keep their place in the log";
  const auto recs = asf_test::readFrames(tmp / "a.rawlog");
  ASSERT_EQ(recs.size(), 3u);
  EXPECT_NEAR(recs[0].timestamp, 0.2, 1e-9);
  EXPECT_NEAR(recs[1].timestamp, 0.4, 1e-9);
  EXPECT_NEAR(recs[2].timestamp, 0.6, 1e-9);

  // As the log says: every scan after the first raised to 1 us after the one before, counted.
  o.timestamps = cv::CarmenToRawlogOptions::Timestamps::Log;
  o.odometry = cv::CarmenToRawlogOptions::Odometry::Laser;
  const auto rl = cv::carmenToRawlog(o);
  EXPECT_FALSE(rl.stamped_by_order);
  EXPECT_EQ(rl.raised_timestamps, 2u);
  EXPECT_TRUE(rl.warnings.empty());

  // A steady log keeps its stamps; ordered on request, the median step is the period.
  writeText(tmp / "s.log",
            flaser(1, "10.0") + flaser(2, "10.5") + flaser(3, "11.0") + flaser(4, "12.0"));
  o = carmenOpts(tmp / "s.log", tmp / "s.rawlog");
  EXPECT_FALSE(cv::carmenToRawlog(o).stamped_by_order);
  EXPECT_NEAR(readFrames(tmp / "s.rawlog")[3].timestamp, 12.0, 1e-9);
  o.timestamps = cv::CarmenToRawlogOptions::Timestamps::Order;
  const auto ro = cv::carmenToRawlog(o);
  EXPECT_TRUE(ro.stamped_by_order);
  EXPECT_DOUBLE_EQ(ro.scan_period_s, 0.5);
  EXPECT_TRUE(ro.warnings.empty()) << "asked for: nothing to warn about";
  EXPECT_NEAR(readFrames(tmp / "s.rawlog")[3].timestamp, 2.0, 1e-9);
}

TEST(CarmenRealData, IntelCorrectedWithSyntheticOdometryFollowsTheModel) {
  const std::string log = ASF_TEST_SHARED_DIR "/datasets/carmen/intel-corrected.log.gz";
  if (!fs::exists(log)) GTEST_SKIP() << "../shared is not available here (" << log << ")";
  TempDir tmp;
  auto o = carmenOpts(log, tmp / "intel.rawlog.gz");
  o.gt_output = tmp / "intel.gt.txt";
  o.odometry = cv::CarmenToRawlogOptions::Odometry::Synthetic;
  o.seed = 42;
  const auto rep = cv::carmenToRawlog(o);
  EXPECT_EQ(rep.lines, 16365u);
  EXPECT_EQ(rep.scans, 910u);
  EXPECT_EQ(rep.rays, 180u);
  EXPECT_DOUBLE_EQ(rep.aperture_deg, 180.0);
  EXPECT_EQ(rep.raised_timestamps, 4u);
  EXPECT_EQ(rep.ignored.at("ODOM"), 14541u);

  const auto frames = readFrames(tmp / "intel.rawlog.gz");
  const auto gt = asf::io::readGroundTruth(tmp / "intel.gt.txt");
  ASSERT_EQ(frames.size(), 910u);
  ASSERT_EQ(gt.size(), 910u);
  std::size_t invalid = 0;
  for (const auto& f : frames) {
    ASSERT_EQ(f.scan->getScanSize(), 180u);
    EXPECT_FLOAT_EQ(f.scan->aperture, static_cast<float>(M_PI));
    for (std::size_t i = 0; i < 180; ++i) invalid += !f.scan->getScanRangeValidity(i);
  }
  EXPECT_EQ(invalid, 4172u);  // the 81.83 m "no echo" readings

  // Noise of each increment, whitened with the model's covariance of the true increment:
  // N(0, I) if the synthesis follows the model.
  const auto whitenedMoments = [&](const asf::mapping::OdometryNoiseModel& m) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d sq = Eigen::Matrix3d::Zero();
    for (std::size_t k = 1; k < frames.size(); ++k) {
      const CPose2D d = gt[k].pose - gt[k - 1].pose;
      const CPose2D& n = frames[k].odometry;
      const Eigen::Vector3d e(n.x() - d.x(), n.y() - d.y(),
                              mrpt::math::wrapToPi(n.phi() - d.phi()));
      const Eigen::Vector3d w = m.covariance(d).llt().matrixL().solve(e);
      sum += w;
      sq += w * w.transpose();
    }
    const double n = static_cast<double>(frames.size() - 1);
    const Eigen::Vector3d mean = sum / n;
    return std::make_pair(mean, Eigen::Matrix3d(sq / n - mean * mean.transpose()));
  };
  const double n = 909;
  const auto [mean, cov] = whitenedMoments(o.model);
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(std::abs(mean[i]), 4 / std::sqrt(n)) << "component " << i;
    EXPECT_NEAR(cov(i, i), 1.0, 4 * std::sqrt(2 / n)) << "component " << i;
    for (int j = 0; j < i; ++j) EXPECT_LT(std::abs(cov(i, j)), 4 / std::sqrt(n)) << i << j;
  }
  // The check has power: a model with twice the spread sees a quarter of the variance.
  asf::mapping::OdometryNoiseModel wide = o.model;
  wide.a1 *= 2;
  wide.a2 *= 2;
  wide.a3 *= 2;
  wide.a4 *= 2;
  wide.min_std_xy *= 2;
  wide.min_std_phi_deg *= 2;
  const auto wide_cov = whitenedMoments(wide).second;
  for (int i = 0; i < 3; ++i) EXPECT_LT(wide_cov(i, i), 0.5) << "component " << i;
}

// --------------------------------------------------------------------- the command

TEST(CarmenCommand, ExitCodesAndMessages) {
  TempDir tmp;
  writeText(tmp / "s.log", smallCarmen());
  auto r = asf_test::runHost("carmen2rawlog -q --timestamps log -i " + tmp / "s.log" + " -o " +
                             tmp / "s.rawlog" + " --gt " + tmp / "s.gt.txt");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "3 scans (FLASER, 180 rays over 180 deg)")) << r.out;
  EXPECT_TRUE(has(r.out, "1 scans stamped before the previous record")) << r.out;
  EXPECT_EQ(readFrames(tmp / "s.rawlog").size(), 3u);
  r = asf_test::runHost("carmen2rawlog -i " + tmp / "s.log");  // no -o
  EXPECT_EQ(r.code, 2) << r.out;
  r = asf_test::runHost("carmen2rawlog --synth-odometry --odom-lines -i " + tmp / "s.log" +
                        " -o x.rawlog");
  EXPECT_EQ(r.code, 2) << r.out;
  writeText(tmp / "bad.log", "FLASER 3 1 2\n");
  r = asf_test::runHost("carmen2rawlog -i " + tmp / "bad.log" + " -o " + tmp / "b.rawlog");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_TRUE(has(r.out, "bad.log:1: FLASER with 3 readings has 14 fields")) << r.out;

  // The quirks are said, not silently fixed: warnings on stderr, the policy on stdout.
  writeText(tmp / "q.log", "PARAM laser_front_laser_fov 3.14159 h 0\n" + flaser(1, "5") +
                               flaser(2, "5") + flaser(3, "5"));
  r = asf_test::runHost("carmen2rawlog -q -i " + tmp / "q.log" + " -o " + tmp / "q.rawlog");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "warning: " + tmp / "q.log:1: PARAM laser_front_laser_fov 3.14159 is "
                                             "implausible in degrees"))
      << r.out;
  EXPECT_TRUE(has(r.out, "180 rays over 180 deg")) << r.out;
  EXPECT_TRUE(has(r.out, "scans stamped from the log's order, 1 s apart")) << r.out;
  r = asf_test::runHost("carmen2rawlog -q --timestamps sometimes -i " + tmp / "q.log" + " -o " +
                        tmp / "q.rawlog");
  EXPECT_EQ(r.code, 2) << r.out;
  r = asf_test::runHost("carmen2rawlog -q --scan-period -1 -i " + tmp / "q.log" + " -o " +
                        tmp / "q.rawlog");
  EXPECT_EQ(r.code, 2) << r.out;
}

// A full disk (/dev/full behind a link) is an error naming the output, the link and the device
// stay what they were, and a conversion that failed keeps the ground truth written before.
TEST(CarmenCommand, AFullDiskIsAnErrorAndKeepsWhatWasThere) {
  if (!fs::is_character_file("/dev/full")) GTEST_SKIP() << "no /dev/full on this machine";
  TempDir tmp;
  writeText(tmp / "s.log", smallCarmen());
  fs::create_symlink("/dev/full", tmp / "full.rawlog");
  writeText(tmp / "old.gt.txt", "# the previous conversion's ground truth\n");
  auto r = asf_test::runHost("carmen2rawlog -q -i " + tmp / "s.log" + " -o " + tmp / "full.rawlog" +
                             " --gt " + tmp / "old.gt.txt");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_TRUE(has(r.out, tmp / "full.rawlog" + ": write failed (disk full")) << r.out;
  EXPECT_TRUE(fs::is_symlink(tmp / "full.rawlog"));
  EXPECT_TRUE(fs::is_character_file("/dev/full")) << "/dev/full was replaced by a file";
  EXPECT_EQ(readText(tmp / "old.gt.txt"), "# the previous conversion's ground truth\n");
  EXPECT_FALSE(fs::exists(tmp / "old.gt.txt.tmp"));
  // The ground truth to the full disk, the rawlog fine: an error too.
  r = asf_test::runHost("carmen2rawlog -q -i " + tmp / "s.log" + " -o " + tmp / "s.rawlog" +
                        " --gt " + tmp / "full.rawlog");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
}
