// The log converters (libs/io): Rawseeds CSV <-> rawlog round trip on a simulated
// run, bzip2 input, bad lines, missing streams, the real Rawseeds ground truth, and the host
// commands. CARMEN logs: test_carmen.cpp.
#include <asf/errors.h>
#include <asf/io/rawlog_io.h>
#include <asf/framework/registry.h>
#include <asf/source.h>
#include <asf/io/carmen.h>
#include <asf/io/rawseeds.h>
#include <asf/io/text_io.h>
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/serialization/CArchive.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Cholesky>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "convert_test_util.h"
#include "test_util.h"

namespace fs = std::filesystem;
namespace cv = asf::io;
using asf_test::errorOf;
using asf_test::has;
using asf_test::readFrames;
using asf_test::readLines;
using asf_test::readText;
using asf_test::TempDir;
using asf_test::writeText;
using mrpt::poses::CPose2D;

namespace {

// ------------------------------------------------------------------------------- helpers

/// Every record of a rawlog: (class name, sensorLabel, time in seconds).
struct Record {
  std::string cls, label;
  double t;
  mrpt::serialization::CSerializable::Ptr obj;
};
std::vector<Record> readRecords(const std::string& rawlog) {
  mrpt::io::CFileGZInputStream in(rawlog);
  auto ar = mrpt::serialization::archiveFrom(in);
  std::vector<Record> out;
  for (;;) {
    mrpt::serialization::CSerializable::Ptr o;
    try {
      o = ar.ReadObject();
    } catch (const mrpt::serialization::CExceptionEOF&) {
      break;
    }
    auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation>(o);
    out.push_back({o->GetRuntimeClass()->className, obs ? obs->sensorLabel : "",
                   obs ? mrpt::Clock::toDouble(obs->timestamp) : 0.0, o});
  }
  return out;
}

double angleDiff(double a, double b) { return std::abs(mrpt::math::wrapToPi(a - b)); }

// --------------------------------------------------------------------- a simulated run

/// Frames of the segment_world simulator driving a loop in an 8 m x 5 m room with a
/// 181-ray / 180-degree laser (6 m range, so some rays are invalid), laser 0.08 m ahead.
std::vector<asf::SensorFrame> simulate(int n) {
  // Kept loaded for the whole test program: frames hold objects made by the plugin.
  static auto info =
      asf::framework::Registry::loadFile(ASF_TEST_PLUGIN_DIR "/source_segment_world.so");
  auto src = asf::framework::Registry::create<asf::Source>(info);
  asf::PluginContext ctx;
  ctx.seed = 11;
  src->configure(asf::Params::fromSpecs("segment_world", info->descriptor->keys,
                                        info->descriptor->num_keys,
                                        {{"world", "rectangle"},
                                         {"room_width", "8"},
                                         {"room_height", "5"},
                                         {"start_x", "1"},
                                         {"start_y", "1"},
                                         {"laser_rays", "181"},
                                         {"laser_fov_deg", "180"},
                                         {"laser_max_range", "6"},
                                         {"sensor_x", "0.08"},
                                         {"max_steps", std::to_string(n)}}),
                 ctx);
  const asf::Goal goals[] = {{6.5, 1.2, 0.2}, {6.5, 4.0, 0.2}, {1.5, 4.0, 0.2}, {1.2, 1.2, 0.2}};
  CPose2D believed(1, 1, 0);
  std::size_t g = 0;
  std::vector<asf::SensorFrame> out;
  while (auto f = src->next()) {
    believed = believed + f->odometry;
    const auto st = src->status();
    if (st != asf::NavStatus::Moving) {
      asf::NavigationContext nc;
      nc.robot_estimate = believed;
      src->navigate(goals[g++ % 4], nc);
    }
    out.push_back(std::move(*f));
  }
  return out;
}

void writeRun(const std::vector<asf::SensorFrame>& frames, const std::string& rawlog,
              const std::string& gt) {
  asf::io::RawlogWriter w(rawlog);
  asf::io::GroundTruthWriter g(gt);
  for (const auto& f : frames) {
    w.write(f);
    g.write(f.timestamp, *f.ground_truth);
  }
}

cv::RawseedsToRawlogOptions toRawlog(const std::string& dir, const std::string& dataset,
                                     const std::string& out) {
  cv::RawseedsToRawlogOptions o;
  o.dir = dir;
  o.dataset = dataset;
  o.output = out;
  return o;
}

// A small hand-written Rawseeds session: 4 odometry lines at 50 Hz, front scans at 75 Hz,
// one rear scan. Ranges of the front scans: R(i) = 1 + 0.01 i, except R1 = 0 (no echo),
// R2 = 81.91 (beyond 80 m) and R3 = 80.5.
std::string sickLine(const std::string& t, double base) {
  std::string l = t + ",181,0";
  for (int i = 0; i < 181; ++i) {
    const double r = i == 0 ? 0 : i == 1 ? 81.91 : i == 2 ? 80.5 : base + 0.01 * i;
    l += "," + cv::fixed(r);
  }
  return l;
}

void writeSmallSession(const std::string& dir) {
  writeText(dir + "/SMALL-ODOMETRY_XYT.csv",
            "1235604664.000000,10,100,200,0.000000,0.000000,0.000000\n"
            "1235604664.020000,11,101,201,0.010000,0.000000,0.001000\n"
            "1235604664.040000,12,102,202,0.020000,0.000100,0.002000\n"
            "1235604664.060000,13,103,203,0.030000,0.000200,0.003000\n");
  writeText(dir + "/SMALL-SICK_FRONT.csv",
            sickLine("1235604664.000000", 1) + "\n" + sickLine("1235604664.013333", 2) + "\n" +
                sickLine("1235604664.026667", 3) + "\n" + sickLine("1235604664.040000", 4) +
                "\n");
  writeText(dir + "/SMALL-SICK_REAR.csv", sickLine("1235604664.005000", 5) + "\n");
}

}  // namespace

