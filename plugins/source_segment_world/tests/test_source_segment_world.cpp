// Tests of asf::mapping::SegmentWorld (exact geometry) and of the segment_world source plugin.
#include <asf/errors.h>
#include <asf/framework/registry.h>
#include <asf/mapping/segment_world.h>
#include <asf/source.h>
#include <gtest/gtest.h>
#include <mrpt/core/Clock.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <cmath>
#include <map>
#include <string>

namespace {

std::shared_ptr<const asf::framework::PluginInfo> info() {
  static auto i =
      asf::framework::Registry::loadFile(ASF_TEST_PLUGIN_DIR "/source_segment_world.so");
  return i;
}

asf::framework::PluginHandle<asf::Source> make(const std::map<std::string, std::string>& kv,
                                    std::uint64_t seed = 1) {
  auto h = asf::framework::Registry::create<asf::Source>(info());
  asf::PluginContext ctx;
  ctx.seed = seed;
  h->configure(asf::Params::fromSpecs("segment_world", info()->descriptor->keys,
                                      info()->descriptor->num_keys, kv),
               ctx);
  return h;
}

std::string configError(const std::map<std::string, std::string>& kv) {
  try {
    make(kv);
  } catch (const asf::ConfigError& e) {
    return e.what();
  }
  return "";
}

// ---------------------------------------------------------------- SegmentWorld geometry

TEST(SegmentWorld, CastRayInRectangleIsExact) {
  const auto w = asf::mapping::SegmentWorld::rectangle(0, 0, 4, 2);
  EXPECT_DOUBLE_EQ(w.castRay(1, 1, 0, 10), 3);
  EXPECT_DOUBLE_EQ(w.castRay(1, 1, M_PI / 2, 10), 1);
  EXPECT_NEAR(w.castRay(1, 1, M_PI, 10), 1, 1e-12);
  EXPECT_NEAR(w.castRay(1, 1, -M_PI / 2, 10), 1, 1e-12);
  EXPECT_NEAR(w.castRay(1, 1, M_PI / 4, 10), std::sqrt(2.0), 1e-12);
  // 30 degrees up: hits y = 2 at distance 1 / sin(30deg) = 2.
  EXPECT_NEAR(w.castRay(1, 1, M_PI / 6, 10), 2, 1e-12);
  EXPECT_DOUBLE_EQ(w.castRay(1, 1, 0, 2.5), 2.5);  // nothing within max_range
}

TEST(SegmentWorld, CastRayMissesAndCollinearWalls) {
  asf::mapping::SegmentWorld w({asf::mapping::Segment{{2, 0}, {3, 0}}});
  EXPECT_DOUBLE_EQ(w.castRay(0, 0, 0, 10), 2);      // along the wall: its near end
  EXPECT_DOUBLE_EQ(w.castRay(2.5, 0, 0, 10), 0);    // starting on it
  EXPECT_DOUBLE_EQ(w.castRay(4, 0, 0, 10), 10);     // wall behind
  EXPECT_DOUBLE_EQ(w.castRay(0, 1, 0, 10), 10);     // parallel, beside
  EXPECT_DOUBLE_EQ(w.castRay(2.5, 1, -M_PI / 2, 10), 1);
  EXPECT_DOUBLE_EQ(w.castRay(3.5, 1, -M_PI / 2, 10), 10);  // passes beyond the end
  EXPECT_NEAR(w.castRay(3, 1, -M_PI / 2, 10), 1, 1e-12);   // grazes the end point
}

TEST(SegmentWorld, TwoRoomsDoorAndBounds) {
  const auto w = asf::mapping::SegmentWorld::twoRooms(5, 4, 1);
  EXPECT_EQ(w.walls().size(), 6u);
  EXPECT_NEAR(w.castRay(1, 2, 0, 20), 9, 1e-12);    // through the door to the far wall
  EXPECT_NEAR(w.castRay(1, 1, 0, 20), 4, 1e-12);    // shared wall below the door
  EXPECT_NEAR(w.castRay(1, 3.4, 0, 20), 4, 1e-12);  // shared wall above the door
  const asf::Box2 b = w.bounds();
  EXPECT_DOUBLE_EQ(b.min_x, 0);
  EXPECT_DOUBLE_EQ(b.min_y, 0);
  EXPECT_DOUBLE_EQ(b.max_x, 10);
  EXPECT_DOUBLE_EQ(b.max_y, 4);
  EXPECT_TRUE(asf::mapping::SegmentWorld().bounds().empty());
}

TEST(SegmentWorld, CollidesIsSegmentDistanceBelowClearance) {
  const auto w = asf::mapping::SegmentWorld::rectangle(0, 0, 4, 2);
  EXPECT_FALSE(w.collides({1, 1}, {1, 1}, 0.5));
  EXPECT_FALSE(w.collides({1, 1}, {3.5, 1}, 0.49));  // 0.5 from the right wall
  EXPECT_TRUE(w.collides({1, 1}, {3.5, 1}, 0.51));
  EXPECT_TRUE(w.collides({1, 1}, {5, 1}, 0.01));     // crosses a wall
  EXPECT_TRUE(w.collides({-1, -1}, {5, 3}, 0.01));   // crosses two walls
  EXPECT_FALSE(w.collides({-1, 3}, {5, 3}, 0.99));   // outside, 1 m above the top wall
  EXPECT_TRUE(w.collides({-1, 3}, {5, 3}, 1.01));
  // Closest approach at a wall's end point: (4, 2) to the segment (5, 3) -> (6, 2).
  EXPECT_TRUE(w.collides({5, 3}, {6, 2}, std::sqrt(2.0) + 1e-9));
  EXPECT_FALSE(w.collides({5, 3}, {6, 2}, std::sqrt(2.0) - 1e-9));
}

TEST(SegmentWorld, ParseAcceptsListsAndNamesTheBadItem) {
  const auto w = asf::mapping::SegmentWorld::parse(" 0 0 1 0; 1,0, 1,1 ;");
  ASSERT_EQ(w.walls().size(), 2u);
  EXPECT_DOUBLE_EQ(w.walls()[1].a.x, 1);
  EXPECT_DOUBLE_EQ(w.walls()[1].b.y, 1);
  EXPECT_TRUE(asf::mapping::SegmentWorld::parse("").walls().empty());
  try {
    asf::mapping::SegmentWorld::parse("0 0 1 0; 1 0 x 1");
    FAIL() << "no exception";
  } catch (const asf::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("wall 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'x'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(asf::mapping::SegmentWorld::parse("0 0 1"), asf::ConfigError);
  EXPECT_THROW(asf::mapping::SegmentWorld::parse("0 0 1 0 5"), asf::ConfigError);
  EXPECT_THROW(asf::mapping::SegmentWorld::parse("1 1 1 1"), asf::ConfigError);
  EXPECT_THROW(asf::mapping::SegmentWorld::parse("0 0 inf 1"), asf::ConfigError);
}

// ---------------------------------------------------------------- the source plugin

TEST(SourceSegmentWorld, Descriptor) {
  EXPECT_STREQ(info()->descriptor->name, "segment_world");
  EXPECT_EQ(info()->kind(), asf::PluginKind::Source);
  auto s = make({});
  EXPECT_TRUE(s->isActive());
  EXPECT_EQ(s->status(), asf::NavStatus::Idle);
}

TEST(SourceSegmentWorld, ScanMatchesExactRayCastingFromTheTruePose) {
  auto s = make({{"world", "rectangle"}, {"range_sigma", "0"}, {"laser_max_range", "3"},
                 {"laser_rays", "91"}, {"laser_fov_deg", "270"}, {"start_phi_deg", "30"}});
  auto f = s->next();
  ASSERT_TRUE(f && f->scan && f->ground_truth);
  const auto& sc = *f->scan;
  ASSERT_EQ(sc.getScanSize(), 91u);
  EXPECT_NEAR(sc.aperture, 270 * M_PI / 180, 1e-6);
  EXPECT_TRUE(sc.rightToLeft);
  EXPECT_FLOAT_EQ(sc.maxRange, 3.0f);
  EXPECT_NEAR(sc.sensorPose.x(), 0.1, 1e-12);
  EXPECT_NEAR(f->ground_truth->x(), 1, 1e-12);
  EXPECT_NEAR(f->ground_truth->phi(), M_PI / 6, 1e-12);
  const auto w = asf::mapping::SegmentWorld::rectangle(0, 0, 5, 4);
  const auto laser = *f->ground_truth + mrpt::poses::CPose2D(0.1, 0, 0);
  int valid = 0, invalid = 0;
  for (std::size_t i = 0; i < sc.getScanSize(); ++i) {
    const double r = w.castRay(laser.x(), laser.y(), laser.phi() + sc.getScanAngle(i), 3);
    if (r < 3) {
      ASSERT_TRUE(sc.getScanRangeValidity(i)) << i;
      EXPECT_NEAR(sc.getScanRange(i), r, 1e-5) << i;
      ++valid;
    } else {
      EXPECT_FALSE(sc.getScanRangeValidity(i)) << i;
      ++invalid;
    }
  }
  EXPECT_GT(valid, 10);
  EXPECT_GT(invalid, 10);
}

TEST(SourceSegmentWorld, RangeNoiseHasTheConfiguredSigma) {
  auto s = make({{"world", "rectangle"}, {"range_sigma", "0.05"}, {"laser_rays", "361"},
                 {"laser_fov_deg", "360"}, {"laser_max_range", "20"}});
  const auto w = asf::mapping::SegmentWorld::rectangle(0, 0, 5, 4);
  double sum = 0, sum2 = 0;
  int n = 0;
  for (int k = 0; k < 10; ++k) {
    auto f = s->next();
    const auto laser = *f->ground_truth + mrpt::poses::CPose2D(0.1, 0, 0);
    for (std::size_t i = 0; i < f->scan->getScanSize(); ++i) {
      ASSERT_TRUE(f->scan->getScanRangeValidity(i));
      const double d = f->scan->getScanRange(i) -
                       w.castRay(laser.x(), laser.y(), laser.phi() + f->scan->getScanAngle(i), 20);
      sum += d;
      sum2 += d * d;
      ++n;
    }
  }
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0, 4 * 0.05 / std::sqrt(n));
  EXPECT_NEAR(sd, 0.05, 0.005);
}

// Drives to `goal` (map frame = world frame: the estimate given is the true pose).
asf::NavStatus driveTo(asf::Source& s, double x, double y, mrpt::poses::CPose2D& gt,
                       int max_frames = 2000, std::vector<asf::SensorFrame>* frames = nullptr) {
  asf::NavigationContext ctx;
  ctx.robot_estimate = gt;
  asf::Goal g;
  g.x = x;
  g.y = y;
  g.tolerance = 0.1;
  asf::NavStatus st = s.navigate(g, ctx);
  for (int k = 0; k < max_frames && st == asf::NavStatus::Moving; ++k) {
    auto f = s.next();
    if (!f) break;
    gt = *f->ground_truth;
    if (frames) frames->push_back(*f);
    st = s.status();
  }
  return st;
}

TEST(SourceSegmentWorld, NoiseFreeOdometryIsTheTrueIncrementAndGoalIsReached) {
  auto s = make({{"odo_sigma_xy", "0"}, {"odo_sigma_phi", "0"}});
  auto f0 = s->next();
  mrpt::poses::CPose2D gt = *f0->ground_truth, prev = gt;
  std::vector<asf::SensorFrame> frames;
  EXPECT_EQ(driveTo(*s, 4, 3, gt, 2000, &frames), asf::NavStatus::Reached);
  EXPECT_LT(std::hypot(gt.x() - 4, gt.y() - 3), 0.1 + 1e-9);
  ASSERT_GT(frames.size(), 10u);
  for (const auto& f : frames) {
    const mrpt::poses::CPose2D inc = *f.ground_truth - prev;
    EXPECT_NEAR(f.odometry.x(), inc.x(), 1e-9);
    EXPECT_NEAR(f.odometry.y(), inc.y(), 1e-9);
    EXPECT_NEAR(f.odometry.phi(), inc.phi(), 1e-9);
    EXPECT_TRUE(f.odometry_cov.isZero());
    prev = *f.ground_truth;
  }
}

TEST(SourceSegmentWorld, OdometryNoiseMatchesTheReportedCovariance) {
  auto s = make({{"world", "rectangle"}, {"room_width", "6"}, {"room_height", "6"},
                 {"odo_sigma_xy", "0.05"}, {"odo_sigma_phi", "0.03"}, {"laser_rays", "2"}},
                7);
  mrpt::poses::CPose2D gt = *s->next()->ground_truth;
  const double route[][2] = {{5, 5}, {1, 5}, {5, 1}, {1, 1}, {5, 5}, {1, 5}, {5, 1}, {1, 1}};
  double z2[3] = {0, 0, 0};
  int cnt[3] = {0, 0, 0};
  for (const auto& wp : route) {
    std::vector<asf::SensorFrame> frames;
    mrpt::poses::CPose2D prev = gt;
    driveTo(*s, wp[0], wp[1], gt, 2000, &frames);
    for (const auto& f : frames) {
      const mrpt::poses::CPose2D inc = *f.ground_truth - prev;
      prev = *f.ground_truth;
      const double e[3] = {f.odometry.x() - inc.x(), f.odometry.y() - inc.y(),
                           f.odometry.phi() - inc.phi()};
      EXPECT_TRUE((f.odometry_cov - f.odometry_cov.transpose()).isZero());
      for (int c = 0; c < 3; ++c) {
        const double var = f.odometry_cov(c, c);
        if (var > 0) {
          z2[c] += e[c] * e[c] / var;
          ++cnt[c];
        } else {
          EXPECT_EQ(e[c], 0.0);
        }
      }
    }
  }
  for (int c = 0; c < 3; ++c) {
    ASSERT_GT(cnt[c], 400) << c;
    // Mean of chi2(1) samples is 1 with std sqrt(2/n).
    EXPECT_NEAR(z2[c] / cnt[c], 1.0, 4 * std::sqrt(2.0 / cnt[c])) << "component " << c;
  }
}

TEST(SourceSegmentWorld, PassesThroughTheDoor) {
  auto s = make({{"start_x", "1"}, {"start_y", "2"}, {"odo_sigma_xy", "0"},
                 {"odo_sigma_phi", "0"}});
  mrpt::poses::CPose2D gt = *s->next()->ground_truth;
  EXPECT_EQ(driveTo(*s, 8, 2, gt), asf::NavStatus::Reached);
  EXPECT_GT(gt.x(), 7.8);
}

TEST(SourceSegmentWorld, BlockedByAWallNeverPassesThrough) {
  auto s = make({});
  mrpt::poses::CPose2D gt = *s->next()->ground_truth;
  std::vector<asf::SensorFrame> frames;
  EXPECT_EQ(driveTo(*s, 8, 0.5, gt, 2000, &frames), asf::NavStatus::Blocked);
  const auto w = asf::mapping::SegmentWorld::twoRooms(5, 4, 1);
  for (const auto& f : frames) {
    const asf::Point2 p{f.ground_truth->x(), f.ground_truth->y()};
    EXPECT_FALSE(w.collides(p, p, 0.2)) << p.x << " " << p.y;
    EXPECT_LT(p.x, 5);
  }
  // Once blocked it stays put (frames keep coming).
  for (int k = 0; k < 5; ++k) {
    auto f = s->next();
    ASSERT_TRUE(f);
    EXPECT_EQ(f->ground_truth->x(), gt.x());
    EXPECT_EQ(f->ground_truth->y(), gt.y());
    EXPECT_EQ(s->status(), asf::NavStatus::Blocked);
  }
}

TEST(SourceSegmentWorld, IdleStandsStillAndBadGoalIsUnreachable) {
  auto s = make({});
  auto a = s->next();
  for (int k = 0; k < 5; ++k) {
    auto b = s->next();
    EXPECT_EQ(b->ground_truth->x(), a->ground_truth->x());
    EXPECT_EQ(b->ground_truth->phi(), a->ground_truth->phi());
    EXPECT_EQ(b->odometry.x(), 0.0);
    EXPECT_EQ(b->odometry.y(), 0.0);
    EXPECT_EQ(b->odometry.phi(), 0.0);
  }
  EXPECT_EQ(s->status(), asf::NavStatus::Idle);
  asf::Goal g;
  g.x = std::nan("");
  EXPECT_EQ(s->navigate(g, {}), asf::NavStatus::Unreachable);
  g.x = 0.05;  // already there (estimate = origin)
  g.y = 0;
  EXPECT_EQ(s->navigate(g, {}), asf::NavStatus::Reached);
}

TEST(SourceSegmentWorld, StreamEndsAfterMaxStepsWithIncreasingTimestamps) {
  auto s = make({{"max_steps", "5"}, {"dt", "0.25"}});
  for (int k = 0; k < 5; ++k) {
    auto f = s->next();
    ASSERT_TRUE(f) << k;
    EXPECT_DOUBLE_EQ(f->timestamp, 0.25 * k);
    EXPECT_NEAR(mrpt::Clock::toDouble(f->scan->timestamp), 0.25 * k, 1e-6);
  }
  EXPECT_FALSE(s->next());
  EXPECT_FALSE(s->next());
}

TEST(SourceSegmentWorld, SeedDeterminesTheStream) {
  auto a = make({}, 42), b = make({}, 42), c = make({}, 43);
  auto fa = a->next(), fb = b->next(), fc = c->next();
  bool differs = false;
  for (std::size_t i = 0; i < fa->scan->getScanSize(); ++i) {
    EXPECT_EQ(fa->scan->getScanRange(i), fb->scan->getScanRange(i));
    differs |= fa->scan->getScanRange(i) != fc->scan->getScanRange(i);
  }
  EXPECT_TRUE(differs);
}

TEST(SourceSegmentWorld, CustomWorldAndConfigErrors) {
  auto s = make({{"world", "custom"}, {"walls", "0 0 3 0; 3 0 3 3; 3 3 0 3; 0 3 0 0"},
                 {"laser_rays", "2"}, {"laser_fov_deg", "180"}, {"range_sigma", "0"}});
  auto f = s->next();
  // Robot at (1,1) heading 0, laser at (1.1, 1): rays at -90 and +90 degrees.
  EXPECT_NEAR(f->scan->getScanRange(0), 1.0, 1e-6);
  EXPECT_NEAR(f->scan->getScanRange(1), 2.0, 1e-6);

  EXPECT_NE(configError({{"world", "custom"}}).find("walls"), std::string::npos);
  EXPECT_NE(configError({{"world", "custom"}, {"walls", "0 0 3 0; 3 0 3"}}).find("wall 2"),
            std::string::npos);
  EXPECT_NE(configError({{"start_x", "5"}, {"start_y", "0.5"}}).find("start_x"),
            std::string::npos);  // on the shared wall
  EXPECT_NE(configError({{"start_x", "20"}}).find("start_x"), std::string::npos);
  EXPECT_NE(configError({{"door_width", "4"}}).find("door_width"), std::string::npos);
}

}  // namespace
