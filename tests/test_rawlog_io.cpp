// Tests of rawlog reading/writing, ground-truth files and the odometry noise model
// (asf/io/rawlog_io.h), on logs built here and on MRPT's sample datasets.
#include <asf/errors.h>
#include <asf/io/rawlog_io.h>
#include <gtest/gtest.h>
#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileInputStream.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "test_util.h"

namespace fs = std::filesystem;
using asf_test::errorOf;
using asf_test::has;
using mrpt::obs::CObservation2DRangeScan;
using mrpt::poses::CPose2D;

namespace {

const std::string kSena =
    "/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";
const std::string kSimul =
    "/usr/share/mrpt/datasets/graphslam-engine-demos/action_observations_map/simul.rawlog";

/// A fresh folder per test under the system's temp folder.
class TempDir {
 public:
  TempDir() {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string(info->test_suite_name()) + "_" + info->name();
    for (char& c : name)
      if (c == '/') c = '_';  // parameterized tests: "Suite/Param"
    path_ = fs::temp_directory_path() / ("asf_rawlog_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

std::shared_ptr<CObservation2DRangeScan> makeScan(const std::string& label, double t, int k,
                                                  std::size_t rays = 91) {
  auto s = std::make_shared<CObservation2DRangeScan>();
  s->sensorLabel = label;
  s->timestamp = mrpt::Clock::fromDouble(t);
  s->aperture = 3.1f;
  s->rightToLeft = true;
  s->maxRange = 20.0f;
  s->stdError = 0.02f;
  s->sensorPose = mrpt::poses::CPose3D(0.2, 0.01, 0.3, 0.05, 0, 0);
  s->resizeScan(rays);
  for (std::size_t i = 0; i < rays; ++i) {
    s->setScanRange(i, static_cast<float>(1.0 + 0.013 * static_cast<double>(i) + 0.1 * k));
    s->setScanRangeValidity(i, (i + static_cast<std::size_t>(k)) % 7 != 0);
  }
  return s;
}

/// Frames with realistic (Unix) timestamps, varied odometry, full covariances, and no scan
/// in every fourth one.
std::vector<asf::SensorFrame> makeFrames(int n) {
  std::vector<asf::SensorFrame> out;
  for (int k = 0; k < n; ++k) {
    asf::SensorFrame f;
    f.timestamp = 1.6e9 + 0.1 * k + 1.234567e-3;
    f.odometry = CPose2D(0.1 * k, -0.02 * k, mrpt::math::wrapToPi(0.3 * k));
    Eigen::Matrix3d a;
    a << 0.01 + 0.001 * k, 0.002, 0.0001 * k, 0.002, 0.02, -0.003, 0.0001 * k, -0.003, 0.05;
    const Eigen::Matrix3d c = a * a.transpose();
    // Bit-symmetric (a product is not always): a rawlog stores one triangle.
    f.odometry_cov = k == 0 ? Eigen::Matrix3d::Zero() : Eigen::Matrix3d(0.5 * (c + c.transpose()));
    // The scan's own time differs from the frame's: the writer stamps it with the frame time.
    if (k % 4 != 3) f.scan = makeScan("LASER", f.timestamp + 0.01, k);
    out.push_back(f);
  }
  return out;
}

double clockRoundTrip(double t) { return mrpt::Clock::toDouble(mrpt::Clock::fromDouble(t)); }

void expectSameScan(const CObservation2DRangeScan& a, const CObservation2DRangeScan& b) {
  EXPECT_EQ(a.sensorLabel, b.sensorLabel);
  ASSERT_EQ(a.getScanSize(), b.getScanSize());
  EXPECT_EQ(a.aperture, b.aperture);
  EXPECT_EQ(a.maxRange, b.maxRange);
  EXPECT_EQ(a.rightToLeft, b.rightToLeft);
  EXPECT_EQ(a.stdError, b.stdError);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(a.sensorPose[i], b.sensorPose[i]) << i;
  EXPECT_EQ(a.sensorPose.yaw(), b.sensorPose.yaw());
  EXPECT_EQ(a.sensorPose.pitch(), b.sensorPose.pitch());
  EXPECT_EQ(a.sensorPose.roll(), b.sensorPose.roll());
  for (std::size_t i = 0; i < a.getScanSize(); ++i) {
    EXPECT_EQ(a.getScanRange(i), b.getScanRange(i)) << i;
    EXPECT_EQ(a.getScanRangeValidity(i), b.getScanRangeValidity(i)) << i;
  }
}

/// `read` is `written` replayed: every number bit-identical, the time through mrpt::Clock.
void expectReplayed(const asf::SensorFrame& written, const asf::SensorFrame& read, int k) {
  SCOPED_TRACE("frame " + std::to_string(k));
  EXPECT_EQ(read.timestamp, clockRoundTrip(written.timestamp));
  EXPECT_EQ(read.odometry.x(), written.odometry.x());
  EXPECT_EQ(read.odometry.y(), written.odometry.y());
  EXPECT_EQ(read.odometry.phi(), written.odometry.phi());
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(read.odometry_cov(r, c), written.odometry_cov(r, c))
          << "cov(" << r << "," << c << ")";
  ASSERT_EQ(read.scan == nullptr, written.scan == nullptr);
  if (read.scan) {
    expectSameScan(*written.scan, *read.scan);
    EXPECT_EQ(read.scan->timestamp, mrpt::Clock::fromDouble(written.timestamp));
  }
  EXPECT_FALSE(read.ground_truth.has_value());
}

std::vector<asf::SensorFrame> readAll(const std::string& path, asf::io::RawlogReaderOptions o = {}) {
  asf::io::RawlogReader r(path, o);
  std::vector<asf::SensorFrame> out;
  while (auto f = r.next()) out.push_back(*f);
  return out;
}

void writeAll(const std::string& path, const std::vector<asf::SensorFrame>& frames,
              std::size_t flush_every = 50) {
  asf::io::RawlogWriter w(path, flush_every);
  for (const auto& f : frames) w.write(f);
  EXPECT_EQ(w.framesWritten(), frames.size());
}

std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

/// a ⊖ b written out: b's pose expressed in a's frame (inverse composition by hand).
CPose2D relative(double x1, double y1, double p1, double x2, double y2, double p2) {
  const double dx = x2 - x1, dy = y2 - y1;
  return CPose2D(std::cos(p1) * dx + std::sin(p1) * dy, -std::sin(p1) * dx + std::cos(p1) * dy,
                 std::remainder(p2 - p1, 2 * M_PI));
}

// ---------------------------------------------------------------- write -> read

class RoundTrip : public testing::TestWithParam<std::string> {};

TEST_P(RoundTrip, ReplayEqualsWrittenFramesExactly) {
  TempDir dir;
  const std::string path = dir.file("log" + GetParam());
  const auto frames = makeFrames(23);
  writeAll(path, frames, 5);  // flushes (reopens) several times on the way

  const std::string bytes = readBytes(path);
  const bool gz = bytes.size() > 2 && static_cast<unsigned char>(bytes[0]) == 0x1f &&
                  static_cast<unsigned char>(bytes[1]) == 0x8b;
  EXPECT_EQ(gz, GetParam() == ".rawlog.gz") << "the file's compression follows its name";

  asf::io::RawlogReader r(path);
  std::vector<asf::SensorFrame> read;
  while (auto f = r.next()) read.push_back(*f);
  EXPECT_FALSE(r.next());
  ASSERT_EQ(read.size(), frames.size());
  for (std::size_t k = 0; k < frames.size(); ++k)
    expectReplayed(frames[k], read[k], static_cast<int>(k));
  EXPECT_EQ(r.recordIndex(), 2 * frames.size() - 1);  // one action + one sensory frame each
  EXPECT_EQ(r.laserLabels(), std::vector<std::string>{"LASER"});
  EXPECT_EQ(r.skippedScans(), 0u);

  // Writing what was read gives the same stream again, bit for bit (times included).
  const std::string again = dir.file("again" + GetParam());
  writeAll(again, read);
  const auto reread = readAll(again);
  ASSERT_EQ(reread.size(), read.size());
  for (std::size_t k = 0; k < read.size(); ++k) {
    EXPECT_EQ(reread[k].timestamp, read[k].timestamp) << k;
    expectReplayed(read[k], reread[k], static_cast<int>(k));
  }
}

INSTANTIATE_TEST_SUITE_P(PlainAndGz, RoundTrip, testing::Values(".rawlog", ".rawlog.gz"),
                         [](const auto& i) { return i.param == ".rawlog" ? "plain" : "gz"; });

TEST(RawlogWriter, FlushedFramesAreReadableWhileWriting) {
  TempDir dir;
  const std::string path = dir.file("live.rawlog.gz");
  const auto frames = makeFrames(7);
  asf::io::RawlogWriter w(path, 3);
  for (const auto& f : frames) w.write(f);
  // 7 frames with flush_every = 3: 6 are on disk before close.
  EXPECT_EQ(readAll(path).size(), 6u);
  w.flush();
  EXPECT_EQ(readAll(path).size(), 7u);
}

// A full disk (/dev/full behind a link): the failed flush is an error naming the file, and so
// is every write after it (the stream is gone: a write must not reach it).
TEST(RawlogWriter, AFullDiskFailsTheFlushAndEveryWriteAfterIt) {
  if (!std::filesystem::is_character_file("/dev/full")) GTEST_SKIP() << "no /dev/full here";
  TempDir dir;
  const std::string path = dir.file("full.rawlog");
  std::filesystem::create_symlink("/dev/full", path);
  const auto frames = makeFrames(2);
  asf::io::RawlogWriter w(path, 0);
  try {
    w.write(frames[0]);  // buffered, or already failing: both are fine
  } catch (const asf::Error&) {
  }
  EXPECT_TRUE(has(errorOf<asf::Error>([&] { w.flush(); }), path));
  const auto after = errorOf<asf::Error>([&] { w.write(frames[1]); });
  EXPECT_TRUE(has(after, path + ": not open for writing (closed, or a write failed)")) << after;
  EXPECT_TRUE(std::filesystem::is_character_file("/dev/full"));
}

TEST(RawlogWriter, CloseEndsTheFileAndAWriteAfterItIsAnError) {
  TempDir dir;
  const std::string path = dir.file("closed.rawlog.gz");
  const auto frames = makeFrames(3);
  asf::io::RawlogWriter w(path, 0);
  w.write(frames[0]);
  w.write(frames[1]);
  w.close();
  EXPECT_EQ(readAll(path).size(), 2u);
  EXPECT_TRUE(has(errorOf<asf::Error>([&] { w.write(frames[2]); }), path + ": not open"));
  EXPECT_NO_THROW(w.close());  // closing again changes nothing
  EXPECT_EQ(readAll(path).size(), 2u);
}

TEST(RawlogWriter, UnwritableFileIsAnInputErrorNamingIt) {
  const std::string bad = "/nonexistent-dir/x.rawlog";
  EXPECT_TRUE(has(errorOf<asf::InputError>([&] { asf::io::RawlogWriter w(bad); }), bad));
}

// ---------------------------------------------------------------- observation-only logs

/// Odometry readings and two lasers interleaved. One reading (D) is stored before a BACK scan
/// but timestamped after it, and one (E) between the last FRONT and BACK scans.
void writeObservationLog(const std::string& path) {
  mrpt::io::CFileGZOutputStream out(path);
  auto ar = mrpt::serialization::archiveFrom(out);
  auto odo = [&](double t, double x, double y, double phi) {
    mrpt::obs::CObservationOdometry o;
    o.sensorLabel = "ODOMETRY";
    o.timestamp = mrpt::Clock::fromDouble(t);
    o.odometry = CPose2D(x, y, phi);
    ar << o;
  };
  auto scan = [&](const std::string& label, double t) { ar << *makeScan(label, t, 0, 11); };
  odo(10.0, 0, 0, 0);  // A
  scan("FRONT", 10.05);
  scan("BACK", 10.06);
  odo(10.1, 1, 0.5, 0.3);  // B
  odo(10.2, 2, 1, 2.9);    // C
  scan("FRONT", 10.25);
  odo(10.4, 2.5, 1.5, -3.0);  // D (after the next BACK scan's time)
  scan("BACK", 10.3);
  scan("FRONT", 10.5);
  odo(10.52, 3, 1, -2.0);  // E
  scan("BACK", 10.55);
}

void expectPose(const CPose2D& got, const CPose2D& want, const std::string& what) {
  EXPECT_NEAR(got.x(), want.x(), 1e-12) << what;
  EXPECT_NEAR(got.y(), want.y(), 1e-12) << what;
  EXPECT_NEAR(got.phi(), want.phi(), 1e-12) << what;
}

TEST(RawlogReader, ObservationOnlyLogFirstLaserByDefault) {
  TempDir dir;
  const std::string path = dir.file("obs.rawlog.gz");
  writeObservationLog(path);
  asf::io::RawlogReaderOptions o;
  o.odometry_model.a1 = 0.05;
  asf::io::RawlogReader r(path, o);
  std::vector<asf::SensorFrame> f;
  while (auto x = r.next()) f.push_back(*x);
  ASSERT_EQ(f.size(), 3u);
  for (const auto& x : f) EXPECT_EQ(x.scan->sensorLabel, "FRONT");
  EXPECT_EQ(f[0].timestamp, clockRoundTrip(10.05));
  EXPECT_EQ(f[2].timestamp, clockRoundTrip(10.5));
  // First frame: zero increment, nothing to be uncertain about.
  expectPose(f[0].odometry, CPose2D(), "frame 0");
  EXPECT_TRUE(f[0].odometry_cov.isZero());
  // FRONT@10.25 sits at C, FRONT@10.05 at A: C itself. FRONT@10.5 at D: D ⊖ C, across ±pi.
  expectPose(f[1].odometry, CPose2D(2, 1, 2.9), "frame 1");
  const CPose2D dc = relative(2, 1, 2.9, 2.5, 1.5, -3.0);
  EXPECT_NEAR(dc.phi(), -5.9 + 2 * M_PI, 1e-12);
  expectPose(f[2].odometry, dc, "frame 2");
  for (int k = 1; k < 3; ++k)
    EXPECT_TRUE(f[k].odometry_cov.isApprox(o.odometry_model.covariance(f[k].odometry), 1e-14)) << k;
  EXPECT_EQ(r.laserLabels(), (std::vector<std::string>{"FRONT", "BACK"}));
  EXPECT_EQ(r.skippedScans(), 3u);
  EXPECT_EQ(r.recordIndex(), 10u);
}

TEST(RawlogReader, ObservationOnlyLogLaserByLabel) {
  TempDir dir;
  const std::string path = dir.file("obs.rawlog.gz");
  writeObservationLog(path);
  asf::io::RawlogReaderOptions o;
  o.laser_label = "BACK";
  const auto f = readAll(path, o);
  ASSERT_EQ(f.size(), 3u);
  for (const auto& x : f) EXPECT_EQ(x.scan->sensorLabel, "BACK");
  // BACK@10.06 at A; BACK@10.3 at C (D, stored earlier, is timestamped later); BACK@10.55 at E.
  expectPose(f[1].odometry, CPose2D(2, 1, 2.9), "frame 1");
  expectPose(f[2].odometry, relative(2, 1, 2.9, 3, 1, -2.0), "frame 2");

  o.laser_label = "NONE";
  asf::io::RawlogReader r(path, o);
  EXPECT_FALSE(r.next());
  EXPECT_EQ(r.skippedScans(), 6u);
}

TEST(RawlogReader, ActionLogLaserSelectionSkipsOtherLabels) {
  TempDir dir;
  const std::string path = dir.file("two.rawlog");
  auto frames = makeFrames(4);
  writeAll(path, frames);
  asf::io::RawlogReaderOptions o;
  o.laser_label = "OTHER";
  asf::io::RawlogReader r(path, o);
  int n = 0;
  while (auto f = r.next()) {
    EXPECT_EQ(f->scan, nullptr);  // one frame per step, without the unwanted scan
    ++n;
  }
  EXPECT_EQ(n, 4);
  EXPECT_EQ(r.skippedScans(), 3u);
}

// ---------------------------------------------------------------- damaged files

TEST(RawlogReader, TruncatedLogEndsWithErrorNamingTheRecord) {
  TempDir dir;
  const std::string path = dir.file("full.rawlog");
  const auto frames = makeFrames(12);
  std::vector<std::uintmax_t> end_of;  // file size after each frame (flushed every frame)
  {
    asf::io::RawlogWriter w(path, 1);
    for (const auto& f : frames) {
      w.write(f);
      end_of.push_back(fs::file_size(path));
    }
  }
  // Cut 10 bytes before the end of frame 6: inside its sensory frame (record 13).
  ASSERT_TRUE(frames[6].scan);
  const std::string cut = dir.file("cut.rawlog");
  writeBytes(cut, readBytes(path).substr(0, end_of[6] - 10));

  asf::io::RawlogReader r(cut);
  std::vector<asf::SensorFrame> got;
  std::string msg;
  try {
    while (auto f = r.next()) got.push_back(*f);
  } catch (const asf::InputError& e) {
    msg = e.what();
  }
  EXPECT_TRUE(has(msg, cut + ": record 13: ")) << msg;
  ASSERT_EQ(got.size(), 6u);
  for (int k = 0; k < 6; ++k) expectReplayed(frames[k], got[k], k);  // still valid
  EXPECT_FALSE(r.next());
  EXPECT_FALSE(r.next());
}

// Issue 20, item 2: a log cut at any byte ends cleanly only where a record ends (positions
// found by reading the whole file with MRPT's own archive: the oracle); anywhere else it is
// an InputError, also inside a length or element count, where MRPT reports a plain EOF.
TEST(RawlogReader, CutAtAnyByteEndsCleanlyOnlyBetweenRecords) {
  TempDir dir;
  const std::string path = dir.file("full.rawlog");
  writeAll(path, makeFrames(3), 1);
  std::set<std::uint64_t> boundaries{0};
  {
    mrpt::io::CFileInputStream in(path);
    auto ar = mrpt::serialization::archiveFrom(in);
    const std::uint64_t size = fs::file_size(path);
    while (in.getPosition() < size) {
      ar.ReadObject();
      boundaries.insert(in.getPosition());
    }
  }
  ASSERT_EQ(boundaries.size(), 7u) << "header + an action and a sensory frame per frame";
  const std::string bytes = readBytes(path), cut = dir.file("cut.rawlog");
  std::size_t clean_inside = 0, errors = 0;
  for (std::size_t n = 0; n <= bytes.size(); ++n) {
    writeBytes(cut, bytes.substr(0, n));
    bool clean = true;
    try {
      asf::io::RawlogReader r(cut);
      while (r.next()) {
      }
    } catch (const asf::InputError& e) {
      clean = false;
      ++errors;
      EXPECT_TRUE(has(e.what(), cut + ": record ")) << e.what();
      // Said as a cut wherever it is, nested objects included (a kill -9 tore a scan inside
      // a sensory frame: MRPT wraps that EOF in another exception).
      if (!has(e.what(), "the file ends inside this record (cut at byte " + std::to_string(n)) &&
          ++clean_inside <= 5)
        ADD_FAILURE() << "cut at byte " << n << " not said as a cut: " << e.what();
    }
    if (clean != (boundaries.count(n) == 1)) {
      ++clean_inside;
      ADD_FAILURE() << "cut at byte " << n << " of " << bytes.size() << ": "
                    << (clean ? "a clean end inside a record" : "an error at a record boundary");
      if (clean_inside > 5) break;  // the first few say it all
    }
  }
  EXPECT_EQ(errors, bytes.size() + 1 - boundaries.size());
}

TEST(RawlogReader, TruncatedGzLogEndsWithError) {
  TempDir dir;
  const std::string path = dir.file("full.rawlog.gz");
  const auto frames = makeFrames(40);
  writeAll(path, frames);
  const std::string bytes = readBytes(path);
  const std::string cut = dir.file("cut.rawlog.gz");
  writeBytes(cut, bytes.substr(0, bytes.size() / 2));
  asf::io::RawlogReader r(cut);
  std::size_t n = 0;
  std::string msg;
  try {
    while (auto f = r.next()) {
      expectReplayed(frames[n], *f, static_cast<int>(n));
      ++n;
    }
  } catch (const asf::InputError& e) {
    msg = e.what();
  }
  EXPECT_GT(n, 5u);
  EXPECT_LT(n, frames.size());
  // The failing record is the action or the sensory frame of frame n.
  const bool named = has(msg, cut + ": record " + std::to_string(2 * n) + ": ") ||
                     has(msg, cut + ": record " + std::to_string(2 * n + 1) + ": ");
  EXPECT_TRUE(named) << msg << " (after " << n << " frames)";
  EXPECT_FALSE(r.next());
}

TEST(RawlogReader, FlippedBytesInARecordHeaderAreAnError) {
  TempDir dir;
  const std::string path = dir.file("ok.rawlog");
  const auto frames = makeFrames(8);
  writeAll(path, frames);
  std::string bytes = readBytes(path);
  // Damage the class name of the 5th sensory frame (record 9).
  std::size_t pos = 0;
  for (int i = 0; i < 5; ++i) {
    pos = bytes.find("CSensoryFrame", i == 0 ? 0 : pos + 1);
    ASSERT_NE(pos, std::string::npos);
  }
  bytes[pos] = static_cast<char>(bytes[pos] ^ 0xff);
  bytes[pos + 1] = static_cast<char>(bytes[pos + 1] ^ 0xff);
  const std::string bad = dir.file("bad.rawlog");
  writeBytes(bad, bytes);
  asf::io::RawlogReader r(bad);
  int n = 0;
  const std::string msg = errorOf<asf::InputError>([&] {
    while (r.next()) ++n;
  });
  EXPECT_TRUE(has(msg, bad + ": record 9: ")) << msg;
  // The damaged class name is quoted, its unprintable bytes replaced.
  EXPECT_TRUE(has(msg, "?ensoryFrame")) << msg;
  for (char c : msg) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << "unprintable byte in the message";
  EXPECT_EQ(n, 4);
  EXPECT_FALSE(r.next());
}

TEST(RawlogReader, MissingNonRawlogAndEmptyFiles) {
  TempDir dir;
  const std::string missing = dir.file("nope.rawlog");
  EXPECT_TRUE(has(errorOf<asf::InputError>([&] { asf::io::RawlogReader r(missing); }), missing));

  const std::string text = dir.file("text.rawlog");
  writeText(text, "this is not a rawlog, just some text that goes on for a while\n");
  asf::io::RawlogReader r(text);
  EXPECT_TRUE(has(errorOf<asf::InputError>([&] { r.next(); }), text + ": record 0: "));
  EXPECT_FALSE(r.next());

  const std::string empty = dir.file("empty.rawlog");
  writeText(empty, "");
  asf::io::RawlogReader e(empty);
  EXPECT_FALSE(e.next());  // no records is a log without steps, not an error
}

// ---------------------------------------------------------------- ground truth

TEST(GroundTruth, ReadSkipsCommentsAndNamesTheBadLine) {
  TempDir dir;
  const std::string ok = dir.file("gt.txt");
  writeText(ok, "# t x y phi\n\n1.0 0 0 0\n  2.5 1.5 -2 3.1\n");
  const auto gt = asf::io::readGroundTruth(ok);
  ASSERT_EQ(gt.size(), 2u);
  EXPECT_EQ(gt[1].t, 2.5);
  EXPECT_EQ(gt[1].pose.x(), 1.5);
  EXPECT_EQ(gt[1].pose.y(), -2);
  EXPECT_DOUBLE_EQ(gt[1].pose.phi(), 3.1);  // CPose2D wraps phi (fmod may move a bit)

  const std::string bad = dir.file("bad.txt");
  writeText(bad, "1 0 0 0\n2 0 0 0\n3 0 zero 0\n");
  EXPECT_TRUE(has(errorOf<asf::InputError>([&] { asf::io::readGroundTruth(bad); }), bad + ":3:"));
  writeText(bad, "1 0 0 0\n2 0 0 0 7\n");
  EXPECT_TRUE(has(errorOf<asf::InputError>([&] { asf::io::readGroundTruth(bad); }), bad + ":2:"));
  writeText(bad, "1 0 0 0\n# back in time\n0.5 0 0 0\n");
  EXPECT_TRUE(has(errorOf<asf::InputError>([&] { asf::io::readGroundTruth(bad); }), bad + ":3:"));
  const std::string missing = dir.file("none.txt");
  EXPECT_TRUE(has(errorOf<asf::InputError>([&] { asf::io::readGroundTruth(missing); }), missing));
}

TEST(GroundTruth, InterpolationIsLinearWithAnglesOnTheCircle) {
  const std::vector<asf::io::GroundTruthPose> gt = {
      {10.0, CPose2D(0, 0, 0.5)},  {10.2, CPose2D(2, -1, 1.5)},
      {10.4, CPose2D(2, -1, 3.0)}, {10.6, CPose2D(4, 1, -3.0)},  // 0.283 rad further, across +-pi
      {12.0, CPose2D(5, 5, 0)},                                  // after a 1.4 s gap
  };
  auto p = asf::io::interpolateGroundTruth(gt, 10.05);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->x(), 0.5, 1e-12);
  EXPECT_NEAR(p->y(), -0.25, 1e-12);
  EXPECT_NEAR(p->phi(), 0.75, 1e-12);
  p = asf::io::interpolateGroundTruth(gt, 10.2);  // on a line: that line
  ASSERT_TRUE(p);
  EXPECT_EQ(p->x(), 2);
  EXPECT_EQ(p->phi(), 1.5);
  // Across the wrap: 3.0 -> -3.0 is +0.2832 rad; the middle is pi + ... wrapped.
  p = asf::io::interpolateGroundTruth(gt, 10.5);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->x(), 3, 1e-12);
  EXPECT_NEAR(std::abs(p->phi()), M_PI, 1e-12);
  p = asf::io::interpolateGroundTruth(gt, 10.55);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->phi(), 3.0 + 0.75 * (2 * M_PI - 6.0) - 2 * M_PI, 1e-12);
  EXPECT_LT(p->phi(), 0);
  // Outside the file, and inside a gap wider than max_gap.
  EXPECT_FALSE(asf::io::interpolateGroundTruth(gt, 9.99));
  EXPECT_FALSE(asf::io::interpolateGroundTruth(gt, 12.01));
  EXPECT_FALSE(asf::io::interpolateGroundTruth(gt, 11.0));
  EXPECT_TRUE(asf::io::interpolateGroundTruth(gt, 11.0, 2.0));
  EXPECT_TRUE(asf::io::interpolateGroundTruth(gt, 12.0));  // the last line itself
  // Within 1 us of a line (the printing resolution of GT files) is at that line, even next
  // to a gap or past an end.
  p = asf::io::interpolateGroundTruth(gt, 10.6 + 5e-7);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->x(), 4);
  p = asf::io::interpolateGroundTruth(gt, 12.0 + 5e-7);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->x(), 5);
  EXPECT_TRUE(asf::io::interpolateGroundTruth(gt, 10.0 - 5e-7));
  EXPECT_FALSE(asf::io::interpolateGroundTruth(gt, 10.6 + 1e-5));
  EXPECT_FALSE(asf::io::interpolateGroundTruth({}, 1.0));
}

