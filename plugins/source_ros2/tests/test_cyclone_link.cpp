// The live source's Cyclone DDS participant (cyclone_link.h), in one process on loopback: two
// links at once share the configured domain, and a map and transforms written by one arrive
// at the other unchanged. (Across vendors: tests/ros2/, against asf sim-robot on Fast DDS.)
#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "../cyclone_link.h"

using namespace asf::ros2live;
namespace ros2 = asf::ros2;

TEST(CycloneLink, TwoLinksShareADomainAndExchangeMessages) {
  LinkOptions o;
  o.domain_id = 97;
  o.loopback = true;
  CycloneLink a(o);
  std::mutex mu;
  std::condition_variable cv;
  std::optional<ros2::OccupancyGrid> got;
  std::vector<ros2::TransformStamped> tfs;
  {
    CycloneLink b(o);  // a second instance in the same process: the domain is shared
    b.onOccupancy("/asf_test_map", [&](ros2::OccupancyGrid m) {
      std::lock_guard<std::mutex> l(mu);
      got = std::move(m);
      cv.notify_all();
    });
    b.onTransforms("/asf_test_tf", Qos::Reliable, [&](std::vector<ros2::TransformStamped> m) {
      std::lock_guard<std::mutex> l(mu);
      tfs = std::move(m);
      cv.notify_all();
    });
    const int map_wr = a.advertiseOccupancy("/asf_test_map");
    const int tf_wr = a.advertiseTransforms("/asf_test_tf", Qos::Reliable);
    ros2::OccupancyGrid m;
    m.stamp = ros2::toStamp(3.5);
    m.frame_id = "map";
    m.resolution = 0.05f;
    m.width = 300, m.height = 200;  // 60 kB: more than one UDP datagram
    m.data.resize(60000);
    for (std::size_t i = 0; i < m.data.size(); ++i) m.data[i] = static_cast<std::int8_t>(i % 102 - 1);
    const ros2::TransformStamped t{ros2::toStamp(3.5), "map", "odom",
                                   ros2::transformFromPose(mrpt::poses::CPose2D(1, 2, 0.5))};
    // Writing delivers to a reader of the same process on the writer's thread: never hold
    // the callbacks' mutex while writing. The map is transient local (a late reader gets it);
    // transforms are volatile: resend until they arrive, at most 10 s.
    ASSERT_TRUE(a.publish(map_wr, m));
    std::unique_lock<std::mutex> l(mu);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while ((!got || tfs.empty()) && std::chrono::steady_clock::now() < deadline) {
      l.unlock();
      a.publish(tf_wr, std::vector<ros2::TransformStamped>{t});
      l.lock();
      cv.wait_for(l, std::chrono::milliseconds(100));
    }
    ASSERT_TRUE(got) << "no map within 10 s";
    EXPECT_EQ(got->data, m.data);
    EXPECT_EQ(got->width, 300u);
    EXPECT_EQ(got->frame_id, "map");
    EXPECT_EQ(got->stamp.sec, 3);
    ASSERT_EQ(tfs.size(), 1u);
    EXPECT_EQ(tfs[0].parent, "map");
    EXPECT_EQ(tfs[0].child, "odom");
    EXPECT_NEAR(tfs[0].transform.tx, 1, 1e-12);
    EXPECT_GE(a.subscriberCount("/asf_test_map"), 1u);
  }
  CycloneLink c(o);  // the domain outlived b, and a third instance still joins it
  EXPECT_TRUE(c.publisherTypes("/asf_test_nothing").empty());
}
