// sim2d worlds from ROS map_server maps (map_image = X.yaml): the YAML's resolution, origin and
// pixel classes, unknown cells blocked (not entered, seen through), free or wall as
// map_unknown says, the start at the free cell farthest from any wall when none is given, and
// the keys the YAML sets refused beside it.
#include <asf/errors.h>
#include <asf/framework/registry.h>
#include <asf/source.h>
#include <gtest/gtest.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "../sim2d_world.h"

namespace {

namespace fs = std::filesystem;
using KV = std::map<std::string, std::string>;

// 3.0 m x 2.0 m at 0.05 m/px, lower-left corner at (-1, 2): a black border two pixels thick;
// columns 40-49 (x in [1, 1.5) in the map frame) unknown (205), 50-51 a black wall, 52-57
// unknown again; the rest free (254). Written here as a binary PGM, not by asf.
constexpr double kOx = -1, kOy = 2;
std::string mapServerWorld() {
  static const std::string yaml = [] {
    const fs::path dir = fs::path(ASF_TEST_BINARY_DIR) / "tests" / "sim2d_map_server";
    fs::create_directories(dir);
    const std::string tag = std::to_string(::getpid());  // tests run in parallel processes
    {
      std::ofstream pgm(dir / ("world" + tag + ".pgm"), std::ios::binary);
      pgm << "P5\n60 40\n255\n";
      for (int row = 0; row < 40; ++row)
        for (int col = 0; col < 60; ++col) {
          int v = 254;
          if (col < 2 || row < 2 || col >= 58 || row >= 38)
            v = 0;
          else if (col >= 50 && col < 52)
            v = 0;
          else if (col >= 40 && col < 58)
            v = 205;
          pgm.put(static_cast<char>(v));
        }
    }
    const fs::path y = dir / ("world" + tag + ".yaml");
    std::ofstream(y) << "image: world" << tag << ".pgm\nresolution: 0.05\norigin: [" << kOx << ", "
                     << kOy << ", 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
    return y.string();
  }();
  return yaml;
}

std::shared_ptr<const asf::framework::PluginInfo> info() {
  static auto i = asf::framework::Registry::loadFile(ASF_TEST_PLUGIN_DIR "/source_sim2d.so");
  return i;
}

asf::framework::PluginHandle<asf::Source> make(KV kv) {
  kv.emplace("record", "false");
  kv.emplace("map_image", mapServerWorld());
  auto h = asf::framework::Registry::create<asf::Source>(info());
  h->setMinLoggingLevel(mrpt::system::LVL_ERROR);
  asf::PluginContext ctx;
  ctx.seed = 1;
  h->configure(
      asf::Params::fromSpecs("sim2d", info()->descriptor->keys, info()->descriptor->num_keys, kv),
      ctx);
  return h;
}

/// The range straight ahead of a robot at map (1.0, 1.0) + origin facing +x (laser 0.1 m
/// ahead of it, no noise).
double rangeAhead(const std::string& unknown) {
  auto src = make({{"map_unknown", unknown},
                   {"start_x", std::to_string(kOx + 1.0)},
                   {"start_y", std::to_string(kOy + 1.0)},
                   {"laser_rays", "3"},
                   {"range_sigma", "0"}});
  const auto f = src->next();
  EXPECT_TRUE(f && f->scan);
  if (!f || !f->scan) return NAN;
  EXPECT_TRUE(f->scan->getScanRangeValidity(1));
  return f->scan->getScanRange(1);
}

TEST(Sim2dMapServer, UnknownCellsAreSeenThroughUnlessTheyAreWalls) {
  // The wall at map x = 2.5, the unknown band from x = 2.0; the laser at x = 1.1.
  EXPECT_NEAR(rangeAhead("blocked"), 1.4, 0.06);
  EXPECT_NEAR(rangeAhead("free"), 1.4, 0.06);
  EXPECT_NEAR(rangeAhead("wall"), 0.9, 0.06);
}

TEST(Sim2dMapServer, StartsAtTheFreeCellFarthestFromTheWalls) {
  // Free: map x in [0.1, 2.0), y in [0.1, 1.9) (unknown cells are walls): the farthest cells are
  // 0.9 m from the walls below and above, at y = 1.0, x in [1.0, 1.1].
  auto src = make({});
  const auto f = src->next();
  ASSERT_TRUE(f && f->ground_truth);
  EXPECT_NEAR(f->ground_truth->y() - kOy, 1.0, 0.03);
  EXPECT_GE(f->ground_truth->x() - kOx, 0.95);
  EXPECT_LE(f->ground_truth->x() - kOx, 1.15);
}

TEST(Sim2dMapServer, KeysTheYamlSetsAreRefused) {
  for (const char* key : {"resolution", "origin_x", "origin_y", "occupied_threshold"}) {
    std::string e = "(no ConfigError)";
    try {
      make({{key, "0.3"}});
    } catch (const asf::ConfigError& x) {
      e = x.what();
    }
    EXPECT_NE(e.find(key), std::string::npos) << e;
    EXPECT_NE(e.find("map_server YAML"), std::string::npos) << e;
  }
}

TEST(Sim2dMapServer, BlockedUnknownCellsKeepTheRobotOut) {
  // The world itself, classes as a map_server map's: 254 free, 0 wall, 205 unknown.
  asf::sim2d::ImageWorldOptions o;
  const std::string yaml = mapServerWorld();
  o.file = yaml.substr(0, yaml.size() - 5) + ".pgm";
  o.resolution = 0.05;
  std::array<asf::sim2d::PixelClass, 256> classes;
  classes.fill(asf::sim2d::PixelClass::Free);
  classes[0] = asf::sim2d::PixelClass::Wall;
  classes[205] = asf::sim2d::PixelClass::Unknown;
  o.classes = classes;
  o.unknown = asf::sim2d::UnknownCells::Blocked;
  const auto blocked = asf::sim2d::World::fromImage(o);
  EXPECT_EQ(blocked.unknownCells(), 36u * 16u);  // (10 + 6) columns x 36 rows
  EXPECT_NEAR(blocked.clearance(1.9, 1.0), 0.1, 0.03);
  EXPECT_TRUE(blocked.sweepCollides({1.5, 1.0}, {2.2, 1.0}, 0.2));
  EXPECT_FALSE(blocked.occupiedAt(2.2, 1.0)) << "unknown is not a wall";
  o.unknown = asf::sim2d::UnknownCells::Free;
  const auto free = asf::sim2d::World::fromImage(o);
  EXPECT_EQ(free.unknownCells(), 0u);
  EXPECT_NEAR(free.clearance(1.9, 1.0), 0.6, 0.03);
  EXPECT_FALSE(free.sweepCollides({1.5, 1.0}, {2.2, 1.0}, 0.2));
  o.unknown = asf::sim2d::UnknownCells::Wall;
  const auto wall = asf::sim2d::World::fromImage(o);
  EXPECT_TRUE(wall.occupiedAt(2.2, 1.0));
  EXPECT_EQ(wall.wallCells(), blocked.wallCells() + blocked.unknownCells());
}

}  // namespace