TEST(GroundTruth, WriterFlushesEveryLineAndReadsBack) {
  TempDir dir;
  const std::string path = dir.file("gt.txt");
  asf::io::GroundTruthWriter w(path);
  w.write(1600000000.123456789, CPose2D(1.0 / 3, -2.0 / 3, -3.0));
  w.write(1600000000.2, CPose2D(1e-10, 5, M_PI));
  // Read while the writer is still open: both lines are on disk.
  const auto gt = asf::io::readGroundTruth(path);
  ASSERT_EQ(gt.size(), 2u);
  EXPECT_NEAR(gt[0].t, 1600000000.123456789, 1e-6);  // double resolution at 1.6e9 s
  EXPECT_NEAR(gt[0].pose.x(), 1.0 / 3, 1e-9);
  EXPECT_NEAR(gt[0].pose.y(), -2.0 / 3, 1e-9);
  EXPECT_NEAR(gt[0].pose.phi(), -3.0, 1e-9);
  EXPECT_NEAR(gt[1].pose.phi(), M_PI, 1e-9);
  EXPECT_TRUE(has(errorOf<asf::InputError>([] { asf::io::GroundTruthWriter x("/nonexistent/gt"); }),
                  "/nonexistent/gt"));
}

TEST(RawlogReader, FramesGetInterpolatedGroundTruth) {
  TempDir dir;
  const std::string log = dir.file("log.rawlog"), gtf = dir.file("gt.txt");
  const auto frames = makeFrames(6);
  writeAll(log, frames);
  {
    asf::io::GroundTruthWriter w(gtf);
    // Lines every 0.2 s from the first frame's time - 0.05: frames fall between lines.
    for (int i = 0; i < 3; ++i)
      w.write(frames[0].timestamp - 0.05 + 0.2 * i, CPose2D(i, 2 * i, 0.1 * i));
  }
  asf::io::RawlogReaderOptions o;
  o.ground_truth_file = gtf;
  const auto read = readAll(log, o);
  ASSERT_EQ(read.size(), 6u);
  const auto gt = asf::io::readGroundTruth(gtf);
  for (std::size_t k = 0; k < read.size(); ++k) {
    const auto want = asf::io::interpolateGroundTruth(gt, read[k].timestamp);
    ASSERT_EQ(read[k].ground_truth.has_value(), want.has_value()) << k;
    if (want) expectPose(*read[k].ground_truth, *want, "frame " + std::to_string(k));
  }
  ASSERT_TRUE(read[1].ground_truth);  // 0.15 s after the first line: 3/4 of the way
  EXPECT_NEAR(read[1].ground_truth->x(), 0.75, 1e-6);
  EXPECT_FALSE(read[5].ground_truth);  // after the last line
  o.ground_truth_file = dir.file("missing.txt");
  EXPECT_THROW(asf::io::RawlogReader(log, o), asf::InputError);
}

