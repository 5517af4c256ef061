// The 3D map layer (asf::mapping::Map3d): ray-cast insertion into the OctoMap octree, the projection
// to the 2D grid (body band), keyframe rebuilds with a cap, .bt/.ot files, and asf map3d.
#include <asf/errors.h>
#include <asf/mapping/map3d.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRotatingScan.h>
#include <octomap/OcTree.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <set>

#include "test_util.h"

namespace {

using asf::mapping::Map3d;
using asf_test::errorOf;
using asf_test::has;
using mrpt::poses::CPose2D;
using mrpt::poses::CPose3D;
using Points = std::vector<Eigen::Vector3f>;
namespace fs = std::filesystem;

constexpr double kRes = 0.1;

asf::Params params(std::map<std::string, std::string> over = {}) {
  std::size_t n = 0;
  const asf::KeySpec* keys = Map3d::keys(n);
  if (!over.count("resolution")) over["resolution"] = std::to_string(kRes);
  if (!over.count("project_resolution")) over["project_resolution"] = std::to_string(kRes);
  return asf::Params::fromSpecs("map3d", keys, n, over);
}

/// A box room of voxel indices [x0, x1] x [y0, y1] x [z0, z1]: its walls, floor and ceiling
/// are the boundary voxels. One point at the centre of every boundary voxel (world frame),
/// except the voxels `skip` rejects.
Points boxRoom(int x0, int x1, int y0, int y1, int z0, int z1,
               const std::function<bool(int, int, int)>& skip = nullptr) {
  Points pts;
  for (int i = x0; i <= x1; ++i)
    for (int j = y0; j <= y1; ++j)
      for (int k = z0; k <= z1; ++k) {
        const bool boundary = i == x0 || i == x1 || j == y0 || j == y1 || k == z0 || k == z1;
        if (!boundary || (skip && skip(i, j, k))) continue;
        pts.emplace_back((i + 0.5) * kRes, (j + 0.5) * kRes, (k + 0.5) * kRes);
      }
  return pts;
}

/// A horizontal slab of voxel centres at voxel height k over [x0, x1] x [y0, y1].
Points slab(int x0, int x1, int y0, int y1, int k) {
  Points pts;
  for (int i = x0; i <= x1; ++i)
    for (int j = y0; j <= y1; ++j) pts.emplace_back((i + 0.5) * kRes, (j + 0.5) * kRes, (k + 0.5) * kRes);
  return pts;
}

std::uint64_t key(int i, int j, int k) {  // as Map3d::occupiedVoxelKeys packs OctoMap keys
  return (static_cast<std::uint64_t>(i + 32768) << 32) |
         (static_cast<std::uint64_t>(j + 32768) << 16) | static_cast<std::uint64_t>(k + 32768);
}

/// World points seen from `sensor` (a pose in the map): the same points in the sensor frame.
Points toSensor(const Points& world, const CPose3D& sensor) {
  Points out;
  out.reserve(world.size());
  for (const auto& p : world) {
    double lx, ly, lz;
    sensor.inverseComposePoint(p.x(), p.y(), p.z(), lx, ly, lz);
    out.emplace_back(static_cast<float>(lx), static_cast<float>(ly), static_cast<float>(lz));
  }
  return out;
}

// The room used below: voxels x in [0, 40], y in [0, 30], z in [-1, 25]: the floor voxel
// layer is z in [-0.1, 0) (below the body band), the ceiling layer [2.5, 2.6).
constexpr int X0 = 0, X1 = 40, Y0 = 0, Y1 = 30, Z0 = -1, Z1 = 25;
const CPose3D kSensor(2.05, 1.55, 1.05, 0, 0, 0);

double pFree(const asf::GridMap& m, double x, double y) {
  return m.grid->getPos(static_cast<float>(x), static_cast<float>(y));
}

TEST(Map3d, BoxRoomOccupiedAndFreeVoxels) {
  Map3d map;
  map.configure(params());
  const Points world = boxRoom(X0, X1, Y0, Y1, Z0, Z1);
  const std::size_t n = map.insertPoints(toSensor(world, kSensor), kSensor);
  EXPECT_EQ(n, world.size());

  // Occupied: exactly the boundary voxels (occupied wins over free inside one cloud).
  std::vector<std::uint64_t> expected;
  for (int i = X0; i <= X1; ++i)
    for (int j = Y0; j <= Y1; ++j)
      for (int k = Z0; k <= Z1; ++k)
        if (i == X0 || i == X1 || j == Y0 || j == Y1 || k == Z0 || k == Z1)
          expected.push_back(key(i, j, k));
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(map.occupiedVoxelKeys(), expected);

  // Free: the rays cross the interior; nothing outside the room is known.
  for (const auto& p : {Eigen::Vector3d(2.05, 1.55, 1.05), Eigen::Vector3d(0.55, 0.55, 0.35),
                        Eigen::Vector3d(3.55, 2.55, 2.25), Eigen::Vector3d(1.05, 2.75, 0.15)}) {
    const double occ = map.occupancyAt(p.x(), p.y(), p.z());
    EXPECT_GE(occ, 0) << p.transpose() << " unknown";
    EXPECT_LT(occ, 0.5) << p.transpose();
  }
  EXPECT_EQ(map.occupancyAt(4.55, 1.55, 1.05), -1.0);   // behind a wall
  EXPECT_EQ(map.occupancyAt(2.05, 1.55, -0.55), -1.0);  // under the floor
  EXPECT_NEAR(map.occupancyAt(0.05, 1.55, 1.05), 0.7, 1e-3);  // one hit = prob_hit

  const asf::mapping::Map3dStats s = map.stats();
  EXPECT_EQ(s.occupied_voxels, expected.size());
  const std::size_t interior = (X1 - X0 - 1) * (Y1 - Y0 - 1) * (Z1 - Z0 - 1);
  EXPECT_GT(s.free_voxels, interior * 9 / 10);  // dense rays: most of the interior
  EXPECT_LE(s.free_voxels, interior);
  EXPECT_NEAR(s.known_volume_m3, (s.free_voxels + s.occupied_voxels) * kRes * kRes * kRes, 1e-6);
  EXPECT_GT(s.memory_bytes, 0u);
  EXPECT_EQ(s.points_inserted, world.size());
}

TEST(Map3d, BoxRoomProjection) {
  Map3d map;
  map.configure(params());
  map.insertPoints(toSensor(boxRoom(X0, X1, Y0, Y1, Z0, Z1), kSensor), kSensor);
  const asf::GridMap g = map.project();
  ASSERT_TRUE(g.grid);
  EXPECT_EQ(g.version, map.version());
  EXPECT_NEAR(g.grid->getResolution(), kRes, 1e-6);  // MRPT stores a float
  int occupied = 0, free = 0, other = 0;
  for (int i = X0; i <= X1; ++i)
    for (int j = Y0; j <= Y1; ++j) {
      const double p = pFree(g, (i + 0.5) * kRes, (j + 0.5) * kRes);
      const bool wall = i == X0 || i == X1 || j == Y0 || j == Y1;
      if (wall) {
        EXPECT_LT(p, 0.4) << "wall cell " << i << "," << j;
        occupied += p < 0.4;
      } else {
        EXPECT_GT(p, 0.55) << "floor cell " << i << "," << j;  // free, not the floor's hits
        free += p > 0.55;
      }
      other += p >= 0.4 && p <= 0.55;
    }
  EXPECT_EQ(occupied, 2 * (X1 - X0 + 1) + 2 * (Y1 - Y0 - 1));
  EXPECT_EQ(free, (X1 - X0 - 1) * (Y1 - Y0 - 1));
  EXPECT_EQ(other, 0);
  // The grid spans the octree: the room and nothing else.
  EXPECT_NEAR(g.grid->getXMin(), X0 * kRes, 1e-6);
  EXPECT_NEAR(g.grid->getXMax(), (X1 + 1) * kRes, 1e-6);
  EXPECT_NEAR(g.grid->getYMin(), Y0 * kRes, 1e-6);
  EXPECT_NEAR(g.grid->getYMax(), (Y1 + 1) * kRes, 1e-6);
}

TEST(Map3d, TableInTheBandLampAboveIt) {
  Map3d map;
  map.configure(params({{"max_height", "1.5"}}));
  // Table top at 0.7 m (voxel layer [0.7, 0.8)) over x [1.0, 1.6), y [1.0, 1.6); the floor
  // under it is hidden. Lamp at 2.0 m ([2.0, 2.1)) over x [2.8, 3.0), y [0.5, 0.7).
  Points world = boxRoom(X0, X1, Y0, Y1, Z0, Z1, [](int i, int j, int k) {
    return k == Z0 && i >= 10 && i <= 15 && j >= 10 && j <= 15;
  });
  const Points table = slab(10, 15, 10, 15, 7), lamp = slab(28, 29, 5, 6, 20);
  world.insert(world.end(), table.begin(), table.end());
  world.insert(world.end(), lamp.begin(), lamp.end());
  map.insertPoints(toSensor(world, kSensor), kSensor);
  ASSERT_GT(map.occupancyAt(2.85, 0.55, 2.05), 0.5);  // the lamp is in the octree
  const asf::GridMap g = map.project();
  ASSERT_TRUE(g.grid);
  for (int i = 10; i <= 15; ++i)
    for (int j = 10; j <= 15; ++j)
      EXPECT_LT(pFree(g, (i + 0.5) * kRes, (j + 0.5) * kRes), 0.4) << "table " << i << "," << j;
  for (int i = 28; i <= 29; ++i)
    for (int j = 5; j <= 6; ++j)
      EXPECT_GT(pFree(g, (i + 0.5) * kRes, (j + 0.5) * kRes), 0.55) << "lamp " << i << "," << j;
  EXPECT_GT(pFree(g, 2.05, 1.55), 0.55);

  // Raising the band's top above the lamp makes it an obstacle.
  Map3d tall;
  tall.configure(params({{"max_height", "2.2"}}));
  tall.insertPoints(toSensor(world, kSensor), kSensor);
  EXPECT_LT(pFree(tall.project(), 2.85, 0.55), 0.4);
}

/// A scan of the floor z = 0 from a laser at height h pitched down by `pitch` (radians).
mrpt::obs::CObservation2DRangeScan floorScan(double h, double pitch) {
  mrpt::obs::CObservation2DRangeScan s;
  s.sensorLabel = "TILTED";
  s.aperture = static_cast<float>(M_PI);
  s.rightToLeft = true;
  s.maxRange = 20;
  s.sensorPose = CPose3D(0.1, 0, h, 0, pitch, 0);
  const std::size_t n = 181;
  s.resizeScan(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double a = -0.5 * M_PI + M_PI * i / (n - 1);
    double gx, gy, gz;  // the ray direction in the robot frame
    s.sensorPose.composePoint(std::cos(a), std::sin(a), 0, gx, gy, gz);
    const double dz = gz - h;
    const double r = dz < -1e-3 ? -h / dz : 0;
    s.setScanRange(i, static_cast<float>(r));
    s.setScanRangeValidity(i, r > 0 && r < s.maxRange);
  }
  return s;
}

TEST(Map3d, TiltedScanOfAFlatFloorIsNoObstacle) {
  // The defaults: 5 cm voxels, the band from 5 cm up.
  const auto cfg = params({{"resolution", "0.05"}, {"project_resolution", "0.05"}});
  Map3d map;
  map.configure(cfg);
  const auto scan = floorScan(0.5, 0.35);
  const CPose2D robot(1.0, 2.0, 0.3);
  const std::size_t n = map.insertObservation(scan, robot);
  EXPECT_GT(n, 100u);
  // The floor hits are in the octree (below the band)...
  const asf::mapping::Map3dStats s = map.stats();
  EXPECT_GT(s.occupied_voxels, 50u);
  // ... the projection has free cells and no obstacle.
  const asf::GridMap g = map.project();
  ASSERT_TRUE(g.grid);
  int occupied = 0, free = 0;
  for (unsigned y = 0; y < g.grid->getSizeY(); ++y)
    for (unsigned x = 0; x < g.grid->getSizeX(); ++x) {
      const float p = g.grid->getCell(x, y);
      occupied += p < 0.45f;
      free += p > 0.55f;
    }
  EXPECT_EQ(occupied, 0);
  EXPECT_GT(free, 50);

  // The same laser level at 0.5 m sees a wall 2 m ahead: that one is an obstacle (the scan
  // geometry, sensor pose and band do mark what they should).
  mrpt::obs::CObservation2DRangeScan wall = scan;
  wall.sensorPose = CPose3D(0.1, 0, 0.5, 0, 0, 0);
  for (std::size_t i = 0; i < wall.getScanSize(); ++i) {
    const double a = -0.5 * M_PI + M_PI * i / (wall.getScanSize() - 1);
    const bool ahead = std::abs(a) < 0.3;
    wall.setScanRange(i, ahead ? static_cast<float>(2.03 / std::cos(a)) : 0.f);
    wall.setScanRangeValidity(i, ahead);
  }
  Map3d m2;
  m2.configure(cfg);
  m2.insertObservation(wall, CPose2D(0, 0, 0));
  EXPECT_GT(m2.occupancyAt(2.13, 0.0, 0.5), 0.5);
  EXPECT_LT(pFree(m2.project(), 2.13, 0.0), 0.4);

  // The same scan as MRPT's one-ring CObservationRotatingScan gives the same points (up to
  // the range image's quantization: the same voxels).
  mrpt::obs::CObservationRotatingScan rot;
  rot.fromScan2D(wall);
  Map3d m3;
  m3.configure(cfg);
  EXPECT_EQ(m3.insertObservation(rot, CPose2D(0, 0, 0)), 35u);  // |a| < 0.3 rad: 35 rays
  EXPECT_EQ(m3.occupiedVoxelKeys(), m2.occupiedVoxelKeys());
  // Several rings have no elevation angles in MRPT 2.5: an input error saying so.
  rot.rowCount = 16;
  const std::string e = errorOf<asf::InputError>([&] { m3.insertObservation(rot, CPose2D()); });
  EXPECT_TRUE(has(e, "16 rings") && has(e, "TILTED")) << e;
}

TEST(Map3d, KeysAndConfigErrorsNameTheKey) {
  std::size_t n = 0;
  const asf::KeySpec* keys = Map3d::keys(n);
  std::set<std::string> names;
  for (std::size_t i = 0; i < n; ++i) {
    names.insert(keys[i].name);
    EXPECT_NE(keys[i].default_value, nullptr) << keys[i].name;
    EXPECT_GT(std::string(keys[i].doc).size(), 10u) << keys[i].name;
  }
  for (const char* k : {"resolution", "max_range", "prob_hit", "prob_miss", "clamping_thres_min",
                        "clamping_thres_max", "min_height", "max_height", "project_resolution",
                        "unknown_band", "max_keyframes_per_update"})
    EXPECT_TRUE(names.count(k)) << k;
  EXPECT_NO_THROW(Map3d().configure(asf::Params::fromSpecs("map3d", keys, n)));

  auto configError = [&](std::map<std::string, std::string> over) {
    return errorOf<asf::ConfigError>([&] { Map3d().configure(params(over)); });
  };
  EXPECT_TRUE(has(configError({{"resolution", "0"}}), "resolution")) << configError({{"resolution", "0"}});
  EXPECT_TRUE(has(configError({{"prob_hit", "0.3"}}), "prob_hit"));
  EXPECT_TRUE(has(configError({{"max_keyframes_per_update", "0"}}), "max_keyframes_per_update"));
  EXPECT_TRUE(has(configError({{"resolutoin", "0.1"}}), "resolutoin"));
  const std::string band = configError({{"min_height", "1.0"}, {"max_height", "0.5"}});
  EXPECT_TRUE(has(band, "max_height")) << band;
  EXPECT_TRUE(has(band, "[map3d]")) << band;
  const std::string range = configError({{"min_range", "40"}});
  EXPECT_TRUE(has(range, "min_range")) << range;
  // An observation without 3D points is an input error naming the sensor and the class.
  mrpt::obs::CObservationOdometry odo;
  odo.sensorLabel = "WHEELS";
  const std::string e = errorOf<asf::InputError>([&] { Map3d().insertObservation(odo, CPose2D()); });
  EXPECT_TRUE(has(e, "WHEELS") && has(e, "CObservationOdometry")) << e;
}

/// A small scene seen from keyframes: the room from robot poses with the sensor 1 m up.
struct Keyframes {
  std::vector<CPose2D> poses{CPose2D(2.0, 1.5, 0.0), CPose2D(1.0, 1.0, 0.5),
                             CPose2D(3.0, 2.0, -1.0), CPose2D(2.5, 1.0, 2.0),
                             CPose2D(1.5, 2.2, 3.0)};
  CPose3D sensor{0, 0, 1.05, 0, 0, 0};
  std::vector<Points> clouds;
  Keyframes() {
    // Coarse points so the test stays fast: every other boundary voxel.
    const Points world = boxRoom(X0, X1, Y0, Y1, Z0, Z1, [](int i, int j, int k) {
      return (i + j + k) % 2 != 0;
    });
    for (const auto& p : poses) clouds.push_back(toSensor(world, CPose3D(p) + sensor));
  }
};

TEST(Map3d, RebuildAfterAMoveEqualsInsertingAtTheNewPose) {
  const Keyframes kf;
  std::vector<CPose2D> moved = kf.poses;
  moved[1] = CPose2D(1.3, 1.1, 0.55);  // a loop closure moves keyframe 1
  moved[3] = CPose2D(2.4, 1.2, 2.1);

  Map3d map;
  map.configure(params({{"max_keyframes_per_update", "100"}}));
  for (std::size_t i = 0; i < kf.poses.size(); ++i)
    map.addKeyframe(i, kf.poses[i], kf.sensor, kf.clouds[i]);
  const auto before = map.occupiedVoxelKeys();
  std::map<Map3d::KeyframeId, CPose2D> update;
  for (std::size_t i = 0; i < moved.size(); ++i) update[i] = moved[i];
  EXPECT_EQ(map.updateKeyframePoses(update), 2u);
  EXPECT_TRUE(map.rebuilding());
  EXPECT_EQ(map.rebuildStep(), kf.poses.size());
  EXPECT_FALSE(map.rebuilding());

  Map3d scratch;
  scratch.configure(params());
  for (std::size_t i = 0; i < moved.size(); ++i)
    scratch.addKeyframe(i, moved[i], kf.sensor, kf.clouds[i]);
  const auto after = map.occupiedVoxelKeys();
  EXPECT_NE(after, before);  // the move changed the map
  EXPECT_EQ(after, scratch.occupiedVoxelKeys());
  EXPECT_EQ(map.stats().free_voxels, scratch.stats().free_voxels);
  EXPECT_EQ(map.stats().rebuilds, 1u);

  // Poses within rebuild_threshold of the inserted ones do not rebuild.
  update[1] = CPose2D(1.31, 1.1, 0.55);
  EXPECT_EQ(map.updateKeyframePoses(update), 0u);
  EXPECT_FALSE(map.rebuilding());
}

TEST(Map3d, RebuildCapLimitsWorkPerStep) {
  const Keyframes kf;
  Map3d map;
  map.configure(params({{"max_keyframes_per_update", "2"}}));
  for (std::size_t i = 0; i < kf.poses.size(); ++i)
    map.addKeyframe(i, kf.poses[i], kf.sensor, kf.clouds[i]);
  (void)map.project();
  EXPECT_EQ(map.rebuildStep(), 0u);  // nothing to rebuild
  const auto before = map.occupiedVoxelKeys();
  const auto version = map.version();
  EXPECT_EQ(map.updateKeyframePoses({{0, CPose2D(2.3, 1.5, 0.2)}}), 1u);
  EXPECT_EQ(map.rebuildPending(), 5u);
  EXPECT_EQ(map.rebuildStep(), 2u);
  EXPECT_EQ(map.rebuildPending(), 3u);
  // Until the rebuild completes the current tree is the old one.
  EXPECT_EQ(map.occupiedVoxelKeys(), before);
  EXPECT_EQ(map.version(), version);
  // A keyframe added meanwhile goes into both trees.
  const CPose2D extra(2.0, 2.0, 1.0);
  map.addKeyframe(9, extra, kf.sensor, kf.clouds[0]);
  EXPECT_EQ(map.rebuildPending(), 4u);
  EXPECT_EQ(map.rebuildStep(), 2u);
  EXPECT_TRUE(map.rebuilding());
  EXPECT_EQ(map.rebuildStep(), 2u);
  EXPECT_FALSE(map.rebuilding());
  EXPECT_GT(map.version(), version);
  EXPECT_TRUE(map.project().rebuilt);
  EXPECT_FALSE(map.project().rebuilt);  // reported once

  Map3d scratch;
  scratch.configure(params());
  scratch.addKeyframe(0, CPose2D(2.3, 1.5, 0.2), kf.sensor, kf.clouds[0]);
  for (std::size_t i = 1; i < kf.poses.size(); ++i)
    scratch.addKeyframe(i, kf.poses[i], kf.sensor, kf.clouds[i]);
  scratch.addKeyframe(9, extra, kf.sensor, kf.clouds[0]);
  EXPECT_EQ(map.occupiedVoxelKeys(), scratch.occupiedVoxelKeys());

  // A keyframe that moves again after its re-insertion restarts the rebuild.
  map.updateKeyframePoses({{0, CPose2D(2.0, 1.5, 0.0)}});
  EXPECT_EQ(map.rebuildStep(), 2u);  // keyframes 0 and 1 re-inserted
  map.updateKeyframePoses({{0, CPose2D(2.2, 1.5, 0.0)}});
  EXPECT_EQ(map.rebuildPending(), 6u);
  EXPECT_THROW(map.addKeyframe(9, extra, kf.sensor, {}), asf::Error);
}

TEST(Map3d, LazyEvalGivesTheSameTree) {
  const Keyframes kf;
  Map3d a, b;
  a.configure(params());
  b.configure(params({{"lazy_eval", "true"}}));
  for (std::size_t i = 0; i < kf.poses.size(); ++i) {
    a.addKeyframe(i, kf.poses[i], kf.sensor, kf.clouds[i]);
    b.addKeyframe(i, kf.poses[i], kf.sensor, kf.clouds[i]);
  }
  EXPECT_EQ(a.occupiedVoxelKeys(), b.occupiedVoxelKeys());
  const asf::mapping::Map3dStats sa = a.stats(), sb = b.stats();
  EXPECT_EQ(sa.free_leaves, sb.free_leaves);
  EXPECT_EQ(sa.occupied_leaves, sb.occupied_leaves);
  EXPECT_EQ(sa.memory_bytes, sb.memory_bytes);  // pruned alike
  EXPECT_EQ(a.occupancyAt(0.05, 1.55, 1.05), b.occupancyAt(0.05, 1.55, 1.05));
}

TEST(Map3d, BtAndOtRoundTripThroughOctoMap) {
  const fs::path dir = fs::path(ASF_TEST_BINARY_DIR) / "test_map3d_files";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const Keyframes kf;
  Map3d map;
  map.configure(params());
  for (std::size_t i = 0; i < 2; ++i) map.addKeyframe(i, kf.poses[i], kf.sensor, kf.clouds[i]);
  const std::string bt = (dir / "m.bt").string(), ot = (dir / "m.ot").string();
  map.writeBt(bt);
  map.writeOt(ot);
  EXPECT_FALSE(fs::exists(bt + ".tmp"));

  octomap::OcTree read(0.5);
  ASSERT_TRUE(read.readBinary(bt));
  EXPECT_DOUBLE_EQ(read.getResolution(), kRes);
  std::vector<std::uint64_t> occ;
  std::size_t free_leaves = 0;
  const unsigned depth = read.getTreeDepth();
  for (auto it = read.begin_leafs(); it != read.end_leafs(); ++it) {
    if (!read.isNodeOccupied(*it)) {
      ++free_leaves;
      continue;
    }
    const auto k = it.getIndexKey();
    const unsigned span = 1u << (depth - it.getDepth());
    for (unsigned a = 0; a < span; ++a)
      for (unsigned b = 0; b < span; ++b)
        for (unsigned c = 0; c < span; ++c)
          occ.push_back((std::uint64_t(k[0] + a) << 32) | (std::uint64_t(k[1] + b) << 16) |
                        std::uint64_t(k[2] + c));
  }
  std::sort(occ.begin(), occ.end());
  EXPECT_EQ(occ, map.occupiedVoxelKeys());
  EXPECT_GT(free_leaves, 0u);

  std::unique_ptr<octomap::AbstractOcTree> any(octomap::AbstractOcTree::read(ot));
  auto* full = dynamic_cast<octomap::OcTree*>(any.get());
  ASSERT_NE(full, nullptr);
  // The .ot keeps the probabilities: every leaf as in the map.
  std::size_t leaves = 0;
  for (auto it = full->begin_leafs(); it != full->end_leafs(); ++it, ++leaves)
    ASSERT_NEAR(it->getOccupancy(), map.occupancyAt(it.getX(), it.getY(), it.getZ()), 1e-6);
  const asf::mapping::Map3dStats s = map.stats();
  EXPECT_EQ(leaves, s.occupied_leaves + s.free_leaves);
  const std::string err = errorOf<asf::Error>([&] { map.writeBt((dir / "no/such/m.bt").string()); });
  EXPECT_TRUE(has(err, "no/such/m.bt")) << err;
}

TEST(Map3d, MaxRangeCutsRaysToFreeSpace) {
  Map3d map;
  map.configure(params({{"max_range", "2.0"}}));
  // One point 5 m ahead: no hit, free space up to 2 m only.
  map.insertPoints({Eigen::Vector3f(5, 0, 0), Eigen::Vector3f(0, 0, 0),
                    Eigen::Vector3f(NAN, 0, 0)},
                   CPose3D(0.05, 0.05, 1.05, 0, 0, 0));
  EXPECT_LT(map.occupancyAt(1.55, 0.05, 1.05), 0.5);
  EXPECT_EQ(map.occupancyAt(2.55, 0.05, 1.05), -1.0);
  EXPECT_EQ(map.occupancyAt(5.05, 0.05, 1.05), -1.0);
  EXPECT_EQ(map.stats().occupied_voxels, 0u);
  EXPECT_EQ(map.stats().points_dropped, 2u);  // the origin and the NaN
}

TEST(Map3dHost, Vlp16Rawlog) {
  const std::string log = "/usr/share/mrpt/datasets/test_velodyne_VLP16.rawlog";
  if (!fs::exists(log)) GTEST_SKIP() << log << " missing (mrpt-common)";
  const fs::path dir = fs::path(ASF_TEST_BINARY_DIR) / "test_map3d_host";
  fs::remove_all(dir);
  const auto r = asf_test::runHost("map3d " + log + " --out " + dir.string() +
                                   " --set resolution=0.2 --set map3d.project_resolution=0.2"
                                   " --sensor-pose \"[0 0 0.8 0 0 0]\"");
  ASSERT_EQ(r.code, 0) << r.out;
  for (const char* f : {"map3d.bt", "map3d.ot", "projected.png", "map3d.json"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  std::ifstream in(dir / "map3d.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["observations_inserted"], 1);
  EXPECT_EQ(j["inserted_by_class"]["mrpt::obs::CObservationVelodyneScan"], 1);
  EXPECT_GT(j["stats"]["occupied_leaves"].get<int>(), 100);
  EXPECT_GT(j["points_per_s"].get<double>(), 0);
  EXPECT_TRUE(j["complete"].get<bool>());

  // Ground truth places the scan: the robot 5 m along x moves the map's x range by 5 m.
  const double x_min = j["projected"]["x_min"].get<double>();
  const double t = 1519637061.085268;  // the scan's time
  {
    std::ofstream gt(dir / "gt.txt");
    gt << std::setprecision(17) << "# t x y phi\n"
       << t - 0.1 << " 5 0 0\n" << t + 0.1 << " 5 0 0\n";  // within the 0.5 s max gap
  }
  const fs::path dir2 = dir / "gt";
  const auto g = asf_test::runHost("map3d " + log + " --out " + dir2.string() + " --gt " +
                                   (dir / "gt.txt").string() +
                                   " --set resolution=0.2 --set map3d.project_resolution=0.2"
                                   " --sensor-pose \"[0 0 0.8 0 0 0]\"");
  ASSERT_EQ(g.code, 0) << g.out;
  std::ifstream in2(dir2 / "map3d.json");
  const auto j2 = nlohmann::json::parse(in2);
  EXPECT_NEAR(j2["projected"]["x_min"].get<double>(), x_min + 5, 0.21);
  {
    std::ofstream gt(dir / "gt_late.txt");
    gt << std::setprecision(17) << t + 10 << " 5 0 0\n" << t + 11 << " 5 0 0\n";
  }
  const auto late = asf_test::runHost("map3d " + log + " --out " + dir2.string() + " --gt " +
                                      (dir / "gt_late.txt").string());
  EXPECT_EQ(late.code, 0) << late.out;
  EXPECT_TRUE(has(late.out, "skipped 1: no ground-truth pose")) << late.out;

  const auto bad = asf_test::runHost("map3d " + log + " --out " + dir.string() +
                                     " --set map3d.max_heigth=2");
  EXPECT_EQ(bad.code, 1);
  EXPECT_TRUE(has(bad.out, "max_heigth")) << bad.out;
  const auto other = asf_test::runHost("map3d " + log + " --out " + dir.string() +
                                       " --set map.resolution=2");
  EXPECT_EQ(other.code, 1);
  EXPECT_TRUE(has(other.out, "[map3d]")) << other.out;

  // A damaged log: the cause and the record, not MRPT's banner; a cut one is not a clean end
  // (issue 20, items 2 and 7).
  std::ifstream raw(log, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(raw)), {});
  std::string flipped = bytes;
  for (std::size_t i = 1; i < 9 && i < flipped.size(); ++i) flipped[i] = '\xff';
  for (const auto& [name, content] : {std::pair<std::string, std::string>{"flipped", flipped},
                                      {"cut", bytes.substr(0, bytes.size() / 2)}}) {
    const std::string damaged = (dir / (name + ".rawlog")).string();
    std::ofstream(damaged, std::ios::binary) << content;
    const auto r2 = asf_test::runHost("map3d " + damaged + " --out " + (dir / name).string());
    EXPECT_EQ(r2.code, 1) << name << "\n" << r2.out;
    EXPECT_TRUE(has(r2.out, damaged + ": record 0: ")) << name << "\n" << r2.out;
    EXPECT_FALSE(has(r2.out, "==== MRPT exception ====")) << name << "\n" << r2.out;
  }
}

}  // namespace