// ----------------------------------------------------------------------------- text_io

TEST(ConvertTextIo, TimestampsAreExactToTheMicrosecond) {
  auto s = cv::parseStamp("1235604664.443286");
  ASSERT_TRUE(s);
  EXPECT_EQ(s->sec, 1235604664);
  EXPECT_EQ(s->usec, 443286);
  EXPECT_EQ(s->str(), "1235604664.443286");
  s = cv::parseStamp("32.9068");
  ASSERT_TRUE(s);
  EXPECT_EQ(s->str(), "32.906800");
  EXPECT_EQ(cv::parseStamp("7")->str(), "7.000000");
  EXPECT_EQ(cv::parseStamp("99999999999.999999")->str(), "99999999999.999999");  // the largest
  EXPECT_EQ(cv::parseStamp("1.9999996")->str(), "2.000000");  // rounded, carried
  EXPECT_EQ(cv::parseStamp("2.5e-06")->str(), "0.000003");    // decimal exponent form
  // 11000000000000 s (a fuzzed Rawseeds line) overflowed the microsecond arithmetic.
  for (const char* bad : {"", "-1.5", "abc", "1.2.3", "1e99", "nan", ".", "11000000000000",
                          "999999999999999.5", "1e14", "100000000000"})
    EXPECT_FALSE(cv::parseStamp(bad)) << bad;
  // One microsecond apart = ten 100 ns clock ticks, also near 1.2e9 s where a double would
  // blur it.
  const auto a = cv::parseStamp("1235604664.443286")->toClock();
  const auto b = cv::parseStamp("1235604664.443287")->toClock();
  EXPECT_EQ((b - a).count(), 10);
  EXPECT_NEAR(mrpt::Clock::toDouble(a), 1235604664.443286, 1e-6);
  EXPECT_EQ(cv::Stamp::fromSeconds(12.3).str(), "12.300000");
}

TEST(ConvertTextIo, FieldsAndNumbers) {
  const auto f = cv::splitFields("1235603336.014442, -0.000581, -0.035454,0.001580", ',');
  ASSERT_EQ(f.size(), 4u);
  EXPECT_EQ(f[1], "-0.000581");
  EXPECT_EQ(cv::parseDouble(f[1]).value(), -0.000581);
  EXPECT_TRUE(cv::splitFields("   ", ',').empty());
  EXPECT_EQ(cv::splitFields("a,,b", ',').size(), 3u);
  EXPECT_EQ(cv::splitWhitespace("  FLASER\t180  1.0 ").size(), 3u);
  EXPECT_FALSE(cv::parseDouble("1.0x"));
  EXPECT_FALSE(cv::parseDouble("inf"));
  EXPECT_TRUE(std::isinf(*cv::parseNumber("inf")));
  EXPECT_EQ(cv::parseDouble("+2.5").value(), 2.5);
  EXPECT_EQ(cv::parseInt("181").value(), 181);
  EXPECT_FALSE(cv::parseInt("181.0"));
  EXPECT_EQ(cv::fixed(-0.0000001), "0.000000");
  EXPECT_EQ(cv::fixed(-1.5), "-1.500000");
}