// ---------------------------------------------------------------- odometry model

/// MRPT's Gaussian motion model as its documentation states it (probabilistic motion models
/// tutorial): independent noise on the increment with
///   sigma_xy  = minStdXY + a1 |d| + a2 |dphi|,  sigma_phi = minStdPHI + a3 |d| + a4 |dphi|
/// in metres and radians, mapped through the Jacobian of the half-angle rotation
///   J = [c -s (-s x - c y); s c (c x - s y); 0 0 1],  c, s = cos, sin(dphi / 2).
/// Our parameters are in MRPT's documented units (a2 m/deg, a3 deg/m, min std deg).
Eigen::Matrix3d documentedModel(const asf::mapping::OdometryNoiseModel& m, double x, double y, double phi) {
  const double deg = M_PI / 180, d = std::hypot(x, y);
  const double sxy = m.min_std_xy + m.a1 * d + (m.a2 / deg) * std::abs(phi);
  const double sphi = m.min_std_phi_deg * deg + m.a3 * deg * d + m.a4 * std::abs(phi);
  const double c = std::cos(phi / 2), s = std::sin(phi / 2);
  Eigen::Matrix3d J;
  J << c, -s, -s * x - c * y, s, c, c * x - s * y, 0, 0, 1;
  return J * Eigen::Vector3d(sxy * sxy, sxy * sxy, sphi * sphi).asDiagonal() * J.transpose();
}

