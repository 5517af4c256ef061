// The 3D map in the pipeline: horizontal slices of 3D points (a virtual 2D laser), 3D
// observations through rawlogs, the grid merge, and a run whose robot has only a 3D sensor.
#include <asf/config.h>
#include <asf/errors.h>
#include <asf/mapping/map3d.h>
#include <asf/mapping/map_builder.h>
#include <asf/framework/pipeline.h>
#include <asf/io/rawlog_io.h>
#include <gtest/gtest.h>
#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/serialization/CArchive.h>
#include <octomap/OcTree.h>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <nlohmann/json.hpp>

#include "test_util.h"

namespace fs = std::filesystem;
using mrpt::obs::CObservationPointCloud;
using mrpt::poses::CPose2D;
using mrpt::poses::CPose3D;

namespace {

fs::path tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("asf_test_map3d_pipeline_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// A room [0, 6] x [-2, 2] with walls up to a ceiling at 2 m, and a low box on the floor
/// (below a 2D laser at 0.3 m and more).
struct Scene {
  double room_x1 = 6, room_y0 = -2, room_y1 = 2, ceiling = 2;
  double bx0 = 2.0, bx1 = 2.3, by0 = 0.4, by1 = 0.7, bz1 = 0.15;

  /// Distance along the unit ray o + t d to the first surface.
  double cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d) const {
    double t = std::numeric_limits<double>::infinity();
    auto plane = [&](double oc, double dc, double c) {
      if (std::abs(dc) < 1e-12) return;
      const double s = (c - oc) / dc;
      if (s > 1e-9) t = std::min(t, s);
    };
    plane(o.z(), d.z(), 0.0);
    plane(o.z(), d.z(), ceiling);
    plane(o.x(), d.x(), 0.0);
    plane(o.x(), d.x(), room_x1);
    plane(o.y(), d.y(), room_y0);
    plane(o.y(), d.y(), room_y1);
    // The box: slab test.
    double tmin = 0, tmax = std::numeric_limits<double>::infinity();
    const double lo[3] = {bx0, by0, 0.0}, hi[3] = {bx1, by1, bz1};
    bool hit = true;
    for (int a = 0; a < 3 && hit; ++a) {
      if (std::abs(d[a]) < 1e-12) {
        hit = o[a] >= lo[a] && o[a] <= hi[a];
        continue;
      }
      double t0 = (lo[a] - o[a]) / d[a], t1 = (hi[a] - o[a]) / d[a];
      if (t0 > t1) std::swap(t0, t1);
      tmin = std::max(tmin, t0);
      tmax = std::min(tmax, t1);
      hit = tmin <= tmax;
    }
    if (hit && tmin > 1e-9) t = std::min(t, tmin);
    return t;
  }

  /// What a 3D lidar at `sensor_on_robot` (translation only) sees from robot pose `robot`:
  /// points in the sensor frame, elevations -40..+10 deg every el_step, azimuths az0 + k
  /// az_step in the robot frame, max 8 m.
  CObservationPointCloud::Ptr cloud(const CPose2D& robot, const CPose3D& sensor_on_robot,
                                    double t, double az_step = 2, double az0 = -179,
                                    double el_step = 2.5) const {
    auto pc = mrpt::maps::CSimplePointsMap::Create();
    const CPose3D sensor = CPose3D(robot) + sensor_on_robot;
    const Eigen::Vector3d o(sensor.x(), sensor.y(), sensor.z());
    for (double el = -40; el <= 10.01; el += el_step)
      for (double az = az0; az < 180; az += az_step) {
        const double e = el * M_PI / 180, a = az * M_PI / 180 + robot.phi();
        const Eigen::Vector3d d(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
        const double r = cast(o, d);
        if (!(r < 8)) continue;
        const Eigen::Vector3d p = o + r * d;
        double lx, ly, lz;
        sensor.inverseComposePoint(p.x(), p.y(), p.z(), lx, ly, lz);
        pc->insertPoint(static_cast<float>(lx), static_cast<float>(ly), static_cast<float>(lz));
      }
    auto obs = CObservationPointCloud::Create();
    obs->pointcloud = pc;
    obs->sensorPose = sensor_on_robot;
    obs->sensorLabel = "LIDAR3D";
    obs->timestamp = mrpt::Clock::fromDouble(t);
    return obs;
  }
};

}  // namespace

TEST(Map3dPipeline, HorizontalSliceOfABoxRoom) {
  const Scene scene;
  const CPose2D robot(1.0, -1.0, 0.3);
  const CPose3D on_robot(0.1, 0, 0.5, 0, 0, 0);
  const auto obs = scene.cloud(robot, on_robot, 1.0);
  asf::mapping::SliceOptions o;
  o.min_z = 0.3;  // above the 0.15 m box
  o.max_z = 1.0;
  o.rays = 180;
  o.max_range = 8;
  const auto scan = asf::mapping::horizontalSlice(*obs, o);
  ASSERT_TRUE(scan);
  EXPECT_EQ(scan->getScanSize(), 180u);
  EXPECT_EQ(scan->sensorLabel, "LIDAR3D_SLICE");
  EXPECT_NEAR(scan->sensorPose.z(), 0.65, 1e-9);
  EXPECT_NEAR(scan->sensorPose.x(), 0.1, 1e-9);
  EXPECT_TRUE(scan->rightToLeft);
  // The cloud has one azimuth per bin, at its centre (every 2 degrees from -179): every valid
  // ray is exactly the horizontal distance from the sensor to the first surface at a height
  // of the band (walls are vertical), never the box below it.
  const CPose3D sensor = CPose3D(robot) + CPose3D(0.1, 0, 0, 0, 0, 0);
  auto expectedAt = [&](std::size_t i, double z) {
    const double a = robot.phi() - M_PI + M_PI / 180 + i * 2 * M_PI / 180;
    return scene.cast(Eigen::Vector3d(sensor.x(), sensor.y(), z),
                      Eigen::Vector3d(std::cos(a), std::sin(a), 0));
  };
  int valid = 0;
  for (std::size_t i = 0; i < scan->getScanSize(); ++i) {
    if (!scan->getScanRangeValidity(i)) continue;
    ++valid;
    EXPECT_NEAR(scan->getScanRange(i), expectedAt(i, 0.65), 1e-3) << "ray " << i;
  }
  EXPECT_EQ(valid, 180);  // every bearing sees a wall between 0.3 and 1.0 m

  // A band holding only the box and the foot of the walls: a ray is never nearer than the
  // first surface at that height, and the rays towards the box stop at it.
  o.min_z = 0.02;
  o.max_z = 0.14;
  const auto low = asf::mapping::horizontalSlice(*obs, o);
  ASSERT_TRUE(low);
  int on_box = 0;
  for (std::size_t i = 0; i < low->getScanSize(); ++i) {
    if (!low->getScanRangeValidity(i)) continue;
    const double e = expectedAt(i, 0.08);
    EXPECT_GE(low->getScanRange(i), e - 1e-3) << "ray " << i;
    if (e < expectedAt(i, 0.65) - 0.5 && std::abs(low->getScanRange(i) - e) < 1e-3) ++on_box;
  }
  EXPECT_GE(on_box, 3);  // the box spans about 8 degrees seen from the sensor

  // An observation without 3D points gives no slice, and says why.
  mrpt::obs::CObservationOdometry odo;
  std::string why;
  EXPECT_FALSE(asf::mapping::horizontalSlice(odo, o, &why));
  EXPECT_TRUE(asf_test::has(why, "no 3D points")) << why;
}

TEST(Map3dPipeline, MergeKeepsEveryObstacle) {
  // a: 0.1 m cells over [0, 1] x [0, 1]; b: 0.2 m cells over [0.5, 1.5] x [0, 1].
  mrpt::maps::COccupancyGridMap2D a(0, 1, 0, 1, 0.1f), b(0.5f, 1.5f, 0, 1, 0.2f);
  a.setPos(0.25, 0.25, 0.9f);  // free in a only
  a.setPos(0.65, 0.55, 0.9f);  // free in a, occupied in b
  b.setPos(0.65, 0.55, 0.1f);
  a.setPos(0.75, 0.15, 0.2f);  // occupied in a, free in b
  b.setPos(0.75, 0.15, 0.8f);
  b.setPos(1.3, 0.5, 0.85f);   // free in b only (outside a)
  a.setPos(0.95, 0.95, 0.8f);  // free in both: the more free one
  b.setPos(0.95, 0.95, 0.7f);
  a.setPos(0.15, 0.75, 0.3f);  // occupied in both: the more occupied one
  b.setPos(0.6, 0.75, 0.1f);   // (b's cell spans x in [0.5, 0.7])
  a.setPos(0.65, 0.75, 0.3f);
  const auto m = asf::mapping::mergeOccupancy(a, b);
  ASSERT_TRUE(m);
  EXPECT_NEAR(m->getResolution(), 0.1, 1e-6);
  EXPECT_LE(m->getXMin(), 0.0f + 1e-4);
  EXPECT_GE(m->getXMax(), 1.5f - 0.1f);
  auto at = [&](double x, double y) {
    return m->getPos(static_cast<float>(x), static_cast<float>(y));
  };
  EXPECT_NEAR(at(0.25, 0.25), 0.9, 0.02);
  EXPECT_NEAR(at(0.65, 0.55), 0.1, 0.02);
  EXPECT_NEAR(at(0.75, 0.15), 0.2, 0.02);
  EXPECT_NEAR(at(1.3, 0.5), 0.85, 0.02);
  EXPECT_NEAR(at(0.95, 0.95), 0.8, 0.03);  // MRPT stores log-odds in 8 bits
  EXPECT_NEAR(at(0.15, 0.75), 0.3, 0.03);
  EXPECT_NEAR(at(0.65, 0.75), 0.1, 0.03);
  EXPECT_NEAR(at(0.05, 0.85), 0.5, 0.02);  // neither knows
}

TEST(Map3dPipeline, RawlogCarriesObservations3d) {
  const fs::path dir = tempDir("rawlog");
  const Scene scene;
  const CPose3D on_robot(0, 0, 0.5, 0, 0, 0);
  const std::string path = (dir / "a.rawlog").string();
  {
    asf::io::RawlogWriter w(path);
    for (int k = 0; k < 3; ++k) {
      asf::SensorFrame f;
      f.timestamp = k;
      f.odometry = CPose2D(k ? 0.5 : 0, 0, 0);
      auto scan = std::make_shared<mrpt::obs::CObservation2DRangeScan>();
      scan->sensorLabel = "LASER";
      scan->resizeScan(3);
      for (int i = 0; i < 3; ++i) scan->setScanRange(i, 1.0f), scan->setScanRangeValidity(i, true);
      f.scan = scan;
      f.observations3d.push_back(scene.cloud(CPose2D(1 + 0.5 * k, -1, 0), on_robot, k));
      w.write(f);
    }
  }
  {
    asf::io::RawlogReaderOptions o;
    o.observations3d = true;
    asf::io::RawlogReader r(path, o);
    int n = 0;
    while (auto f = r.next()) {
      ASSERT_TRUE(f->scan);
      EXPECT_EQ(f->scan->sensorLabel, "LASER");
      ASSERT_EQ(f->observations3d.size(), 1u) << "frame " << n;
      auto pc = std::dynamic_pointer_cast<const CObservationPointCloud>(f->observations3d[0]);
      ASSERT_TRUE(pc);
      EXPECT_EQ(pc->pointcloud->size(),
                scene.cloud(CPose2D(1 + 0.5 * n, -1, 0), on_robot, n)->pointcloud->size());
      ++n;
    }
    EXPECT_EQ(n, 3);
    EXPECT_EQ(r.skippedScans(), 0u);
  }
  {
    asf::io::RawlogReader r(path);  // default: 3D observations are not read into frames
    while (auto f = r.next()) EXPECT_TRUE(f->observations3d.empty());
  }
  {
    // scan_from_3d: the scan is the cloud's slice; the LASER scans are not frame scans.
    asf::io::RawlogReaderOptions o;
    o.scan_from_3d = true;
    o.slice.min_z = 0.3;
    o.slice.rays = 90;
    asf::io::RawlogReader r(path, o);
    int n = 0;
    while (auto f = r.next()) {
      ASSERT_TRUE(f->scan);
      EXPECT_EQ(f->scan->sensorLabel, "LIDAR3D_SLICE");
      EXPECT_EQ(f->scan->getScanSize(), 90u);
      EXPECT_TRUE(f->observations3d.empty());
      EXPECT_NEAR(f->odometry.x(), n ? 0.5 : 0.0, 1e-12);
      ++n;
    }
    EXPECT_EQ(n, 3);
    EXPECT_EQ(r.skippedScans(), 3u);  // the LASER scans
  }
}

TEST(Map3dPipeline, ObservationOnlyLogFramesFromThe3dSensor) {
  const fs::path dir = tempDir("obsonly");
  const Scene scene;
  const CPose3D on_robot(0, 0, 0.5, 0, 0, 0);
  const std::string path = (dir / "b.rawlog").string();
  {
    mrpt::io::CFileGZOutputStream out(path);
    auto ar = mrpt::serialization::archiveFrom(out);
    for (int k = 0; k < 4; ++k) {
      mrpt::obs::CObservationOdometry odo;
      odo.odometry = CPose2D(1 + 0.4 * k, -1, 0);
      odo.timestamp = mrpt::Clock::fromDouble(k);
      ar << odo;
      ar << *scene.cloud(CPose2D(1 + 0.4 * k, -1, 0), on_robot, k + 0.01);
    }
  }
  asf::io::RawlogReaderOptions o;
  o.scan_from_3d = true;
  o.observations3d = true;
  o.slice.min_z = 0.3;
  asf::io::RawlogReader r(path, o);
  int n = 0;
  while (auto f = r.next()) {
    ASSERT_TRUE(f->scan) << "frame " << n;
    EXPECT_EQ(f->observations3d.size(), 1u);
    EXPECT_NEAR(f->odometry.x(), n ? 0.4 : 0.0, 1e-9);
    EXPECT_NEAR(f->timestamp, n + 0.01, 1e-6);
    ++n;
  }
  EXPECT_EQ(n, 4);
}

// A log the rawlog source gets no frame from is an error saying what the log holds, not an
// empty run: 3D observations only (the hint: scan_from_3d), or scans under another label.
TEST(Map3dPipeline, ALogWithoutAFrameSaysWhatItHolds) {
  const fs::path dir = tempDir("noframe");
  const Scene scene;
  const std::string clouds = (dir / "clouds.rawlog").string(),
                    hokuyo = (dir / "hokuyo.rawlog").string();
  {
    mrpt::io::CFileGZOutputStream out(clouds);
    auto ar = mrpt::serialization::archiveFrom(out);
    for (int k = 0; k < 4; ++k)
      ar << *scene.cloud(CPose2D(1 + 0.4 * k, -1, 0), CPose3D(0, 0, 0.5, 0, 0, 0), k);
  }
  {  // the observation-only layout: scans as records of their own
    mrpt::io::CFileGZOutputStream out(hokuyo);
    auto ar = mrpt::serialization::archiveFrom(out);
    for (int k = 0; k < 3; ++k) {
      mrpt::obs::CObservation2DRangeScan scan;
      scan.sensorLabel = "HOKUYO";
      scan.timestamp = mrpt::Clock::fromDouble(k);
      scan.resizeScan(3);
      for (int i = 0; i < 3; ++i) scan.setScanRange(i, 1.0f), scan.setScanRangeValidity(i, true);
      ar << scan;
    }
  }
  auto run = [&](const std::string& log, const std::string& extra) {
    const std::string ini =
        "[pipeline]\nsource = rawlog\nfrontend = odometry\nprogress_interval = 0\n"
        "[rawlog]\nfile = " +
        log + "\n" + extra;
    asf::framework::Registry reg;
    const auto rc =
        asf::framework::resolveConfig(asf::IniConfig::fromText(ini, (dir / "r.ini").string()), reg);
    asf::framework::Pipeline p(rc, (dir / "out").string());
    return asf_test::errorOf<asf::InputError>([&] { p.run(); });
  };
  const std::string e = run(clouds, "");
  EXPECT_TRUE(asf_test::has(e, "[rawlog] file = '" + clouds +
                                   "': no frame: it has no 2D laser scan; it "
                                   "holds 3D observations (4): scan_from_3d = true"))
      << e;
  const std::string e2 = run(hokuyo, "laser_label = LASER\n");
  EXPECT_TRUE(asf_test::has(
      e2, "no 2D laser scan labelled 'LASER' (laser_label; labels in the file: 'HOKUYO')"))
      << e2;
}

TEST(Map3dPipeline, NavigationMapNeedsTheMap3d) {
  asf::framework::Registry reg;
  const auto ini = asf::IniConfig::fromText(
      "[pipeline]\nsource = rawlog\nfrontend = odometry\nnavigation_map = merged\n"
      "[rawlog]\nfile = x.rawlog\n",
      "p.ini");
  const std::string msg =
      asf_test::errorOf<asf::Error>([&] { asf::framework::resolveConfig(ini, reg); });
  EXPECT_TRUE(asf_test::has(msg, "navigation_map")) << msg;
  EXPECT_TRUE(asf_test::has(msg, "map3d = true")) << msg;
  const auto typo = asf::IniConfig::fromText(
      "[pipeline]\nsource = rawlog\nfrontend = odometry\n[map3d]\nresolutoin = 0.1\n", "q.ini");
  const std::string msg2 =
      asf_test::errorOf<asf::Error>([&] { asf::framework::resolveConfig(typo, reg); });
  EXPECT_TRUE(asf_test::has(msg2, "resolutoin")) << msg2;
  EXPECT_TRUE(asf_test::has(msg2, "resolution")) << msg2;  // did you mean
}

TEST(Map3dPipeline, RobotWithOnlyA3dSensor) {
  // A robot drives along y = -1 past a low box; its only sensor is a 3D lidar 0.5 m up.
  const fs::path dir = tempDir("run");
  const Scene scene;
  const CPose3D on_robot(0, 0, 0.5, 0, 0, 0);
  const std::string log = (dir / "drive.rawlog").string();
  {
    asf::io::RawlogWriter w(log);
    for (int k = 0; k <= 16; ++k) {
      asf::SensorFrame f;
      f.timestamp = 0.5 * k;
      f.odometry = CPose2D(k ? 0.25 : 0, 0, 0);
      f.odometry_cov = Eigen::Matrix3d::Identity() * 1e-6;
      f.observations3d.push_back(
          scene.cloud(CPose2D(0.8 + 0.25 * k, -1, 0), on_robot, f.timestamp, 1, -179.5, 1.25));
      w.write(f);
    }
  }
  auto run = [&](const std::string& nav, const std::string& name) {
    const std::string ini =
        "[pipeline]\nsource = rawlog\nfrontend = odometry\nmap3d = true\n"
        "navigation_map = " + nav + "\nprogress_interval = 0\n"
        "[rawlog]\nfile = " + log + "\nobservations3d = true\nscan_from_3d = true\n"
        "slice_min_z = 0.3\nslice_max_z = 1.0\nslice_rays = 360\n"
        "[odometry]\nkeyframe_distance = 0.5\n"
        "[map3d]\nresolution = 0.05\nmax_range = 8\nmin_height = 0.05\nmax_height = 1.0\n";
    asf::framework::Registry reg;
    const auto rc = asf::framework::resolveConfig(
        asf::IniConfig::fromText(ini, (dir / (name + ".ini")).string()), reg);
    asf::framework::Pipeline p(rc, (dir / name).string());
    return p.run();
  };
  const asf::framework::RunSummary merged = run("merged", "merged");
  EXPECT_EQ(merged.steps, 17);
  const fs::path out = dir / "merged";
  for (const char* f :
       {"map3d.bt", "map3d.ot", "map3d.json", "map3d_grid.png", "map.png", "report.html"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  std::ifstream in(out / "map3d.json");
  const auto j = nlohmann::json::parse(in);
  // One cloud per keyframe (the odometry front-end adds a node once it has driven more than
  // 0.5 m: every 0.75 m here, 6 nodes over 4 m); the other clouds are not used.
  EXPECT_EQ(merged.nodes, 6u);
  EXPECT_EQ(j["keyframes"].get<std::size_t>(), merged.nodes);
  EXPECT_EQ(j["observations_not_at_keyframes"].get<std::size_t>(), 17u - merged.nodes);
  EXPECT_EQ(j["navigation_map"], "merged");

  // The octree (read back by OctoMap): the box's near face is occupied, the air above the
  // robot's path and above the box is free. Map frame = the first pose (0.8, -1): the box
  // [2, 2.3] x [0.4, 0.7] x [0, 0.15] is at x in [1.2, 1.5], y in [1.4, 1.7].
  octomap::OcTree tree(0.05);
  ASSERT_TRUE(tree.readBinary((out / "map3d.bt").string()));
  auto occ = [&](double x, double y, double z) {
    const octomap::OcTreeNode* n = tree.search(x, y, z);
    return n ? n->getOccupancy() : -1.0;
  };
  double face = 0;
  for (double x : {1.27, 1.32, 1.37, 1.42})
    for (double z : {0.025, 0.075, 0.125})
      face = std::max({face, occ(x, 1.37, z), occ(x, 1.42, z)});
  EXPECT_GT(face, 0.5);
  EXPECT_GE(occ(1.35, 0.0, 0.3), 0.0);
  EXPECT_LT(occ(1.35, 0.0, 0.3), 0.5);
  EXPECT_GE(occ(1.35, 1.55, 0.5), 0.0);
  EXPECT_LT(occ(1.35, 1.55, 0.5), 0.5);

  // The 2D laser slice (0.3..1.0 m) never sees the box, the 3D map does: in the merged grid
  // (map.png, the grid the segmenter, policy and coverage use) the box is an obstacle, in
  // the scans' grid alone it is free floor.
  const asf::framework::RunSummary scan2d = [&] {
    const std::string ini =
        "[pipeline]\nsource = rawlog\nfrontend = odometry\nprogress_interval = 0\n"
        "[rawlog]\nfile = " + log + "\nscan_from_3d = true\n"
        "slice_min_z = 0.3\nslice_max_z = 1.0\nslice_rays = 360\n"
        "[odometry]\nkeyframe_distance = 0.5\n";
    asf::framework::Registry reg;
    asf::framework::Pipeline p(
        asf::framework::resolveConfig(asf::IniConfig::fromText(ini, (dir / "s.ini").string()), reg),
        (dir / "scan2d").string());
    return p.run();
  }();
  EXPECT_EQ(scan2d.nodes, merged.nodes);
  EXPECT_FALSE(fs::exists(dir / "scan2d" / "map3d.bt"));
  // Cells of map.png (the run's navigation grid) around the box footprint that are
  // obstacles (grey below 100: p(free) < 0.4), and one free-floor cell far from it.
  auto probe = [&](const fs::path& run, int& dark, int& floor_gray) {
    std::ifstream sin(run / "summary.json");
    const auto sj = nlohmann::json::parse(sin)["map"];
    const cv::Mat img = cv::imread((run / "map.png").string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(img.empty());
    ASSERT_EQ(img.rows, sj["height"].get<int>());
    const double res = sj["resolution"].get<double>(), x0 = sj["x_min"].get<double>(),
                 y0 = sj["y_min"].get<double>();
    auto at = [&](double x, double y) {
      const int cx = static_cast<int>((x - x0) / res), cy = static_cast<int>((y - y0) / res);
      return static_cast<int>(img.at<unsigned char>(img.rows - 1 - cy, cx));
    };
    dark = 0;
    for (double x = 1.2; x <= 1.5; x += res)
      for (double y = 1.4; y <= 1.7; y += res) dark += at(x, y) < 100;
    floor_gray = at(3.0, 1.0);
  };
  int dark2d = 0, floor2d = 0, dark_merged = 0, floor_merged = 0;
  probe(dir / "scan2d", dark2d, floor2d);
  probe(out, dark_merged, floor_merged);
  EXPECT_EQ(dark2d, 0);         // the 2D slice never sees the box
  EXPECT_GE(dark_merged, 6);    // the 3D map does: its near face at least (6 cells wide)
  EXPECT_GT(floor2d, 140);      // free floor (p(free) > 0.55) in both, as free in the merge
  EXPECT_GE(floor_merged, floor2d - 3);  // as the more certain of the two
}

TEST(Map3dPipeline, TiltedLaserAndMergedMapAvoidTheLowBoxes) {
  // configs/low_obstacles.ini: boxes 0.20-0.25 m tall under a 2D laser at 0.3 m. The frontier
  // explorer with the 3D map merged into its grid explores the whole world; with the 2D
  // scans' grid alone it keeps driving into the first box, which it never sees.
  auto run = [](bool with3d, const std::string& name) {
    auto ini = asf::IniConfig::fromFile(ASF_TEST_SOURCE_DIR "/configs/low_obstacles.ini");
    ini.set("pipeline", "progress_interval", "0");
    ini.set("pipeline", "verbosity", "WARN");
    ini.set("sim2d", "record", with3d ? "true" : "false");
    // Every move of a keyframe by the back-end re-inserts the octree's keyframes (below).
    ini.set("map3d", "rebuild_threshold", "1e-6");
    if (!with3d) {
      ini.set("pipeline", "map3d", "false");
      ini.set("pipeline", "navigation_map", "scan2d");
    }
    asf::framework::Registry reg;
    asf::framework::Pipeline p(asf::framework::resolveConfig(ini, reg), tempDir(name).string());
    return p.run();
  };
  const asf::framework::RunSummary with3d = run(true, "low3d");
  EXPECT_TRUE(with3d.finished) << with3d.stop_reason;
  EXPECT_GE(with3d.coverage, 0.98);
  EXPECT_TRUE(fs::exists(fs::temp_directory_path() / "asf_test_map3d_pipeline_low3d" /
                         "map3d_grid.png"));

  // Keyframes follow the back-end: the final octree is the one built by inserting each
  // keyframe's tilted scan (from the run's rawlog) at its final pose (keyframes.txt).
  const fs::path out = fs::temp_directory_path() / "asf_test_map3d_pipeline_low3d";
  std::ifstream jin(out / "map3d.json");
  const auto j = nlohmann::json::parse(jin);
  EXPECT_GE(j["stats"]["rebuilds"].get<int>(), 1);
  std::vector<std::pair<double, CPose2D>> kf;
  {
    std::ifstream in(out / "keyframes.txt");
    std::string line;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') continue;
      std::istringstream ls(line);
      double t, x, y, phi;
      ls >> t >> x >> y >> phi;
      kf.emplace_back(t, CPose2D(x, y, phi));
    }
  }
  ASSERT_EQ(kf.size(), with3d.nodes);
  auto ini = asf::IniConfig::fromFile(ASF_TEST_SOURCE_DIR "/configs/low_obstacles.ini");
  ini.set("map3d", "rebuild_threshold", "1e-6");
  asf::framework::Registry reg;
  asf::mapping::Map3d fresh;
  fresh.configure(asf::framework::resolveConfig(ini, reg).map3d);
  asf::io::RawlogReaderOptions o;
  o.observations3d = true;
  o.laser_label = "LASER";
  asf::io::RawlogReader reader((out / "sim2d.rawlog").string(), o);
  std::size_t next = 0;
  while (auto f = reader.next()) {
    if (next < kf.size() && std::abs(f->timestamp - kf[next].first) < 1e-6) {
      ASSERT_EQ(f->observations3d.size(), 1u);
      fresh.addKeyframe(next, kf[next].second, *f->observations3d[0]);
      ++next;
    }
  }
  EXPECT_EQ(next, kf.size());
  octomap::OcTree run_tree(0.05);
  ASSERT_TRUE(run_tree.readBinary((out / "map3d.bt").string()));
  std::size_t run_occupied = 0;
  for (auto it = run_tree.begin_leafs(); it != run_tree.end_leafs(); ++it)
    if (run_tree.isNodeOccupied(*it)) run_occupied += std::size_t(1) << (3 * (16 - it.getDepth()));
  EXPECT_EQ(run_occupied, fresh.stats().occupied_voxels);
  EXPECT_EQ(fresh.stats().occupied_voxels, j["stats"]["occupied_voxels"].get<std::size_t>());

  const asf::framework::RunSummary only2d = run(false, "low2d");
  EXPECT_LT(only2d.coverage, 0.9) << "the 2D laser alone was expected to miss the boxes";
}
