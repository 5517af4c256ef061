// KeyframeTracker: the keyframe bookkeeping shared by the front-ends.
#include <asf/errors.h>
#include <asf/mapping/keyframe_tracker.h>
#include <gtest/gtest.h>

#include <cmath>

namespace {

using mrpt::poses::CPose2D;

asf::SensorFrame frame(double t, const CPose2D& u, double var = 1e-4) {
  asf::SensorFrame f;
  f.timestamp = t;
  f.odometry = u;
  f.odometry_cov = Eigen::Matrix3d::Identity() * var;
  return f;
}

TEST(KeyframeTracker, RootThenAKeyframeWhenTheDistanceIsExceeded) {
  asf::mapping::KeyframeTracker kf("test");
  kf.setThresholds(1.0, M_PI / 2);
  asf::PoseGraph g;
  EXPECT_EQ(kf.begin(frame(0, CPose2D(5, 5, 1)), g), asf::mapping::KeyframeTracker::Begin::AddedRoot);
  ASSERT_EQ(g.size(), 1u);
  EXPECT_EQ(g.revision, 1u);
  // The first frame's odometry is not accumulated: the root is the origin of the map.
  EXPECT_NEAR(kf.currentPose(g).x(), 0, 1e-12);
  for (int k = 1; k <= 3; ++k) {
    EXPECT_EQ(kf.begin(frame(k, CPose2D(0.3, 0, 0)), g), asf::mapping::KeyframeTracker::Begin::NotFirst);
    EXPECT_FALSE(kf.due()) << k;  // 0.9 m after three steps
  }
  EXPECT_NEAR(kf.currentPose(g).x(), 0.9, 1e-12);
  EXPECT_TRUE(kf.due(0.5));
  kf.begin(frame(4, CPose2D(0.3, 0, 0)), g);
  ASSERT_TRUE(kf.due());
  EXPECT_FALSE(kf.due(2));
  // Four increments of variance 1e-4 each (straight line: no rotation coupling in x).
  EXPECT_NEAR(kf.incrementCov()(0, 0), 4e-4, 1e-12);
  const asf::NodeId id = kf.addKeyframe(g, g.nodes[0].pose + kf.increment(), frame(4, CPose2D()));
  EXPECT_EQ(id, 1u);
  EXPECT_EQ(kf.last(), 1u);
  EXPECT_EQ(g.nodes[1].timestamp, 4);
  EXPECT_NEAR(g.nodes[1].pose.x(), 1.2, 1e-12);
  EXPECT_NEAR(kf.increment().x(), 0, 1e-12);
  EXPECT_EQ(kf.incrementCov().norm(), 0);
  EXPECT_NEAR(kf.currentPose(g).x(), 1.2, 1e-12);
}

TEST(KeyframeTracker, TurningInPlaceIsDueByAngle) {
  asf::mapping::KeyframeTracker kf("test");
  kf.setThresholds(1.0, 0.5);
  asf::PoseGraph g;
  kf.begin(frame(0, CPose2D()), g);
  kf.begin(frame(1, CPose2D(0, 0, 0.3)), g);
  EXPECT_FALSE(kf.due());
  kf.begin(frame(2, CPose2D(0, 0, -0.9)), g);  // net -0.6 rad
  EXPECT_TRUE(kf.due());
}

TEST(KeyframeTracker, ContinuesAGivenGraphAndRefusesAReplacedOne) {
  asf::mapping::KeyframeTracker kf("my front-end");
  asf::PoseGraph g;
  g.addNode(CPose2D());
  g.addNode(CPose2D(2, 0, 0));
  EXPECT_EQ(kf.begin(frame(0, CPose2D()), g), asf::mapping::KeyframeTracker::Begin::Continued);
  EXPECT_EQ(kf.last(), 1u);
  EXPECT_NEAR(kf.currentPose(g).x(), 2, 1e-12);
  asf::PoseGraph smaller;
  smaller.addNode(CPose2D());
  try {
    kf.begin(frame(1, CPose2D()), smaller);
    FAIL() << "expected an error";
  } catch (const asf::Error& e) {
    EXPECT_NE(std::string(e.what()).find("my front-end"), std::string::npos) << e.what();
  }
}

}  // namespace