TEST(OdometryNoiseModel, MatchesMrptsDocumentedGaussianModel) {
  const asf::mapping::OdometryNoiseModel def;
  // Standing still: the minimum stds alone, 0.01 m and 0.2 deg.
  const double s0 = 0.2 * M_PI / 180;
  Eigen::Matrix3d want = Eigen::Vector3d(1e-4, 1e-4, s0 * s0).asDiagonal();
  EXPECT_TRUE(def.covariance(CPose2D()).isApprox(want, 1e-12)) << def.covariance(CPose2D());
  // 1 m straight ahead: sigma_xy = 0.01 + 0.01 = 0.02 m, sigma_phi = 0.2 + 1 = 1.2 deg, and
  // heading noise moves y by 1 m per radian.
  const double s1 = 1.2 * M_PI / 180;
  want << 4e-4, 0, 0, 0, 4e-4 + s1 * s1, s1 * s1, 0, s1 * s1, s1 * s1;
  EXPECT_TRUE(def.covariance(CPose2D(1, 0, 0)).isApprox(want, 1e-12))
      << def.covariance(CPose2D(1, 0, 0));

  asf::mapping::OdometryNoiseModel m;
  m.a1 = 0.03;
  m.a2 = 0.002;
  m.a3 = 2.0;
  m.a4 = 0.1;
  m.min_std_xy = 0.005;
  m.min_std_phi_deg = 0.5;
  for (const auto& d : {CPose2D(0.4, 0.1, 0.3), CPose2D(-0.2, 0.3, -1.2), CPose2D(0, 0, 2.5)}) {
    const Eigen::Matrix3d got = m.covariance(d), exp = documentedModel(m, d.x(), d.y(), d.phi());
    EXPECT_TRUE(got.isApprox(exp, 1e-12)) << d << "\n" << got << "\nvs\n" << exp;
  }
  EXPECT_TRUE(
      def.covariance(CPose2D(0.4, 0.1, 0.3)).isApprox(documentedModel(def, 0.4, 0.1, 0.3), 1e-12));
}