TEST(ConvertTextIo, LineReaderPlainGzipAndConcatenatedBzip2) {
  TempDir tmp;
  {
    cv::Bz2Writer a(tmp / "a.bz2");
    a.write("one\ntwo\n");
    a.close();
    cv::Bz2Writer b(tmp / "b.bz2");
    b.write("three\r\nfour");  // CRLF, and no newline at the end
    b.close();
  }
  EXPECT_EQ(readText(tmp / "a.bz2").substr(0, 3), "BZh");
  // Two bzip2 streams back to back, as parallel compressors write them.
  writeText(tmp / "ab.bz2", readText(tmp / "a.bz2") + readText(tmp / "b.bz2"));
  const std::vector<std::string> want{"one", "two", "three", "four"};
  EXPECT_EQ(readLines(tmp / "ab.bz2"), want);
  {
    cv::LineReader r(tmp / "ab.bz2");
    std::string l;
    while (r.next(l)) {
    }
    EXPECT_EQ(r.lineNumber(), 4u);
    EXPECT_DOUBLE_EQ(r.progress(), 1.0);
  }
  writeText(tmp / "p.txt", "one\ntwo\nthree\r\nfour");
  EXPECT_EQ(readLines(tmp / "p.txt"), want);
  {
    mrpt::io::CFileGZOutputStream gz(tmp / "g.txt.gz");
    const std::string t = "one\ntwo\nthree\nfour\n";
    gz.Write(t.data(), t.size());
  }
  EXPECT_EQ(readLines(tmp / "g.txt.gz"), want);
  {
    mrpt::io::CFileGZOutputStream gz(tmp / "long.txt.gz");
    std::string t;
    for (int i = 0; i < 20000; ++i) t += "line " + std::to_string(i * 7919 % 10007) + "\n";
    gz.Write(t.data(), t.size());
  }
  writeText(tmp / "cut.txt.gz", readText(tmp / "long.txt.gz").substr(0, 4000));
  EXPECT_EQ(readLines(tmp / "long.txt.gz").size(), 20000u);
  // A truncated download must not pass for a shorter log.
  const std::string ge = errorOf<asf::InputError>([&] { readLines(tmp / "cut.txt.gz"); });
  EXPECT_TRUE(has(ge, tmp / "cut.txt.gz: gzip data")) << ge;
  EXPECT_TRUE(has(ge, "truncated")) << ge;

  writeText(tmp / "bad.bz2", "BZh91AY&SYnot really bzip2 data at all");
  EXPECT_TRUE(has(errorOf<asf::InputError>([&] { readLines(tmp / "bad.bz2"); }),
                  tmp / "bad.bz2"));
  writeText(tmp / "cut.bz2", readText(tmp / "a.bz2").substr(0, 20));  // truncated
  EXPECT_TRUE(has(errorOf<asf::InputError>([&] { readLines(tmp / "cut.bz2"); }), "cut.bz2"));
  EXPECT_TRUE(has(errorOf<asf::InputError>([&] { cv::LineReader r(tmp / "none.csv"); }),
                  "none.csv: no such file"));
}

// ------------------------------------------------------------------------------ Rawseeds

