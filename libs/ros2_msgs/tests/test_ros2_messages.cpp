// The vendor-free ROS 2 conversions (asf/ros2/messages.h): analytic cases and round trips.
#include <asf/ros2/messages.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <cmath>
#include <limits>

using namespace asf::ros2;

TEST(Ros2Messages, StampsAndQuaternions) {
  const Stamp s = toStamp(12.000000123);
  EXPECT_EQ(s.sec, 12);
  EXPECT_EQ(s.nanosec, 123u);
  EXPECT_NEAR(toSeconds(toStamp(3.25)), 3.25, 1e-12);
  EXPECT_EQ(toStamp(-1).sec, 0);
  for (double yaw : {0.0, 0.3, -2.9, M_PI / 2, 3.1}) {
    const auto q = quaternionFromYaw(yaw);
    EXPECT_NEAR(yawFromQuaternion(q[0], q[1], q[2], q[3]), yaw, 1e-12) << yaw;
    // Not normalised: the same yaw.
    EXPECT_NEAR(yawFromQuaternion(2 * q[0], 2 * q[1], 2 * q[2], 2 * q[3]), yaw, 1e-12);
  }
  // 90 degrees about z: (0, 0, sin 45, cos 45).
  const auto q = quaternionFromYaw(M_PI / 2);
  EXPECT_NEAR(q[2], std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(q[3], std::sqrt(0.5), 1e-12);
}

TEST(Ros2Messages, TransformsRoundTrip) {
  const mrpt::poses::CPose3D p(1.0, -2.0, 0.3, 0.7, 0.1, -0.2);
  const mrpt::poses::CPose3D back = poseFromTransform(transformFromPose(p));
  EXPECT_NEAR((back.asVectorVal() - p.asVectorVal()).norm(), 0, 1e-12);
  const Transform t2 = transformFromPose(mrpt::poses::CPose2D(3, 4, -1.2));
  EXPECT_NEAR(yawFromQuaternion(t2.qx, t2.qy, t2.qz, t2.qw), -1.2, 1e-12);
  EXPECT_EQ(t2.tz, 0);
  Transform zero;  // an unset quaternion reads as no rotation
  zero.qw = 0;
  EXPECT_NEAR(poseFromTransform(zero).yaw(), 0, 1e-12);
}

TEST(Ros2Messages, TopicNames) {
  EXPECT_EQ(ddsTopic("/scan"), "rt/scan");
  EXPECT_EQ(ddsTopic("scan"), "rt/scan");
  EXPECT_EQ(ddsTopic("/navigate_to_pose/_action/status"), "rt/navigate_to_pose/_action/status");
  for (const char* bad : {"", "/", "/scan/", "a//b", "/sc an", "/1scan"})
    EXPECT_THROW(ddsTopic(bad), std::invalid_argument) << bad;
}

TEST(Ros2Messages, ScanRoundTripKeepsEveryRay) {
  mrpt::obs::CObservation2DRangeScan s;
  s.aperture = static_cast<float>(270 * M_PI / 180);
  s.rightToLeft = true;
  s.maxRange = 10;
  s.resizeScan(541);
  for (std::size_t i = 0; i < 541; ++i) {
    s.setScanRange(i, 0.5f + 0.01f * i);
    s.setScanRangeValidity(i, i % 7 != 0);
  }
  const LaserScan m = laserScanFromMrpt(s, toStamp(1.5), "laser");
  ASSERT_EQ(m.ranges.size(), 541u);
  EXPECT_TRUE(std::isinf(m.ranges[0]));
  EXPECT_NEAR(m.angle_min, -135 * M_PI / 180, 1e-6);
  EXPECT_NEAR(m.angle_max, 135 * M_PI / 180, 1e-6);
  const mrpt::poses::CPose3D mount(0.1, 0, 0.3, 0, 0, 0);
  const auto back = mrptFromLaserScan(m, mount, 1.5);
  ASSERT_EQ(back->getScanSize(), 541u);
  EXPECT_NEAR(back->sensorPose.yaw(), 0, 1e-6);
  EXPECT_NEAR(back->sensorPose.x(), 0.1, 1e-12);
  for (std::size_t i = 0; i < 541; ++i) {
    EXPECT_EQ(back->getScanRangeValidity(i), s.getScanRangeValidity(i)) << i;
    if (s.getScanRangeValidity(i)) {
      EXPECT_FLOAT_EQ(back->getScanRange(i), s.getScanRange(i));
    }
    EXPECT_NEAR(back->getScanAngle(i), s.getScanAngle(i), 1e-6) << i;
  }
}

TEST(Ros2Messages, AsymmetricAndClockwiseScansKeepTheirAngles) {
  for (float inc : {0.01f, -0.01f}) {
    LaserScan m;
    m.angle_min = inc > 0 ? -0.5f : 1.2f;  // not symmetric about x
    m.angle_increment = inc;
    m.range_min = 0.2f;
    m.range_max = 8;
    m.ranges = {1.0f, 0.1f, std::numeric_limits<float>::quiet_NaN(), 9.0f, 2.0f};
    for (int i = 0; i < 50; ++i) m.ranges.push_back(3.0f);
    const auto s = mrptFromLaserScan(m, mrpt::poses::CPose3D(), 0);
    ASSERT_EQ(s->getScanSize(), m.ranges.size());
    for (std::size_t i = 0; i < m.ranges.size(); ++i) {
      const double ros_angle = m.angle_min + static_cast<double>(i) * inc;
      const double mrpt_angle = s->sensorPose.yaw() + s->getScanAngle(i);
      EXPECT_NEAR(std::remainder(mrpt_angle - ros_angle, 2 * M_PI), 0, 1e-5) << i << " " << inc;
    }
    EXPECT_TRUE(s->getScanRangeValidity(0));
    EXPECT_FALSE(s->getScanRangeValidity(1));  // below range_min
    EXPECT_FALSE(s->getScanRangeValidity(2));  // NaN
    EXPECT_FALSE(s->getScanRangeValidity(3));  // beyond range_max
  }
  LaserScan one;
  one.ranges = {1.0f};
  one.angle_increment = 0.1f;
  one.range_max = 5;
  EXPECT_THROW(mrptFromLaserScan(one, {}, 0), std::invalid_argument);
  LaserScan zero_inc = one;
  zero_inc.ranges = {1.0f, 2.0f};
  zero_inc.angle_increment = 0;
  EXPECT_THROW(mrptFromLaserScan(zero_inc, {}, 0), std::invalid_argument);
}

TEST(Ros2Messages, OccupancyRoundTripCellByCell) {
  mrpt::maps::COccupancyGridMap2D g(-1.0f, 2.0f, -0.5f, 1.5f, 0.1f);
  for (int cy = 0; cy < static_cast<int>(g.getSizeY()); ++cy)
    for (int cx = 0; cx < static_cast<int>(g.getSizeX()); ++cx)
      g.setCell(cx, cy, (cx + cy) % 3 == 0 ? 0.5f : (cx % 2 ? 0.1f : 0.95f));
  const OccupancyGrid m = occupancyFromMrpt(g, toStamp(2), "map");
  EXPECT_EQ(m.width, g.getSizeX());
  EXPECT_EQ(m.height, g.getSizeY());
  EXPECT_NEAR(m.origin.tx, g.getXMin(), 1e-6);
  EXPECT_NEAR(m.origin.ty, g.getYMin(), 1e-6);
  // Cell (1, 0): cx odd, p(free) 0.1 -> 90 % occupied; cell (2, 0): p(free) 0.95 -> 5 % (to
  // MRPT's quantisation of the log-odds it stores).
  EXPECT_NEAR(m.data[1], 90, 1);
  EXPECT_NEAR(m.data[2], 5, 1);
  EXPECT_EQ(m.data[0], -1);
  const auto back = mrptFromOccupancy(m);
  ASSERT_EQ(back->getSizeX(), g.getSizeX());
  ASSERT_EQ(back->getSizeY(), g.getSizeY());
  EXPECT_NEAR(back->getXMin(), g.getXMin(), 1e-5);
  EXPECT_NEAR(back->getYMin(), g.getYMin(), 1e-5);
  for (int cy = 0; cy < static_cast<int>(g.getSizeY()); ++cy)
    for (int cx = 0; cx < static_cast<int>(g.getSizeX()); ++cx)
      EXPECT_NEAR(back->getCell(cx, cy), g.getCell(cx, cy), 0.011) << cx << "," << cy;
  OccupancyGrid bad = m;
  bad.data.pop_back();
  EXPECT_THROW(mrptFromOccupancy(bad), std::invalid_argument);
}

// Every cell of m against the grid read cell by cell through MRPT's own getCell (p(free)).
void expectSameCells(const OccupancyGrid& m, const mrpt::maps::COccupancyGridMap2D& g) {
  ASSERT_EQ(m.width, g.getSizeX());
  ASSERT_EQ(m.height, g.getSizeY());
  ASSERT_EQ(m.data.size(), std::size_t(m.width) * m.height);
  EXPECT_NEAR(m.origin.tx, g.getXMin(), 1e-6);
  EXPECT_NEAR(m.origin.ty, g.getYMin(), 1e-6);
  int wrong = 0;
  for (int cy = 0; cy < static_cast<int>(g.getSizeY()); ++cy)
    for (int cx = 0; cx < static_cast<int>(g.getSizeX()); ++cx)
      wrong += m.data[cy * m.width + cx] != occupancyValue(1.0f - g.getCell(cx, cy));
  EXPECT_EQ(wrong, 0);
}

TEST(Ros2Messages, OccupancyConverterRedoesChangedRowsOnly) {
  mrpt::maps::COccupancyGridMap2D g(-1.0f, 2.0f, -0.5f, 1.5f, 0.1f);
  OccupancyConverter c;
  expectSameCells(c.convert(g, toStamp(1), "map"), g);
  EXPECT_EQ(c.rowsConverted(), g.getSizeY());
  EXPECT_EQ(c.convert(g, toStamp(2), "map").stamp.sec, 2);
  EXPECT_EQ(c.rowsConverted(), 0u);
  // Cells of rows 3 and 7 change: those two rows are converted again, the rest kept.
  g.setCell(4, 3, 0.1f);
  g.setCell(0, 7, 0.9f);
  g.setCell(5, 7, 0.3f);
  expectSameCells(c.convert(g, toStamp(3), "map"), g);
  EXPECT_EQ(c.rowsConverted(), 2u);
  // Many changes, then a grid grown on every side (a new shape: every row again).
  unsigned state = 7;
  for (int k = 0; k < 200; ++k) {
    state = state * 1103515245u + 12345u;
    g.setCell(state % g.getSizeX(), (state >> 8) % g.getSizeY(), ((state >> 16) % 100) / 100.0f);
  }
  expectSameCells(c.convert(g, toStamp(4), "map"), g);
  g.resizeGrid(-2.0f, 3.0f, -1.5f, 2.5f, 0.5f, false);
  expectSameCells(c.convert(g, toStamp(5), "map"), g);
  EXPECT_EQ(c.rowsConverted(), g.getSizeY());
  g.setCell(1, 1, 0.05f);
  expectSameCells(c.convert(g, toStamp(6), "map"), g);
  EXPECT_EQ(c.rowsConverted(), 1u);
}

TEST(Ros2Messages, LoopbackConfigNamesLoopbackOnly) {
  const std::string xml = cycloneLoopbackXml(12);
  EXPECT_NE(xml.find("name=\"lo\""), std::string::npos);
  EXPECT_NE(xml.find("<AllowMulticast>false</AllowMulticast>"), std::string::npos);
  EXPECT_NE(xml.find("127.0.0.1"), std::string::npos);
  EXPECT_NE(xml.find("<MaxAutoParticipantIndex>12<"), std::string::npos);
}