/// MRPT's own CActionRobotMovement2D, the oracle: OdometryNoiseModel writes its formula out
/// (no PDFs built per call) and must give the same covariance to the last bit, so that every
/// run's graph is the one MRPT's model gives.
Eigen::Matrix3d mrptModel(const asf::mapping::OdometryNoiseModel& m, const CPose2D& d) {
  mrpt::obs::CActionRobotMovement2D::TMotionModelOptions o;
  o.modelSelection = mrpt::obs::CActionRobotMovement2D::mmGaussian;
  o.gaussianModel.a1 = m.a1;
  o.gaussianModel.a2 = mrpt::RAD2DEG(m.a2);
  o.gaussianModel.a3 = mrpt::DEG2RAD(m.a3);
  o.gaussianModel.a4 = m.a4;
  o.gaussianModel.minStdXY = m.min_std_xy;
  o.gaussianModel.minStdPHI = mrpt::DEG2RAD(m.min_std_phi_deg);
  mrpt::obs::CActionRobotMovement2D act;
  act.computeFromOdometry(d, o);
  mrpt::math::CMatrixDouble33 cov;
  CPose2D mean;
  act.poseChange->getCovarianceAndMean(cov, mean);
  Eigen::Matrix3d out;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) out(r, k) = cov(r, k);
  return out;
}

