// The live source's DDS-free state (live_core.h): pose interpolation, transform chains, goal
// outcomes through an action's status list, the scan queue.
#include <gtest/gtest.h>

#include "../live_core.h"

using namespace asf::ros2live;
using mrpt::poses::CPose2D;
using mrpt::poses::CPose3D;

TEST(LiveCore, PoseHistoryInterpolatesOnSE2) {
  PoseHistory h;
  EXPECT_FALSE(h.at(0, 1).has_value());
  ASSERT_TRUE(h.add(1.0, CPose2D(0, 0, 0)));
  ASSERT_TRUE(h.add(2.0, CPose2D(1, 0, M_PI / 2)));
  EXPECT_FALSE(h.add(1.5, CPose2D()));  // older than the newest
  const auto mid = h.at(1.5, 0);
  ASSERT_TRUE(mid);
  // Half of the increment (1, 0, 90 deg) applied at the first pose.
  EXPECT_NEAR(mid->x(), 0.5, 1e-12);
  EXPECT_NEAR(mid->phi(), M_PI / 4, 1e-12);
  EXPECT_TRUE(h.at(2.05, 0.1).has_value());
  EXPECT_FALSE(h.at(2.2, 0.1).has_value());
  EXPECT_FALSE(h.at(0.5, 0.1).has_value());
  PoseHistory small(3);
  for (int i = 0; i < 10; ++i) small.add(i, CPose2D(i, 0, 0));
  EXPECT_FALSE(small.at(5.0, 0.5).has_value());  // forgotten
  EXPECT_NEAR(small.at(8.5, 0)->x(), 8.5, 1e-12);
}

TEST(LiveCore, TransformChainsToTheRobotFrame) {
  TransformTree t;
  t.set("base_footprint", "base_link", CPose3D(0, 0, 0.1, 0, 0, 0));
  t.set("base_link", "base_scan", CPose3D(-0.05, 0, 0.2, M_PI, 0, 0));
  const auto m = t.lookup("base_footprint", "base_scan");
  ASSERT_TRUE(m);
  EXPECT_NEAR(m->x(), -0.05, 1e-12);
  EXPECT_NEAR(m->z(), 0.3, 1e-12);
  EXPECT_NEAR(std::abs(m->yaw()), M_PI, 1e-12);
  EXPECT_FALSE(t.lookup("odom", "base_scan").has_value());
  EXPECT_TRUE(t.lookup("base_scan", "base_scan").has_value());
  EXPECT_NE(t.describe().find("base_link -> base_scan"), std::string::npos);
  t.set("a", "b", CPose3D());  // a cycle ends, it does not hang
  t.set("b", "a", CPose3D());
  EXPECT_FALSE(t.lookup("base_link", "a").has_value());
}

namespace {
GoalStatusEntry entry(std::uint8_t id, std::int8_t status) {
  GoalStatusEntry e;
  e.id.fill(id);
  e.status = status;
  return e;
}
}  // namespace

TEST(LiveCore, GoalAdoptedByANewIdAndReportedAfterEarlierScans) {
  GoalTracker g;
  g.statusArrived({entry(1, 4)}, 0);  // an old goal, before ours
  g.sent(100.0);
  EXPECT_EQ(g.status(0, 100.1, 5, 0), asf::NavStatus::Moving);
  g.statusArrived({entry(1, 4), entry(2, 2)}, 3);  // ours: id 2, executing
  EXPECT_EQ(g.status(3, 101, 5, 0), asf::NavStatus::Moving);
  g.statusArrived({entry(1, 4), entry(2, 4)}, 10);  // succeeded after 10 scans arrived
  EXPECT_EQ(g.status(9, 102, 5, 0), asf::NavStatus::Moving);  // scan 10 not processed yet
  EXPECT_EQ(g.status(10, 102, 5, 0), asf::NavStatus::Reached);
  EXPECT_FALSE(g.active());
  EXPECT_EQ(g.status(11, 103, 5, 0), asf::NavStatus::Reached);  // stays
  // The next goal: aborted.
  g.sent(200.0);
  g.statusArrived({entry(2, 4), entry(3, 6)}, 12);
  EXPECT_EQ(g.status(12, 200.5, 5, 0), asf::NavStatus::Unreachable);
  EXPECT_NE(g.why().find("aborted"), std::string::npos);
  // Canceled (preempted).
  g.sent(300.0);
  g.statusArrived({entry(4, 5)}, 12);
  EXPECT_EQ(g.status(12, 300.5, 5, 0), asf::NavStatus::Blocked);
}

TEST(LiveCore, GoalTimeouts) {
  GoalTracker g;
  g.sent(0.0);
  EXPECT_EQ(g.status(0, 4.9, 5, 0), asf::NavStatus::Moving);
  EXPECT_EQ(g.status(0, 5.1, 5, 0), asf::NavStatus::Unreachable);  // nobody accepted it
  EXPECT_NE(g.why().find("accepted"), std::string::npos);
  g.sent(10.0);
  g.statusArrived({entry(7, 2)}, 0);
  EXPECT_EQ(g.status(0, 39, 5, 30), asf::NavStatus::Moving);
  EXPECT_EQ(g.status(0, 41, 5, 30), asf::NavStatus::Blocked);  // ran too long
  EXPECT_NE(g.why().find("goal_timeout_s"), std::string::npos);
}

TEST(LiveCore, ScanQueueKeepsOrderAndCountsDrops) {
  ScanQueue q(3);
  for (int i = 0; i < 5; ++i) {
    asf::ros2::LaserScan s;
    s.stamp.sec = i;
    q.push(s);
  }
  EXPECT_EQ(q.arrived(), 5u);
  EXPECT_EQ(q.dropped(), 2u);
  const auto a = q.pop(std::chrono::milliseconds(1));
  ASSERT_TRUE(a);
  EXPECT_EQ(a->msg.stamp.sec, 2);
  EXPECT_EQ(a->seq, 3u);
  q.pop(std::chrono::milliseconds(1));
  q.pop(std::chrono::milliseconds(1));
  EXPECT_FALSE(q.pop(std::chrono::milliseconds(5)).has_value());
}

TEST(LiveCore, ScanQueueStampsWhenEachScanArrived) {
  ScanQueue q(4);
  const auto before = std::chrono::steady_clock::now();
  q.push(asf::ros2::LaserScan{});
  const auto between = std::chrono::steady_clock::now();
  q.push(asf::ros2::LaserScan{});
  const auto after = std::chrono::steady_clock::now();
  const auto a = q.pop(std::chrono::milliseconds(1));
  const auto b = q.pop(std::chrono::milliseconds(1));
  ASSERT_TRUE(a && b);
  EXPECT_GE(a->arrived_at, before);
  EXPECT_LE(a->arrived_at, between);
  EXPECT_GE(b->arrived_at, between);
  EXPECT_LE(b->arrived_at, after);
}

TEST(LiveCore, LatencySummaryTakesTheSortedElementAtTheQuantile) {
  EXPECT_EQ(latencySummary({}), "none");
  EXPECT_EQ(latencySummary({7}), "median 7 ms, p95 7 ms, max 7 ms over 1");
  // 1..21 shuffled, nearest rank: ceil(0.5 * 21) = 11th -> 11; ceil(0.95 * 21) = 20th -> 20; max 21.
  std::vector<double> v;
  for (int i = 21; i >= 1; i -= 2) v.push_back(i);
  for (int i = 2; i <= 20; i += 2) v.push_back(i);
  EXPECT_EQ(latencySummary(v), "median 11 ms, p95 20 ms, max 21 ms over 21");
}