TEST(Rawseeds, SimulatedRunSurvivesRawlogToCsvToRawlog) {
  TempDir tmp;
  const auto frames = simulate(400);
  ASSERT_EQ(frames.size(), 400u);
  writeRun(frames, tmp / "sim.rawlog", tmp / "sim.gt.txt");

  cv::RawlogToRawseedsOptions a;
  a.rawlog = tmp / "sim.rawlog";
  a.gt_input = tmp / "sim.gt.txt";
  a.dir = tmp / "csv";
  a.dataset = "SIM";
  const auto ra = cv::rawlogToRawseeds(a);
  EXPECT_EQ(ra.frames, 400u);
  EXPECT_EQ(ra.scans, 400u);
  EXPECT_EQ(ra.odometry_lines, 400u);
  EXPECT_EQ(ra.gt_lines, 400u);

  // The documented line formats.
  const auto laser = readLines(tmp / "csv/SIM-SICK_FRONT.csv");
  const auto odo = readLines(tmp / "csv/SIM-ODOMETRY_XYT.csv");
  const auto gtl = readLines(tmp / "csv/SIM-GROUNDTRUTH.csv");
  ASSERT_EQ(laser.size(), 400u);
  ASSERT_EQ(odo.size(), 400u);
  ASSERT_EQ(gtl.size(), 400u);
  const auto l1 = cv::splitFields(laser[1], ',');
  ASSERT_EQ(l1.size(), 184u);
  EXPECT_EQ(l1[0], "0.100000");
  EXPECT_EQ(l1[1], "181");
  EXPECT_EQ(l1[2], "0");
  for (std::size_t k : {0u, 1u, 399u}) {
    const auto o = cv::splitFields(odo[k], ',');
    ASSERT_EQ(o.size(), 7u);
    EXPECT_EQ(o[1], std::to_string(k));  // rolling counter
    EXPECT_EQ(o[2], "0");
    EXPECT_EQ(o[3], "0");
    EXPECT_EQ(cv::splitFields(gtl[k], ',').size(), 13u);
  }

  cv::RawseedsToRawlogOptions b = toRawlog(tmp / "csv", "SIM", tmp / "back.rawlog.gz");
  b.gt_output = tmp / "back.gt.txt";
  const auto rb = cv::rawseedsToRawlog(b);
  EXPECT_EQ(rb.scans, 400u);
  EXPECT_EQ(rb.odometry, 400u);
  EXPECT_EQ(rb.gt_poses, 400u);
  ASSERT_EQ(rb.streams.size(), 3u);
  EXPECT_EQ(rb.streams[0].stream, "ODOMETRY_XYT");
  EXPECT_EQ(rb.streams[1].stream, "SICK_FRONT");
  EXPECT_EQ(rb.streams[2].stream, "GROUNDTRUTH");
  for (const auto& s : rb.streams) EXPECT_EQ(s.bad_lines, 0u) << s.stream;
  EXPECT_FALSE(fs::exists(tmp / "back.rawlog.gz.part"));
  // gzip-compressed as the name asks.
  EXPECT_EQ(static_cast<unsigned char>(readText(tmp / "back.rawlog.gz")[0]), 0x1f);

  asf::io::RawlogReaderOptions ro;
  ro.ground_truth_file = tmp / "back.gt.txt";
  const auto back = readFrames(tmp / "back.rawlog.gz", ro);
  ASSERT_EQ(back.size(), frames.size());
  CPose2D p_orig, p_back;
  std::size_t valid = 0, invalid = 0;
  double path = 0, turned = 0;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    SCOPED_TRACE("frame " + std::to_string(k));
    EXPECT_NEAR(back[k].timestamp, frames[k].timestamp, 1e-6);
    const auto& s0 = *frames[k].scan;
    ASSERT_TRUE(back[k].scan);
    const auto& s1 = *back[k].scan;
    EXPECT_EQ(s1.sensorLabel, "SICK_FRONT");
    ASSERT_EQ(s1.getScanSize(), 181u);
    EXPECT_FLOAT_EQ(s1.aperture, static_cast<float>(M_PI));
    EXPECT_TRUE(s1.rightToLeft);
    EXPECT_NEAR(s1.sensorPose.x(), 0.08, 1e-12);
    EXPECT_NEAR(s1.sensorPose.z(), 0.45, 1e-12);
    EXPECT_NEAR(s1.sensorPose.yaw(), 0.0, 1e-12);
    for (std::size_t i = 0; i < 181; ++i) {
      ASSERT_EQ(s1.getScanRangeValidity(i), s0.getScanRangeValidity(i)) << "ray " << i;
      if (s0.getScanRangeValidity(i)) {
        EXPECT_NEAR(s1.getScanRange(i), s0.getScanRange(i), 2e-6) << "ray " << i;
        ++valid;
      } else {
        ++invalid;
      }
    }
    // Integrated odometry: the written poses are the original increments composed.
    p_orig = p_orig + frames[k].odometry;
    p_back = p_back + back[k].odometry;
    EXPECT_NEAR(p_back.x(), p_orig.x(), 2e-6);
    EXPECT_NEAR(p_back.y(), p_orig.y(), 2e-6);
    EXPECT_LT(angleDiff(p_back.phi(), p_orig.phi()), 2e-6);
    path += frames[k].odometry.norm();
    turned += std::abs(frames[k].odometry.phi());
    // Ground truth through the converted file, interpolated by the reader at the scan times.
    ASSERT_TRUE(back[k].ground_truth);
    EXPECT_NEAR(back[k].ground_truth->x(), frames[k].ground_truth->x(), 2e-6);
    EXPECT_NEAR(back[k].ground_truth->y(), frames[k].ground_truth->y(), 2e-6);
    EXPECT_LT(angleDiff(back[k].ground_truth->phi(), frames[k].ground_truth->phi()), 2e-6);
  }
  // The run exercised what it should: driving, turning, valid and invalid rays.
  EXPECT_GT(path, 5.0);
  EXPECT_GT(turned, M_PI);
  EXPECT_GT(valid, 1000u);
  EXPECT_GT(invalid, 100u);

  const auto gt0 = asf::io::readGroundTruth(tmp / "sim.gt.txt");
  const auto gt1 = asf::io::readGroundTruth(tmp / "back.gt.txt");
  ASSERT_EQ(gt1.size(), gt0.size());
  for (std::size_t k = 0; k < gt0.size(); ++k) {
    EXPECT_NEAR(gt1[k].t, gt0[k].t, 1e-6);
    EXPECT_NEAR(gt1[k].pose.x(), gt0[k].pose.x(), 1e-6);
    EXPECT_NEAR(gt1[k].pose.y(), gt0[k].pose.y(), 1e-6);
    EXPECT_LT(angleDiff(gt1[k].pose.phi(), gt0[k].pose.phi()), 1e-6);
  }
}