TEST(OdometryNoiseModel, IsMrptsModelToTheLastBit) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> step(-0.5, 0.5), turn(-3.1, 3.1), param(0.0, 0.1);
  for (int i = 0; i < 2000; ++i) {
    asf::mapping::OdometryNoiseModel m;
    if (i % 2) {  // the defaults, and random models
      m.a1 = param(rng), m.a2 = param(rng) / 10, m.a3 = 20 * param(rng), m.a4 = param(rng);
      m.min_std_xy = param(rng) / 10, m.min_std_phi_deg = 5 * param(rng);
    }
    const CPose2D d = i % 7 == 0 ? CPose2D(0, 0, 0) : CPose2D(step(rng), step(rng), turn(rng));
    const Eigen::Matrix3d got = m.covariance(d), want = mrptModel(m, d);
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k)
        ASSERT_EQ(got(r, k), want(r, k)) << "increment " << d << ", entry (" << r << ", " << k << ")";
  }
}

// ---------------------------------------------------------------- MRPT's sample datasets

TEST(RealData, SenaTelecomFacultyLoop) {
  if (!fs::exists(kSena)) GTEST_SKIP() << kSena << " is missing (Debian package mrpt-common)";
  asf::io::RawlogReader r(kSena);
  std::vector<asf::SensorFrame> f;
  while (auto x = r.next()) f.push_back(*x);
  // 225 sensory frames, the first without an action before it: 224 odometry steps.
  ASSERT_EQ(f.size(), 225u);
  EXPECT_EQ(r.recordIndex(), 448u);
  // Its scans have no sensorLabel: the empty label is the first (and only) one seen.
  EXPECT_EQ(r.laserLabels(), std::vector<std::string>{""});
  EXPECT_EQ(r.skippedScans(), 0u);
  double path = 0, turned = 0;
  for (std::size_t k = 0; k < f.size(); ++k) {
    SCOPED_TRACE("frame " + std::to_string(k));
    ASSERT_TRUE(f[k].scan);
    EXPECT_EQ(f[k].scan->getScanSize(), 361u);
    EXPECT_EQ(f[k].scan->sensorLabel, f[0].scan->sensorLabel);
    EXPECT_TRUE(std::isfinite(f[k].timestamp));
    if (k > 0) {
      EXPECT_GE(f[k].timestamp, f[k - 1].timestamp);
    }
    const auto& o = f[k].odometry;
    ASSERT_TRUE(std::isfinite(o.x()) && std::isfinite(o.y()) && std::isfinite(o.phi()));
    EXPECT_LT(std::hypot(o.x(), o.y()), 1.0);  // one step of a walking-speed robot
    EXPECT_LT(std::abs(o.phi()), 1.0);
    EXPECT_TRUE(f[k].odometry_cov.allFinite());
    EXPECT_GE(f[k].odometry_cov.diagonal().minCoeff(), k == 0 ? 0.0 : 1e-6);
    path += std::hypot(o.x(), o.y());
    turned += o.phi();
  }
  EXPECT_TRUE(f[0].odometry_cov.isZero());
  // One loop around the faculty in about a minute: 76 m of odometry and, with the turns in
  // and out of corridors, -8.1 rad of heading change (the dead-reckoned end is 22 m off).
  EXPECT_NEAR(f.back().timestamp - f.front().timestamp, 59.07, 0.01);
  EXPECT_NEAR(path, 76.35, 0.01);
  EXPECT_NEAR(turned, -8.1455, 1e-3);
}

