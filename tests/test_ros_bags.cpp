// ROS bags to rawlogs (asf bag2rawlog): the CDR decoder on hand-laid bytes, and whole bags
// written by independent writers (ROS 1: the official ROS 1 Python library,
// scripts/make-rosbag1-fixture.sh; ROS 2: Foxglove's CDR serializer and the sqlite3 shell,
// scripts/make-rosbag2-fixture.sh) converted and compared message by message with what the
// writer put in; a real log through each kind of bag and back; the errors a user meets name
// the bag and what is there instead.
#include <asf/errors.h>
#include <asf/io/ground_truth.h>
#include <asf/io/rosbag2.h>
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/serialization/CArchive.h>
#include <unistd.h>
#include <zstd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "test_util.h"

namespace {

namespace fs = std::filesystem;
using asf::io::CdrReader;

// ----------------------------------------------------------------------- CDR by hand -----

/// Little-endian CDR of a std_msgs/Header-led message: stamp (7, 500), frame_id "ab", then a
/// float64 (aligned to 8 after the header's end) and a float32 sequence.
std::vector<std::uint8_t> handMessage(bool little_endian) {
  std::vector<std::uint8_t> b{0, static_cast<std::uint8_t>(little_endian ? 1 : 0), 0, 0};
  auto put = [&](const void* p, std::size_t n) {
    const auto* c = static_cast<const std::uint8_t*>(p);
    std::vector<std::uint8_t> v(c, c + n);
    if (!little_endian) std::reverse(v.begin(), v.end());
    b.insert(b.end(), v.begin(), v.end());
  };
  auto pad = [&](std::size_t n) {
    while ((b.size() - 4) % n) b.push_back(0);
  };
  const std::int32_t sec = 7;
  const std::uint32_t nsec = 500, len = 3, count = 2;
  put(&sec, 4);
  put(&nsec, 4);
  put(&len, 4);
  b.insert(b.end(), {'a', 'b', 0});
  pad(8);
  const double d = 2.5;
  put(&d, 8);
  put(&count, 4);
  for (float f : {1.5f, -3.25f}) put(&f, 4);
  return b;
}

TEST(Rosbag2, CdrReadsAlignedFieldsInBothByteOrders) {
  for (bool le : {true, false}) {
    const auto b = handMessage(le);
    ASSERT_EQ(b.size(), 4u + 8 + 4 + 3 + 1 + 8 + 4 + 8) << "the layout this test means";
    CdrReader c(b.data(), b.size(), "hand");
    EXPECT_EQ(c.i32(), 7);
    EXPECT_EQ(c.u32(), 500u);
    EXPECT_EQ(c.str(), "ab");
    EXPECT_EQ(c.f64(), 2.5);
    EXPECT_EQ(c.f32seq(), (std::vector<float>{1.5f, -3.25f}));
    EXPECT_EQ(c.offset(), b.size());
  }
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const asf::InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

TEST(Rosbag2, CdrRefusesTruncatedAndForeignData) {
  auto b = handMessage(true);
  b.resize(b.size() - 14);  // inside the float64
  EXPECT_NE(errorOf([&] {
              CdrReader c(b.data(), b.size(), "m");
              c.i32(), c.u32(), c.str(), c.f64(), c.f32seq();
            }).find("m: the message ends"),
            std::string::npos);
  std::vector<std::uint8_t> pl{0, 3, 0, 0, 0, 0, 0, 0};  // PL_CDR_LE
  EXPECT_NE(errorOf([&] { CdrReader(pl.data(), pl.size(), "m"); }).find("not plain CDR"),
            std::string::npos);
  std::vector<std::uint8_t> huge{0, 1, 0, 0, 0xff, 0xff, 0xff, 0x7f};
  EXPECT_NE(errorOf([&] {
              CdrReader(huge.data(), huge.size(), "m").f32seq();
            }).find("longer than the message"),
            std::string::npos);
}

// ------------------------------------------------------------- bags by another writer -----

/// A fixture bag: the folder the writer filled (expected.json too) and the bag in it.
struct Fixture {
  fs::path dir, bag;
  bool ok() const { return !dir.empty(); }
};

/// Writes the fixture bag VARIANT of `format` (ros1: the official ROS 1 Python library; ros2:
/// Foxglove's CDR serializer and the sqlite3 shell; ros2_mcap: the same messages in MCAP
/// storage by Foxglove's MCAP writer, chunks zstd-compressed) into a fresh folder; none when the
/// writer's tools cannot be had here. `extra`: more arguments for the writer.
Fixture fixture(const std::string& format, const std::string& variant,
                const std::string& extra = "") {
  const fs::path dir = fs::temp_directory_path() /
                       ("asf_test_" + format + "_" + variant + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string cmd = "ASF_TEST_TOOLS='" ASF_TEST_BINARY_DIR
                          "/test-tools' bash '" ASF_TEST_SOURCE_DIR "/scripts/make-" +
                          std::string(format == "ros1" ? "rosbag1" : "rosbag2") + "-fixture.sh' '" +
                          dir.string() + "' " + variant + " " + extra + " > '" + dir.string() +
                          ".log' 2>&1";
  if (std::system(cmd.c_str()) != 0) return {};
  return {dir, format == "ros1" ? dir / "data.bag" : dir};
}

#define FIXTURE_OR_SKIP(var, format, variant)                                              \
  const Fixture var = fixture(format, variant);                                            \
  if (!var.ok()) {                                                                         \
    GTEST_SKIP() << "the independent " << format << " bag writer could not run here (see " \
                 << "scripts/make-rosbag1-fixture.sh, make-rosbag2-fixture.sh)";           \
  }

/// Both formats through the same tests.
class RosBag : public ::testing::TestWithParam<std::string> {};

/// Every record of an observation-only rawlog.
std::vector<mrpt::serialization::CSerializable::Ptr> records(const fs::path& rawlog) {
  mrpt::io::CFileGZInputStream f(rawlog.string());
  auto ar = mrpt::serialization::archiveFrom(f);
  std::vector<mrpt::serialization::CSerializable::Ptr> out;
  for (;;) {
    try {
      out.push_back(ar.ReadObject());
    } catch (const std::exception&) {
      break;  // the end of the file
    }
  }
  return out;
}

mrpt::Clock::time_point clockOf(std::int64_t sec, std::int64_t nanosec) {
  // The writer's nanoseconds are whole multiples of MRPT's 100 ns tick.
  return mrpt::Clock::fromDouble(static_cast<double>(sec)) + mrpt::Clock::duration(nanosec / 100);
}

/// The fixture `variant` converted: every record as the writer's expected.json has it.
void checkConverted(const std::string& format, const std::string& variant) {
  FIXTURE_OR_SKIP(fx, format, variant);
  const fs::path out = fx.dir / "out.rawlog";
  asf::io::BagToRawlogOptions o;
  o.input = fx.bag.string();
  o.output = out.string();
  const auto rep = asf::io::bagToRawlog(o);
  EXPECT_EQ(rep.scan_topic, "/scan");
  EXPECT_EQ(rep.odom_topic, variant == "tf_odom" ? "/tf" : "/odom");
  EXPECT_EQ(rep.odom_from_tf, variant == "tf_odom");
  EXPECT_EQ(rep.laser_frame, "laser");
  EXPECT_EQ(rep.base_frame, "base_link");
  EXPECT_EQ(rep.laser_pose_from, "/tf_static");
  // base_link -> laser_mount (0.2, 0, 0.1), then -> laser (0.05, 0.01, 0.2, yaw 10 deg).
  EXPECT_NEAR(rep.laser_pose.x(), 0.25, 1e-12);
  EXPECT_NEAR(rep.laser_pose.y(), 0.01, 1e-12);
  EXPECT_NEAR(rep.laser_pose.z(), 0.3, 1e-12);
  EXPECT_NEAR(rep.laser_pose.yaw(), 10 * M_PI / 180, 1e-12);

  std::ifstream ef(fx.dir / "expected.json");
  const nlohmann::json expected = nlohmann::json::parse(ef);
  const auto recs = records(out);
  ASSERT_EQ(recs.size(), expected.size());
  for (std::size_t k = 0; k < recs.size(); ++k) {
    const auto& e = expected[k];
    const auto t = clockOf(e["sec"].get<std::int64_t>(), e["nanosec"].get<std::int64_t>());
    if (e["kind"] == "odom") {
      auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(recs[k]);
      ASSERT_TRUE(odo) << "record " << k << " is not odometry";
      EXPECT_EQ(odo->timestamp, t) << k;
      EXPECT_EQ(odo->odometry.x(), e["x"].get<double>()) << k;
      EXPECT_EQ(odo->odometry.y(), e["y"].get<double>()) << k;
      EXPECT_NEAR(odo->odometry.phi(), e["yaw"].get<double>(), 1e-12) << k;
      continue;
    }
    auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(recs[k]);
    ASSERT_TRUE(scan) << "record " << k << " is not a scan";
    EXPECT_EQ(scan->timestamp, t) << k;
    const auto& r = e["ranges"];
    ASSERT_EQ(scan->getScanSize(), r.size());
    // angle_max agrees with angle_min + (n - 1) increment here: the rays span [min, max].
    const double amin = static_cast<float>(e["angle_min"].get<double>());
    const double amax = static_cast<float>(e["angle_max"].get<double>());
    EXPECT_EQ(scan->aperture, static_cast<float>(amax - amin));
    EXPECT_TRUE(scan->rightToLeft);
    EXPECT_EQ(scan->maxRange, 30.0f);
    // The sensor pose's yaw is the mount's plus the scan's middle angle.
    const double mid = (amin + amax) / 2;
    EXPECT_NEAR(scan->sensorPose.yaw(), 10 * M_PI / 180 + mid, 1e-6);
    EXPECT_NEAR(scan->sensorPose.x(), 0.25, 1e-12);
    for (std::size_t i = 0; i < r.size(); ++i) {
      const bool valid =
          r[i].is_number() && r[i].get<double>() >= 0.1f && r[i].get<double>() <= 30.0;
      EXPECT_EQ(scan->getScanRangeValidity(i), valid) << k << " ray " << i;
      if (valid) {
        EXPECT_EQ(scan->getScanRange(i), static_cast<float>(r[i].get<double>()));
      }
    }
  }
  fs::remove_all(fx.dir);
}

TEST_P(RosBag, ConvertedRecordsAreTheMessagesWritten) {
  for (const char* variant : {"plain", "tf_odom"}) {
    SCOPED_TRACE(variant);
    checkConverted(GetParam(), variant);
    if (HasFatalFailure() || IsSkipped()) return;
  }
}

TEST_P(RosBag, ErrorsNameTheBagAndWhatIsThere) {
  FIXTURE_OR_SKIP(fx, GetParam(), "two_scans");
  asf::io::BagToRawlogOptions o;
  o.input = fx.bag.string();
  o.output = (fx.dir / "out.rawlog").string();
  // Two LaserScan topics: one must be chosen; the message lists the topics present.
  std::string e = errorOf([&] { asf::io::bagToRawlog(o); });
  EXPECT_NE(e.find("several sensor_msgs/msg/LaserScan topics (/scan, /scan_back)"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("/chatter (std_msgs/msg/String, 1)"), std::string::npos) << e;
  o.scan_topic = "/nope";
  e = errorOf([&] { asf::io::bagToRawlog(o); });
  EXPECT_NE(e.find("no topic /nope; topics: "), std::string::npos) << e;
  EXPECT_NE(e.find("/scan (sensor_msgs/msg/LaserScan, 20)"), std::string::npos) << e;
  o.scan_topic = "/chatter";
  e = errorOf([&] { asf::io::bagToRawlog(o); });
  EXPECT_NE(e.find("/chatter is a std_msgs/msg/String, not a sensor_msgs/msg/LaserScan"),
            std::string::npos)
      << e;
  o.scan_topic = "/scan_back";
  o.base_frame = "chassis";
  e = errorOf([&] { asf::io::bagToRawlog(o); });
  EXPECT_NE(e.find("laser frame 'laser' has no transform to the base frame 'chassis'"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("laser_mount -> laser"), std::string::npos) << e;
  EXPECT_FALSE(fs::exists(fx.dir / "out.rawlog")) << "nothing written on an error";
  fs::remove_all(fx.dir);
}

TEST_P(RosBag, MissingTransformsAndCompressionAreReported) {
  FIXTURE_OR_SKIP(no_tf, GetParam(), "no_tf");
  asf::io::BagToRawlogOptions o;
  o.input = no_tf.bag.string();
  o.output = (no_tf.dir / "out.rawlog").string();
  EXPECT_NE(errorOf([&] { asf::io::bagToRawlog(o); }).find("in /tf_static (none)"),
            std::string::npos);
  o.laser_pose = mrpt::poses::CPose3D(0.1, 0, 0.2, 0, 0, 0);  // given by hand instead
  const auto rep = asf::io::bagToRawlog(o);
  EXPECT_EQ(rep.scans, 20u);
  EXPECT_EQ(rep.odometry, 20u);
  EXPECT_EQ(rep.laser_pose_from, "--laser-pose");
  fs::remove_all(no_tf.dir);
  o.laser_pose.reset();
  if (GetParam() != "ros1") {  // rosbag2 compression other than zstd: an error naming it
    FIXTURE_OR_SKIP(lz4, GetParam(), "lz4_compressed");
    o.input = lz4.bag.string();
    o.output = (lz4.dir / "out.rawlog").string();
    const std::string e = errorOf([&] { asf::io::bagToRawlog(o); });
    EXPECT_NE(e.find("metadata.yaml: compressed with 'lz4' (FILE mode"), std::string::npos) << e;
    fs::remove_all(lz4.dir);
    return;
  }
  for (const char* c : {"bz2", "lz4"}) {  // ROS 1's compressed chunks are read
    FIXTURE_OR_SKIP(z, GetParam(), c);
    o.input = z.bag.string();
    o.output = (z.dir / "out.rawlog").string();
    const auto r = asf::io::bagToRawlog(o);
    EXPECT_EQ(r.scans, 20u) << c;
    EXPECT_EQ(records(z.dir / "out.rawlog").size(), 40u) << c;
    fs::remove_all(z.dir);
  }
}

// ------------------------------------------------- a real log through a bag and back -----

/// Seconds and nanoseconds of an MRPT time point (exact: whole 100 ns ticks).
std::pair<std::int64_t, std::int64_t> secNsec(mrpt::Clock::time_point t) {
  auto sec = static_cast<std::int64_t>(std::floor(mrpt::Clock::toDouble(t)));
  auto rest = (t - mrpt::Clock::fromDouble(static_cast<double>(sec))).count() * 100;
  while (rest < 0) --sec, rest += 1000000000;
  while (rest >= 1000000000) ++sec, rest -= 1000000000;
  return {sec, rest};
}

/// The records of an observation-only rawlog as the fixture writer's input (make_rosbag2.js
/// `from`): every scan's ends, ranges (null where invalid) and stamps; the odometry poses.
nlohmann::json dump(const std::vector<mrpt::serialization::CSerializable::Ptr>& recs) {
  nlohmann::json out{{"records", nlohmann::json::array()}};
  for (const auto& r : recs) {
    if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(r)) {
      const auto [sec, ns] = secNsec(o->timestamp);
      out["records"].push_back({{"kind", "odom"},
                                {"sec", sec},
                                {"nanosec", ns},
                                {"x", o->odometry.x()},
                                {"y", o->odometry.y()},
                                {"yaw", o->odometry.phi()}});
    } else if (auto s = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(r)) {
      const auto [sec, ns] = secNsec(s->timestamp);
      const double half = s->aperture / 2.0;  // exact: a float halved
      nlohmann::json ranges = nlohmann::json::array();
      for (std::size_t i = 0; i < s->getScanSize(); ++i)
        ranges.push_back(s->getScanRangeValidity(i) ? nlohmann::json(s->getScanRange(i))
                                                    : nlohmann::json(nullptr));
      out["records"].push_back(
          {{"kind", "scan"},
           {"sec", sec},
           {"nanosec", ns},
           {"angle_min", -half},
           {"angle_max", half},
           {"angle_increment", s->aperture / static_cast<double>(s->getScanSize() - 1)},
           {"range_max", s->maxRange},
           {"ranges", ranges}});
      out["laser"] = {{"x", s->sensorPose.x()},
                      {"y", s->sensorPose.y()},
                      {"z", s->sensorPose.z()},
                      {"yaw", s->sensorPose.yaw()}};
    }
  }
  return out;
}

TEST_P(RosBag, ARealLogThroughABagGivesTheSameFramesAndTrajectory) {
  const std::string log = ASF_TEST_SHARED_DIR "/datasets/carmen/orebro-corrected.log.gz";
  if (!fs::exists(log)) GTEST_SKIP() << "../shared is not available here (" << log << ")";
  const fs::path dir = fs::temp_directory_path() /
                       ("asf_test_" + GetParam() + "_real_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto conv = asf_test::runHost("carmen2rawlog -q --synth-odometry --seed 1 -i " + log +
                                      " -o " + (dir / "a.rawlog").string());
  ASSERT_EQ(conv.code, 0) << conv.out;
  const auto a = records(dir / "a.rawlog");
  std::ofstream(dir / "records.json") << dump(a).dump();
  // The same data written as a bag by the independent writer, read back by asf.
  const Fixture fx = fixture(GetParam(), "from", "'" + (dir / "records.json").string() + "'");
  if (!fx.ok())
    GTEST_SKIP() << "the independent " << GetParam() << " bag writer could not run here";
  const auto back = asf_test::runHost("bag2rawlog -q -i " + fx.bag.string() + " -o " +
                                      (dir / "b.rawlog").string());
  ASSERT_EQ(back.code, 0) << back.out;
  const auto b = records(dir / "b.rawlog");
  ASSERT_EQ(a.size(), b.size());
  double worst_yaw = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (auto oa = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(a[k])) {
      auto ob = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(b[k]);
      ASSERT_TRUE(ob) << k;
      EXPECT_EQ(oa->timestamp, ob->timestamp) << k;
      EXPECT_EQ(oa->odometry.x(), ob->odometry.x()) << k;
      EXPECT_EQ(oa->odometry.y(), ob->odometry.y()) << k;
      // A ROS pose holds its heading as a quaternion: sin and cos of half of it.
      worst_yaw = std::max(worst_yaw,
                           std::abs(mrpt::math::wrapToPi(oa->odometry.phi() - ob->odometry.phi())));
      continue;
    }
    auto sa = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(a[k]);
    auto sb = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(b[k]);
    ASSERT_TRUE(sa && sb) << k;
    EXPECT_EQ(sa->timestamp, sb->timestamp) << k;
    EXPECT_EQ(sa->aperture, sb->aperture) << k;
    EXPECT_EQ(sa->rightToLeft, sb->rightToLeft) << k;
    EXPECT_EQ(sa->maxRange, sb->maxRange) << k;
    EXPECT_EQ(sa->sensorPose, sb->sensorPose) << k;
    ASSERT_EQ(sa->getScanSize(), sb->getScanSize()) << k;
    for (std::size_t i = 0; i < sa->getScanSize(); ++i) {
      EXPECT_EQ(sa->getScanRangeValidity(i), sb->getScanRangeValidity(i)) << k << " " << i;
      EXPECT_EQ(sa->getScanRange(i), sb->getScanRange(i)) << k << " " << i;
    }
  }
  EXPECT_LT(worst_yaw, 1e-15);
  // SLAM on both: the same keyframes, to 1e-9 m (the CARMEN converter's laser pose holds a
  // negative zero where the bag's holds +0, which moves the last bits of some sums).
  for (const char* v : {"a", "b"}) {
    const auto run = asf_test::runHost(
        "run " ASF_TEST_SOURCE_DIR "/configs/slam_carmen.ini -o " + (dir / v).string() +
        " --set rawlog.file=" + (dir / (std::string(v) + ".rawlog")).string() +
        " --set rawlog.ground_truth=");
    ASSERT_EQ(run.code, 0) << run.out;
  }
  std::ifstream ka(dir / "a" / "keyframes.txt"), kb(dir / "b" / "keyframes.txt");
  std::string la, lb;
  std::size_t lines = 0;
  double worst = 0;
  while (std::getline(ka, la) && std::getline(kb, lb)) {
    if (la.empty() || la[0] == '#') continue;
    std::istringstream pa(la), pb(lb);
    double ta, xa, ya, fa, tb, xb, yb, fb;
    pa >> ta >> xa >> ya >> fa;
    pb >> tb >> xb >> yb >> fb;
    EXPECT_EQ(ta, tb);
    worst = std::max({worst, std::abs(xa - xb), std::abs(ya - yb)});
    ++lines;
  }
  EXPECT_GT(lines, 200u);
  EXPECT_LT(worst, 1e-6) << "keyframes moved by the bag";
  // The bag itself as the rawlog source's file: the same run as its converted rawlog's.
  const auto direct = asf_test::runHost(
      "run " ASF_TEST_SOURCE_DIR "/configs/slam_carmen.ini -o " + (dir / "bag_run").string() +
      " --set rawlog.file=" + fx.bag.string() + " --set rawlog.ground_truth=");
  ASSERT_EQ(direct.code, 0) << direct.out;
  std::ifstream gb(dir / "b" / "graph.g2o"), gd(dir / "bag_run" / "graph.g2o");
  const std::string tb((std::istreambuf_iterator<char>(gb)), std::istreambuf_iterator<char>());
  const std::string td((std::istreambuf_iterator<char>(gd)), std::istreambuf_iterator<char>());
  EXPECT_FALSE(tb.empty());
  EXPECT_EQ(tb, td) << "the bag as a source differs from its converted rawlog";
  std::cout << "bag round trip: " << lines << " keyframes, largest difference " << worst
            << " m, heading " << worst_yaw << " rad\n";
  fs::remove_all(dir);
  fs::remove_all(fx.dir);
}

INSTANTIATE_TEST_SUITE_P(Formats, RosBag, ::testing::Values("ros1", "ros2", "ros2_mcap"));

// A ground-truth topic (a simulator's /ground_truth Odometry) becomes a ground-truth file, with
// /odom still chosen as the odometry; through the rawlog source, the run's ground truth.
TEST_P(RosBag, AGroundTruthTopicBecomesTheGroundTruthFile) {
  FIXTURE_OR_SKIP(fx, GetParam(), "with_gt");
  asf::io::BagToRawlogOptions o;
  o.input = fx.bag.string();
  o.output = (fx.dir / "out.rawlog").string();
  o.gt_topic = "/ground_truth";
  o.gt_output = (fx.dir / "gt.txt").string();
  const auto rep = asf::io::bagToRawlog(o);
  EXPECT_EQ(rep.odom_topic, "/odom");
  EXPECT_EQ(rep.gt_poses, 20u);
  std::ifstream ef(fx.dir / "expected_gt.json");
  const nlohmann::json want = nlohmann::json::parse(ef);
  const auto got = asf::io::readGroundTruth(o.gt_output);
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t k = 0; k < got.size(); ++k) {
    EXPECT_NEAR(got[k].t, want[k]["sec"].get<double>() + want[k]["nanosec"].get<double>() * 1e-9,
                1e-6);
    EXPECT_NEAR(got[k].pose.x(), want[k]["x"].get<double>(), 1e-9) << k;
    EXPECT_NEAR(got[k].pose.y(), want[k]["y"].get<double>(), 1e-9) << k;
    EXPECT_NEAR(got[k].pose.phi(), want[k]["yaw"].get<double>(), 1e-9) << k;
  }
  o.gt_topic = "/scan";
  EXPECT_NE(errorOf([&] {
              asf::io::bagToRawlog(o);
            }).find("ground-truth topic /scan is a sensor_msgs/msg/LaserScan"),
            std::string::npos);
  // The bag as a source with bag_gt_topic: the run is scored against it.
  const auto run = asf_test::runHost(
      "run " ASF_TEST_SOURCE_DIR "/configs/replay_rawlog.ini -o " + (fx.dir / "run").string() +
      " --set rawlog.file=" + fx.bag.string() + " --set rawlog.ground_truth= " +
      "--set rawlog.bag_gt_topic=/ground_truth --set rawlog.ground_truth_max_gap=2");
  ASSERT_EQ(run.code, 0) << run.out;
  EXPECT_TRUE(fs::exists(fx.dir / "run" / "bag.gt.txt"));
  std::ifstream sf(fx.dir / "run" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(sf);
  EXPECT_GT(summary["ate_poses"].get<int>(), 0) << summary.dump();
  fs::remove_all(fx.dir);
}

// rosbag2's own zstd compression, per message and of the whole storage file: the same records.
TEST(RosBag2Compression, ZstdMessagesAndFilesAreRead) {
  for (const char* storage : {"plain@sqlite3_zmsg", "plain@sqlite3_zfile"}) {
    SCOPED_TRACE(storage);
    checkConverted("ros2", storage);
    if (HasFatalFailure() || IsSkipped()) return;
  }
}

/// This process's decompressed copies of FILE-mode bags in the temporary folder.
std::size_t scratchFiles() {
  const std::string prefix = "asf_rosbag2_" + std::to_string(::getpid()) + "_";
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(fs::temp_directory_path()))
    n += e.path().filename().string().rfind(prefix, 0) == 0;
  return n;
}

// A FILE-mode bag's copy leaves the temporary folder once SQLite has it open: the reader still
// reads every message, and a kill leaves nothing behind.
TEST(RosBag2Compression, TheDecompressedCopyIsGoneWhileTheReaderReads) {
  FIXTURE_OR_SKIP(fx, "ros2", "plain@sqlite3_zfile");
  asf::io::Rosbag2Reader reader(fx.bag.string());
  EXPECT_EQ(scratchFiles(), 0u);
  const auto* scan = reader.topic("/scan");
  ASSERT_NE(scan, nullptr);
  std::size_t seen = 0;
  reader.forEach({"/scan"}, [&](const std::string&, std::int64_t, const std::uint8_t*,
                                std::size_t) { ++seen; });
  EXPECT_EQ(seen, scan->messages);
  EXPECT_GT(seen, 0u);
  fs::remove_all(fx.dir);
}

// A storage file of zeros, 3 KiB of zstd for 80 MiB: refused past 64 MiB (1000-fold of its size
// is less), naming the file, with no copy left in the temporary folder.
TEST(RosBag2Compression, AFileExpandingBeyondAnyRecordersIsRefused) {
  const fs::path dir = asf_test::freshTempDir("asf_test_zstd_bomb_" + std::to_string(::getpid()));
  const std::string zeros(80u << 20, '\0');
  std::string z(ZSTD_compressBound(zeros.size()), '\0');
  const std::size_t n = ZSTD_compress(z.data(), z.size(), zeros.data(), zeros.size(), 1);
  ASSERT_FALSE(ZSTD_isError(n));
  z.resize(n);
  asf_test::writeFile(dir / "bomb_0.db3.zstd", z);
  asf_test::writeFile(dir / "metadata.yaml",
            "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: sqlite3\n"
            "  relative_file_paths:\n    - bomb_0.db3.zstd\n  compression_format: zstd\n"
            "  compression_mode: FILE\n");
  const std::string e = errorOf([&] { asf::io::Rosbag2Reader r(dir.string()); });
  EXPECT_NE(e.find((dir / "bomb_0.db3.zstd").string() + ": expands more than 1000-fold"),
            std::string::npos)
      << e;
  EXPECT_EQ(scratchFiles(), 0u);
  fs::remove_all(dir);
}

// MCAP: chunks uncompressed, LZ4 or zstd, the folder or the .mcap file itself; a damaged file
// is an error naming it.
TEST(RosBagMcap, EveryChunkCompressionAndADamagedFile) {
  for (const char* storage : {"mcap", "mcap_lz4"}) {
    FIXTURE_OR_SKIP(fx, "ros2", std::string("plain@") + storage);
    asf::io::BagToRawlogOptions o;
    o.input = (fx.dir / "data.mcap").string();  // the file itself, without metadata.yaml
    o.output = (fx.dir / "out.rawlog").string();
    const auto rep = asf::io::bagToRawlog(o);
    EXPECT_EQ(rep.scans, 20u) << storage;
    EXPECT_EQ(rep.odometry, 20u) << storage;
    EXPECT_EQ(records(fx.dir / "out.rawlog").size(), 40u) << storage;
    // Cut in the middle: the record it ends in is named.
    const auto size = fs::file_size(fx.dir / "data.mcap");
    fs::resize_file(fx.dir / "data.mcap", size / 2);
    const std::string e = errorOf([&] { asf::io::bagToRawlog(o); });
    EXPECT_NE(e.find("data.mcap: the file ends inside the record at byte"), std::string::npos)
        << storage << ": " << e;
    fs::remove_all(fx.dir);
  }
}

}  // namespace