TEST(Rawseeds, Bzip2StreamsGiveTheSameRawlogAsPlainOnes) {
  TempDir tmp;
  const auto frames = simulate(120);
  writeRun(frames, tmp / "sim.rawlog", tmp / "sim.gt.txt");
  cv::RawlogToRawseedsOptions a;
  a.rawlog = tmp / "sim.rawlog";
  a.gt_input = tmp / "sim.gt.txt";
  a.dir = tmp / "plain";
  a.dataset = "SIM";
  cv::rawlogToRawseeds(a);
  a.dir = tmp / "bz";
  a.bz2 = true;
  const auto r = cv::rawlogToRawseeds(a);
  ASSERT_EQ(r.files.size(), 3u);
  for (const auto& f : r.files) {
    EXPECT_TRUE(has(f, ".csv.bz2")) << f;
    EXPECT_EQ(readText(f).substr(0, 3), "BZh") << f;
  }
  EXPECT_FALSE(fs::exists(tmp / "bz/SIM-SICK_FRONT.csv"));
  // The compressed stream holds exactly the plain text.
  EXPECT_EQ(readLines(tmp / "bz/SIM-SICK_FRONT.csv.bz2"),
            readLines(tmp / "plain/SIM-SICK_FRONT.csv"));

  auto o = toRawlog(tmp / "plain", "SIM", tmp / "plain.rawlog");
  o.gt_output = tmp / "plain.gt.txt";
  cv::rawseedsToRawlog(o);
  o = toRawlog(tmp / "bz", "SIM", tmp / "bz.rawlog");
  o.gt_output = tmp / "bz.gt.txt";
  const auto rb = cv::rawseedsToRawlog(o);
  EXPECT_TRUE(has(rb.streams[1].file, "SIM-SICK_FRONT.csv.bz2"));
  EXPECT_EQ(readText(tmp / "bz.rawlog"), readText(tmp / "plain.rawlog"));
  EXPECT_EQ(readText(tmp / "bz.gt.txt"), readText(tmp / "plain.gt.txt"));
  EXPECT_EQ(readFrames(tmp / "bz.rawlog").size(), 120u);
}

TEST(Rawseeds, MergesStreamsByTimeOdometryFirstWithDocumentedSensorPoses) {
  TempDir tmp;
  writeSmallSession(tmp.str());
  auto o = toRawlog(tmp.str(), "SMALL", tmp / "small.rawlog");
  o.lasers = {"SICK_FRONT", "SICK_REAR"};
  const auto rep = cv::rawseedsToRawlog(o);
  EXPECT_EQ(rep.scans, 5u);
  EXPECT_EQ(rep.odometry, 4u);
  const auto recs = readRecords(tmp / "small.rawlog");
  const std::vector<std::pair<std::string, double>> want{
      {"ODOMETRY_XYT", 0.0},    {"SICK_FRONT", 0.0},       {"SICK_REAR", 0.005},
      {"SICK_FRONT", 0.013333}, {"ODOMETRY_XYT", 0.02},    {"SICK_FRONT", 0.026667},
      {"ODOMETRY_XYT", 0.04},   {"SICK_FRONT", 0.04},      {"ODOMETRY_XYT", 0.06}};
  ASSERT_EQ(recs.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) {
    EXPECT_EQ(recs[i].label, want[i].first) << i;
    EXPECT_NEAR(recs[i].t - 1235604664.0, want[i].second, 1e-6) << i;
  }
  const auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(recs[4].obj);
  ASSERT_TRUE(odo);
  EXPECT_DOUBLE_EQ(odo->odometry.x(), 0.01);
  EXPECT_NEAR(odo->odometry.phi(), 0.001, 1e-12);
  EXPECT_TRUE(odo->hasEncodersInfo);
  EXPECT_EQ(odo->encoderLeftTicks, 101);
  EXPECT_EQ(odo->encoderRightTicks, 201);

  const auto front = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(recs[3].obj);
  ASSERT_TRUE(front);
  EXPECT_EQ(front->getScanSize(), 181u);
  EXPECT_FALSE(front->getScanRangeValidity(0));  // 0: no echo
  EXPECT_FALSE(front->getScanRangeValidity(1));  // 81.91 m
  EXPECT_FALSE(front->getScanRangeValidity(2));  // 80.5 m
  EXPECT_TRUE(front->getScanRangeValidity(3));
  EXPECT_FLOAT_EQ(front->getScanRange(3), 2.03f);
  EXPECT_FLOAT_EQ(front->getScanRange(180), 3.8f);
  EXPECT_FLOAT_EQ(front->maxRange, 80.0f);
  EXPECT_NEAR(front->sensorPose.x(), 0.08, 1e-12);
  const auto rear = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(recs[2].obj);
  ASSERT_TRUE(rear);
  EXPECT_NEAR(rear->sensorPose.x(), -0.463, 1e-12);
  EXPECT_NEAR(rear->sensorPose.y(), 0.001, 1e-12);
  EXPECT_NEAR(std::abs(rear->sensorPose.yaw()), M_PI, 1e-12);

  // The reader picks one laser (the first seen) and pairs it with the odometry.
  asf::io::RawlogReader r(tmp / "small.rawlog");
  std::size_t n = 0;
  while (r.next()) ++n;
  EXPECT_EQ(n, 4u);
  EXPECT_EQ(r.skippedScans(), 1u);
}