TEST(RealData, GraphSlamSimulWithGroundTruth) {
  if (!fs::exists(kSimul) || !fs::exists(kSimul + ".GT.txt"))
    GTEST_SKIP() << kSimul << "(.GT.txt) is missing (Debian package mrpt-common)";
  asf::io::RawlogReaderOptions o;
  o.ground_truth_file = kSimul + ".GT.txt";  // 'timestamp x y phi' lines: our format
  asf::io::RawlogReader r(kSimul, o);
  std::vector<asf::SensorFrame> f;
  while (auto x = r.next()) f.push_back(*x);
  ASSERT_EQ(f.size(), 1733u);
  EXPECT_EQ(r.laserLabels(), std::vector<std::string>{"LASER_SIM"});
  // The GT lines are at the scan times (printed to 1 us): every frame gets a pose.
  for (std::size_t k = 0; k < f.size(); ++k) ASSERT_TRUE(f[k].ground_truth) << k;
  // The odometry of frame k is the motion from frame k-1 to k: it follows that true
  // increment (simulated noise) much better than the next one (~0.12 m steps).
  double err = 0, err_shifted = 0, step = 0;
  const std::size_t n = f.size() - 2;
  for (std::size_t k = 1; k <= n; ++k) {
    const CPose2D inc = *f[k].ground_truth - *f[k - 1].ground_truth;
    const CPose2D next = *f[k + 1].ground_truth - *f[k].ground_truth;
    const auto& o = f[k].odometry;
    err += std::hypot(inc.x() - o.x(), inc.y() - o.y()) / n;
    err_shifted += std::hypot(next.x() - o.x(), next.y() - o.y()) / n;
    step += std::hypot(o.x(), o.y()) / n;
  }
  EXPECT_NEAR(step, 0.1157, 1e-3);
  EXPECT_LT(err, 0.03);
  EXPECT_GT(err_shifted, 2 * err);
}

}  // namespace