TEST(Rawseeds, BadLinesNameFileAndLineOrAreSkippedAndCounted) {
  TempDir tmp;
  writeSmallSession(tmp.str());
  auto lines = readLines(tmp / "SMALL-SICK_FRONT.csv");
  const std::string r7 = ",3.060000,";  // line 3 (base 3 m), R7
  lines[2].replace(lines[2].find(r7), r7.size(), ",abc,");
  std::string text;
  for (const auto& l : lines) text += l + "\n";
  writeText(tmp / "SMALL-SICK_FRONT.csv", text);
  auto o = toRawlog(tmp.str(), "SMALL", tmp / "out.rawlog");
  const std::string e = errorOf<asf::InputError>([&] { cv::rawseedsToRawlog(o); });
  EXPECT_TRUE(has(e, tmp / "SMALL-SICK_FRONT.csv:3: range R7 'abc' is not a number")) << e;
  EXPECT_FALSE(fs::exists(tmp / "out.rawlog"));
  EXPECT_FALSE(fs::exists(tmp / "out.rawlog.part"));

  o.skip_bad_lines = true;
  auto rep = cv::rawseedsToRawlog(o);
  EXPECT_EQ(rep.scans, 3u);
  EXPECT_EQ(rep.odometry, 4u);
  EXPECT_EQ(rep.streams[1].bad_lines, 1u);
  EXPECT_EQ(rep.streams[1].first_bad_line, 3u);
  EXPECT_EQ(rep.streams[1].lines, 4u);
  EXPECT_EQ(rep.streams[0].bad_lines, 0u);
  EXPECT_EQ(readFrames(tmp / "out.rawlog").size(), 3u);

  // Wrong count of ranges, time going backwards, a short odometry line.
  writeText(tmp / "SMALL-SICK_FRONT.csv",
            sickLine("1235604664.000000", 1) + "\n1235604664.01,181,0,1.0,2.0\n");
  o.skip_bad_lines = false;
  EXPECT_TRUE(has(errorOf<asf::InputError>([&] { cv::rawseedsToRawlog(o); }),
                  "SMALL-SICK_FRONT.csv:2: 181 ranges announced, 2 found"));
  writeSmallSession(tmp.str());
  writeText(tmp / "SMALL-ODOMETRY_XYT.csv",
            "1235604664.020000,11,101,201,0.01,0,0\n1235604664.010000,12,102,202,0.02,0,0\n");
  EXPECT_TRUE(has(errorOf<asf::InputError>([&] { cv::rawseedsToRawlog(o); }),
                  "SMALL-ODOMETRY_XYT.csv:2: time 1235604664.010000 goes backwards"));
  writeText(tmp / "SMALL-ODOMETRY_XYT.csv", "1235604664.020000,11,101,201,0.01,0\n");
  EXPECT_TRUE(has(errorOf<asf::InputError>([&] { cv::rawseedsToRawlog(o); }),
                  "SMALL-ODOMETRY_XYT.csv:1: expected 7 fields"));
  o.skip_bad_lines = true;
  rep = cv::rawseedsToRawlog(o);
  EXPECT_EQ(rep.odometry, 0u);
  EXPECT_EQ(rep.streams[0].bad_lines, 1u);
  EXPECT_EQ(rep.scans, 4u);
}

TEST(Rawseeds, MissingOrUnsupportedStreamsAreClearErrors) {
  TempDir tmp;
  writeSmallSession(tmp.str());
  fs::remove(tmp / "SMALL-ODOMETRY_XYT.csv");
  auto o = toRawlog(tmp.str(), "SMALL", tmp / "out.rawlog");
  std::string e = errorOf<asf::InputError>([&] { cv::rawseedsToRawlog(o); });
  EXPECT_TRUE(has(e, "stream ODOMETRY_XYT not found")) << e;
  EXPECT_TRUE(has(e, tmp / "SMALL-ODOMETRY_XYT.csv nor")) << e;
  EXPECT_TRUE(has(e, tmp / "SMALL-ODOMETRY_XYT.csv.bz2")) << e;
  EXPECT_FALSE(fs::exists(tmp / "out.rawlog"));

  writeSmallSession(tmp.str());
  o.gt_output = tmp / "gt.txt";  // no GROUNDTRUTH file in this session
  e = errorOf<asf::InputError>([&] { cv::rawseedsToRawlog(o); });
  EXPECT_TRUE(has(e, "stream GROUNDTRUTH not found")) << e;
  o.gt_output.clear();
  o.lasers = {"HOKUYO_FRONT"};
  e = errorOf<asf::InputError>([&] { cv::rawseedsToRawlog(o); });
  EXPECT_TRUE(has(e, "'HOKUYO_FRONT' is not supported")) << e;
  o.lasers = {"SICK_FRONT", "SICK_FRONT"};
  EXPECT_TRUE(has(errorOf<asf::InputError>([&] { cv::rawseedsToRawlog(o); }), "given twice"));
}

TEST(Rawseeds, Rawlog2RawseedsRefusesScansThatAreNot181RaysOver180Degrees) {
  TempDir tmp;
  auto frames = simulate(3);
  const auto write = [&](std::size_t rays, double aperture_deg) {
    auto s = std::make_shared<mrpt::obs::CObservation2DRangeScan>(*frames[2].scan);
    s->resizeScan(rays);
    s->aperture = static_cast<float>(aperture_deg * M_PI / 180);
    auto f = frames;
    f[2].scan = s;
    asf::io::RawlogWriter w(tmp / "odd.rawlog");
    for (const auto& x : f) w.write(x);
  };
  cv::RawlogToRawseedsOptions a;
  a.rawlog = tmp / "odd.rawlog";
  a.dir = tmp / "csv";
  a.dataset = "ODD";
  write(361, 180);
  std::string e = errorOf<asf::InputError>([&] { cv::rawlogToRawseeds(a); });
  EXPECT_TRUE(has(e, "odd.rawlog: record 5: scan 'LASER' has 361 rays over 180.00 degrees; a "
                     "Rawseeds SICK stream holds 181 rays over 180 degrees"))
      << e;
  EXPECT_FALSE(fs::exists(tmp / "csv/ODD-SICK_FRONT.csv"));  // nothing half-written
  EXPECT_FALSE(fs::exists(tmp / "csv/ODD-SICK_FRONT.csv.part"));
  write(181, 270);
  e = errorOf<asf::InputError>([&] { cv::rawlogToRawseeds(a); });
  EXPECT_TRUE(has(e, "181 rays over 270.00 degrees")) << e;
  write(181, 180);
  EXPECT_EQ(cv::rawlogToRawseeds(a).scans, 3u);
}

TEST(RawseedsRealData, BicoccaGroundTruth) {
  const std::string dir = ASF_TEST_SHARED_DIR "/datasets/rawseeds";
  const std::string csv = dir + "/Bicocca_2009-02-25b-GROUNDTRUTH.csv";
  if (!fs::exists(csv)) GTEST_SKIP() << "../shared is not available here (" << csv << ")";
  TempDir tmp;
  const auto rep = cv::rawseedsGroundTruthToFile(csv, tmp / "gt.txt", false);
  EXPECT_EQ(rep.lines, 5829u);
  EXPECT_EQ(rep.records, 5829u);
  EXPECT_EQ(rep.bad_lines, 0u);
  const auto gt = asf::io::readGroundTruth(tmp / "gt.txt");
  ASSERT_EQ(gt.size(), 5829u);
  EXPECT_NEAR(gt.front().t, 1235604664.443286, 1e-6);
  EXPECT_NEAR(gt.front().pose.x(), -0.623883, 1e-9);
  EXPECT_NEAR(gt.front().pose.y(), -8.987304, 1e-9);
  EXPECT_NEAR(gt.front().pose.phi(), 1.491652, 1e-9);
  EXPECT_NEAR(gt.back().t, 1235605067.488693, 1e-6);
  double min_x = 1e9, max_x = -1e9, min_y = 1e9, max_y = -1e9;
  for (std::size_t k = 0; k < gt.size(); ++k) {
    if (k > 0) {
      ASSERT_GT(gt[k].t, gt[k - 1].t) << "line " << k + 1;
    }
    min_x = std::min(min_x, gt[k].pose.x());
    max_x = std::max(max_x, gt[k].pose.x());
    min_y = std::min(min_y, gt[k].pose.y());
    max_y = std::max(max_y, gt[k].pose.y());
  }
  // A stretch of corridors of one floor: about 14 m x 12 m, within the ~400 s covered.
  EXPECT_NEAR(min_x, -5.551864, 1e-9);
  EXPECT_NEAR(max_x, 8.264425, 1e-9);
  EXPECT_NEAR(min_y, -9.101797, 1e-9);
  EXPECT_NEAR(max_y, 2.900184, 1e-9);
  EXPECT_NEAR(gt.back().t - gt.front().t, 403.045, 1e-3);

  // GT-extended: "t, x, y, theta" with spaces after the commas.
  const std::string ext = dir + "/Bicocca_2009-02-25b-GT-extended.csv";
  const auto re = cv::rawseedsGroundTruthToFile(ext, tmp / "gtx.txt", false);
  EXPECT_EQ(re.stream, "GT-extended");
  EXPECT_EQ(re.records, 6580u);
  EXPECT_EQ(asf::io::readGroundTruth(tmp / "gtx.txt").size(), 6580u);
}

// --------------------------------------------------------------------- host commands

namespace {
using Run = asf_test::HostResult;
Run runAsf(const std::string& args) { return asf_test::runHost(args); }
}  // namespace

TEST(ConvertCommands, ExitCodesAndMessages) {
  TempDir tmp;
  writeSmallSession(tmp.str());
  auto r = runAsf("rawseeds2rawlog -q --dir " + tmp.str() + " --dataset SMALL --laser SICK_FRONT "
          "--laser SICK_REAR -o " + tmp / "small.rawlog");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "5 scans and 4 odometry readings")) << r.out;
  r = runAsf("rawseeds2rawlog --dir " + tmp.str() + " --dataset NOPE -o " + tmp / "n.rawlog");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_TRUE(has(r.out, "stream ODOMETRY_XYT not found")) << r.out;
  r = runAsf("rawlog2rawseeds --rawlog " + tmp / "small.rawlog" + " --dir " + tmp / "out" +
          " --dataset BACK");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "4 frames: 4 scan lines, 4 odometry lines")) << r.out;
  EXPECT_EQ(readLines(tmp / "out/BACK-SICK_FRONT.csv").size(), 4u);

  // Only the ground truth (the real Rawseeds laser streams are not on these machines).
  writeText(tmp / "SMALL-GROUNDTRUTH.csv",
            "1235604664.000000,1.0,2.0,0.5,1e-6,0,0,0,1e-6,0,0,0,1e-6\n"
            "1235604664.020000,1.1,2.0,0.5,1e-6,0,0,0,1e-6,0,0,0,1e-6\n");
  r = runAsf("rawseeds2rawlog -q --dir " + tmp.str() + " --dataset SMALL --gt-only --gt " +
             tmp / "small.gt.txt");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "2 ground-truth poses")) << r.out;
  EXPECT_EQ(asf::io::readGroundTruth(tmp / "small.gt.txt").size(), 2u);
  r = runAsf("rawseeds2rawlog --dir " + tmp.str() + " --dataset SMALL --gt-only");
  EXPECT_EQ(r.code, 2) << r.out;
  r = runAsf("rawseeds2rawlog --dir " + tmp.str() +
             " --dataset SMALL");  // neither -o nor --gt-only
  EXPECT_EQ(r.code, 2) << r.out;
}

// Converters writing to a full disk (/dev/full behind links) fail naming the output and replace
// neither the links nor the device; rawlog-normalize keeps the old output when it fails.
TEST(ConvertCommands, AFullDiskIsAnErrorAndNothingIsReplaced) {
  if (!fs::is_character_file("/dev/full")) GTEST_SKIP() << "no /dev/full on this machine";
  TempDir tmp;
  writeSmallSession(tmp.str());
  fs::create_symlink("/dev/full", tmp / "full.rawlog");
  auto r = runAsf("rawseeds2rawlog -q --dir " + tmp.str() + " --dataset SMALL --laser SICK_FRONT "
                  "--laser SICK_REAR -o " + tmp / "full.rawlog");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_TRUE(has(r.out, tmp / "full.rawlog" + ": write failed (disk full")) << r.out;
  EXPECT_TRUE(fs::is_symlink(tmp / "full.rawlog"));
  EXPECT_TRUE(fs::is_character_file("/dev/full")) << "/dev/full was replaced by a file";

  r = runAsf("rawseeds2rawlog -q --dir " + tmp.str() + " --dataset SMALL --laser SICK_FRONT "
             "--laser SICK_REAR -o " + tmp / "small.rawlog");
  ASSERT_EQ(r.code, 0) << r.out;
  r = runAsf("rawlog-normalize " + tmp / "small.rawlog" + " " + tmp / "full.rawlog");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_TRUE(has(r.out, "full.rawlog: write failed")) << r.out;
  EXPECT_TRUE(fs::is_character_file("/dev/full"));

  fs::create_directories(tmp / "out");
  fs::create_symlink("/dev/full", tmp / "out/BACK-SICK_FRONT.csv");
  r = runAsf("rawlog2rawseeds --rawlog " + tmp / "small.rawlog" + " --dir " + tmp / "out" +
             " --dataset BACK");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_TRUE(has(r.out, "BACK-SICK_FRONT.csv: write error")) << r.out;
  EXPECT_TRUE(fs::is_symlink(tmp / "out/BACK-SICK_FRONT.csv"));

  // Not a rawlog: the normalized output of before stays whole, no temporary file.
  writeText(tmp / "old.rawlog", "the previous output");
  writeText(tmp / "junk.rawlog", std::string(4096, '\x7f'));
  r = runAsf("rawlog-normalize " + tmp / "junk.rawlog" + " " + tmp / "old.rawlog");
  EXPECT_NE(r.code, 0) << r.out;
  EXPECT_EQ(readText(tmp / "old.rawlog"), "the previous output");
  EXPECT_FALSE(fs::exists(tmp / "old.rawlog.tmp"));
}
