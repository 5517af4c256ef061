// Records MRPT 2.5 crashes on are refused by RawlogReader, naming the record:
// - a 2D scan claiming an absurd ray count (fuzzing: 4294967295, which MRPT allocates 16.9 GB
//   for and, where that fails, crashes on), or a sensory frame claiming millions of
//   observations, before MRPT allocates; counts any laser has read as before. Both rawlog
//   layouts, plain and gz.
// - an action collection holding an object that is not an action or a null one, and an
//   odometry action whose pose change is not a pose PDF (MRPT clones the null result of its
//   cast: SIGSEGV); the well-formed actions MRPT writes read as before.
// - a 3D range scan of MRPT's own sample claiming a 0x7fffffff-row range image (SIGSEGV in
//   rangeImage_setSize), through RawlogReader and through asf map3d's reader; the sample
//   itself reads as before.
#include <asf/errors.h>
#include <asf/mapping/map3d.h>
#include <asf/studies/map3d_from_log.h>
#include <asf/io/rawlog_io.h>
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/serialization/CArchive.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <tuple>

#include "test_util.h"

namespace fs = std::filesystem;
using mrpt::obs::CObservation2DRangeScan;

namespace {

std::string tempPath(const std::string& name) {
  return (fs::temp_directory_path() /
          ("asf_rawlog_guard_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

CObservation2DRangeScan::Ptr scan(std::size_t rays) {
  auto s = std::make_shared<CObservation2DRangeScan>();
  s->sensorLabel = "LASER";
  s->aperture = 3.0f;
  s->maxRange = 10.0f;
  s->sensorPose = mrpt::poses::CPose3D(0.1, 0, 0.2, 0, 0, 0);
  s->timestamp = mrpt::Clock::fromDouble(5.0);
  s->resizeScan(rays);
  for (std::size_t i = 0; i < rays; ++i) {
    s->setScanRange(i, 1.0f + 0.01f * i);
    s->setScanRangeValidity(i, true);
  }
  return s;
}

/// Three scans of 77 rays: as plain observations, or each in a sensory frame.
void writeLog(const std::string& path, bool sensory_frames) {
  mrpt::io::CFileOutputStream out(path);
  auto ar = mrpt::serialization::archiveFrom(out);
  for (int k = 0; k < 3; ++k) {
    if (sensory_frames) {
      mrpt::obs::CSensoryFrame sf;
      sf.insert(scan(77));
      ar << sf;
    } else {
      ar << *scan(77);
    }
  }
}

std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Offset of the ray count of the scan whose sensor pose is the `k`-th "CPose3D" in the
/// file: name, version byte (3), twelve doubles, end flag (MRPT 2.5's layout).
std::size_t countOffset(const std::string& bytes, int k) {
  std::size_t at = 0;
  for (int i = 0; i <= k; ++i) at = bytes.find("CPose3D", i ? at + 1 : 0);
  return at + 7 + 1 + 12 * 8 + 1;
}

std::size_t framesIn(const std::string& path) {
  asf::io::RawlogReader r(path);
  std::size_t n = 0;
  while (r.next()) ++n;
  return n;
}

}  // namespace

TEST(RawlogGuard, ADamagedRayCountIsRefusedBeforeMrptAllocates) {
  for (bool sf : {false, true}) {
    SCOPED_TRACE(sf ? "sensory frames" : "observations");
    const std::string path = tempPath(sf ? "sf.rawlog" : "obs.rawlog");
    writeLog(path, sf);
    ASSERT_EQ(framesIn(path), 3u);
    std::string bytes = readBytes(path);
    const std::size_t at = countOffset(bytes, 1);  // the second scan
    ASSERT_LT(at + 4, bytes.size());
    ASSERT_EQ(bytes.substr(at, 4), std::string("\x4d\x00\x00\x00", 4))
        << "not MRPT 2.5's layout: the test (and the guard) need updating";
    bytes.replace(at, 4, "\xff\xff\xff\xff");
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;

    asf::io::RawlogReader r(path);
    ASSERT_TRUE(r.next()) << "the first scan is whole";
    const std::string e = asf_test::errorOf<asf::InputError>([&] { r.next(); });
    EXPECT_TRUE(asf_test::has(e, path + ": record 1: a 2D scan claims 4294967295 rays"))
        << "[" << e << "]";

    // A count any laser has (here 1048576, the limit) is MRPT's to read: this one is a lie
    // too, so MRPT finds the bytes missing and the reader says the record is cut.
    bytes.replace(at, 4, std::string("\x00\x00\x10\x00", 4));
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    asf::io::RawlogReader r2(path);
    ASSERT_TRUE(r2.next());
    const std::string e2 = asf_test::errorOf<asf::InputError>([&] {
      while (r2.next()) {
      }
    });
    EXPECT_FALSE(asf_test::has(e2, "claims")) << e2;
    fs::remove(path);
  }
}

TEST(RawlogGuard, GzLogsAreGuardedToo) {
  const std::string plain = tempPath("g.rawlog"), gz = tempPath("g.rawlog.gz");
  writeLog(plain, false);
  std::string bytes = readBytes(plain);
  bytes.replace(countOffset(bytes, 2), 4, "\xff\xff\xff\xff");  // the third scan
  {
    mrpt::io::CFileGZOutputStream out(gz);
    out.Write(bytes.data(), bytes.size());
  }
  asf::io::RawlogReader r(gz);
  ASSERT_TRUE(r.next());
  ASSERT_TRUE(r.next());
  const std::string e = asf_test::errorOf<asf::InputError>([&] { r.next(); });
  EXPECT_TRUE(asf_test::has(e, "record 2: a 2D scan claims 4294967295 rays")) << e;
  fs::remove(plain);
  fs::remove(gz);
}

TEST(RawlogGuard, ASensoryFrameClaimingMillionsOfObservationsIsRefused) {
  // Fuzzing: a frame count of 980615169 made MRPT resize a deque of that many pointers
  // (16 GB and 39 s here before failing).
  const std::string path = tempPath("frame.rawlog");
  writeLog(path, true);
  std::string bytes = readBytes(path);
  const std::size_t name = bytes.find("CSensoryFrame", bytes.find("CSensoryFrame") + 1);
  const std::size_t at = name + std::string("CSensoryFrame").size() + 1;  // after the version
  ASSERT_EQ(bytes.substr(at, 4), std::string("\x01\x00\x00\x00", 4)) << "one observation";
  bytes.replace(at, 4, std::string("\x01\x00\x73\x3a", 4));
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  asf::io::RawlogReader r(path);
  ASSERT_TRUE(r.next());
  const std::string e = asf_test::errorOf<asf::InputError>([&] { r.next(); });
  EXPECT_TRUE(asf_test::has(e, "record 1: a sensory frame claims 980615169 objects")) << e;
  fs::remove(path);
}

// ------------------------------------------------------------- what sits inside an action

namespace {

using mrpt::obs::CActionRobotMovement2D;

/// The bytes MRPT writes for an object (header, version, contents, end flag).
std::string bytesOf(const mrpt::serialization::CSerializable& o) {
  mrpt::io::CMemoryStream mem;
  auto ar = mrpt::serialization::archiveFrom(mem);
  ar << o;
  return {static_cast<const char*>(mem.getRawBufferData()),
          static_cast<std::size_t>(mem.getTotalBytesCount())};
}

std::string u32(std::uint32_t v) {
  return {static_cast<char>(v & 0xff), static_cast<char>((v >> 8) & 0xff),
          static_cast<char>((v >> 16) & 0xff), static_cast<char>(v >> 24)};
}

/// An action collection written by hand around the objects' bytes, claiming `count`.
std::string collection(const std::vector<std::string>& objects, std::uint32_t count) {
  const std::string name = "mrpt::obs::CActionCollection";
  std::string c = std::string(1, static_cast<char>(0x80 | name.size())) + name + '\0' + u32(count);
  for (const auto& o : objects) c += o;
  return c + '\x88';
}

const std::string kNull = "\x87nullptr\x88";  // MRPT's null pointer: no version

CActionRobotMovement2D odometryAction(double x) {
  CActionRobotMovement2D m;
  m.computeFromOdometry(mrpt::poses::CPose2D(x, 0, 0.1),
                        CActionRobotMovement2D::TMotionModelOptions());
  return m;
}

/// An odometry action estimated by scan matching: its pose PDF is written as an object.
CActionRobotMovement2D matchedAction() {
  CActionRobotMovement2D m;
  m.estimationMethod = CActionRobotMovement2D::emScan2DMatching;
  auto pdf = mrpt::poses::CPosePDFGaussian::Create();
  pdf->mean = mrpt::poses::CPose2D(0.5, 0, 0);
  m.poseChange = pdf;
  return m;
}

/// A rawlog of a sensory frame (record 0) and then `record` (record 1).
std::string logWith(const std::string& name, const std::string& record) {
  const std::string path = tempPath(name);
  mrpt::obs::CSensoryFrame sf;
  sf.insert(scan(20));
  std::ofstream(path, std::ios::binary) << bytesOf(sf) << record;
  return path;
}

/// What reading the whole log says: "" if it reads to the end.
std::string readError(const std::string& path) {
  try {
    asf::io::RawlogReader r(path);
    while (r.next()) {
    }
  } catch (const asf::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(RawlogGuard, ActionsMrptWritesReadAsBefore) {
  mrpt::obs::CActionCollection acts;
  acts.insert(odometryAction(1.0));
  acts.insert(matchedAction());
  acts.insert(mrpt::obs::CActionRobotMovement3D());
  const std::string by_hand = collection({bytesOf(odometryAction(1.0)), bytesOf(matchedAction()),
                                          bytesOf(mrpt::obs::CActionRobotMovement3D())},
                                         3);
  ASSERT_EQ(by_hand, bytesOf(acts))
      << "not MRPT 2.5's layout: the test (and the guard) need updating";
  const std::string path = logWith("good_actions.rawlog", bytesOf(acts) + bytesOf(acts));
  EXPECT_EQ(readError(path), "");
  fs::remove(path);
}

TEST(RawlogGuard, AnActionCollectionHoldingWhatIsNotAnActionIsRefused) {
  // Fuzzing: MRPT 2.5 died with SIGSEGV on each of these.
  const std::string pose = bytesOf(mrpt::poses::CPose2D(1, 2, 3));
  const std::string odo = bytesOf(odometryAction(1.0));
  const struct {
    const char* name;
    std::string record;
    const char* says;
  } cases[] = {
      {"pose", collection({pose}, 1), "holds mrpt::poses::CPose2D, not an action"},
      {"null", collection({kNull}, 1), "holds a null object, not an action"},
      {"second", collection({odo, pose}, 2), "holds mrpt::poses::CPose2D, not an action"},
      {"after_matched", collection({bytesOf(matchedAction()), kNull}, 2), "a null object"},
      // MRPT finds the second action where the end flag should be: its error, not a crash.
      {"more", collection({odo, odo}, 1), "end-flag missing"},
      {"fewer", collection({odo}, 2) + odo, "claims 2 objects but ends after 1"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = logWith(std::string(c.name) + ".rawlog", c.record);
    const std::string e = readError(path);
    EXPECT_TRUE(asf_test::has(e, path + ": record 1: ")) << e;
    EXPECT_TRUE(asf_test::has(e, c.says)) << e;
    fs::remove(path);
  }
}

TEST(RawlogGuard, AMatchedActionWhosePoseChangeIsNotAPdfIsRefused) {
  const std::string good = bytesOf(matchedAction());
  const std::string pdf = bytesOf(*matchedAction().poseChange.get_ptr());
  const std::size_t at = good.find(pdf);
  ASSERT_NE(at, std::string::npos);
  // Fuzzing: the abstract "mrpt::poses::CPosePDF" has no constructor: MRPT reads it as null.
  const std::string abstract_pdf = std::string("\x95mrpt::poses::CPosePDF", 22) + '\0' + '\x88';
  for (const std::string& in_place :
       {bytesOf(mrpt::poses::CPose2D(1, 2, 3)), kNull, abstract_pdf}) {
    std::string bad = good;
    bad.replace(at, pdf.size(), in_place);
    for (const bool in_collection : {true, false}) {
      SCOPED_TRACE(in_place + (in_collection ? " in a collection" : " alone"));
      const std::string path =
          logWith("matched.rawlog", in_collection ? collection({bad}, 1) : bad);
      const std::string e = readError(path);
      EXPECT_TRUE(asf_test::has(e, "record 1: an odometry action's pose change is")) << e;
      EXPECT_TRUE(asf_test::has(e, "not a pose PDF")) << e;
      fs::remove(path);
    }
  }
  // Odometry estimated from wheels writes a CPose2D there: MRPT reads it.
  EXPECT_EQ(bytesOf(odometryAction(2.0)).find("mrpt::poses::CPosePDF"), std::string::npos);
}

TEST(RawlogGuard, ASensoryFrameHoldingWhatIsNotAnObservationIsAnError) {
  // MRPT reads it as a null observation; the reader used to dereference it.
  const std::string name = "mrpt::obs::CSensoryFrame";
  const std::string frame = std::string(1, static_cast<char>(0x80 | name.size())) + name + '\x02' +
                            u32(2) + bytesOf(*scan(10)) + bytesOf(mrpt::poses::CPose2D(1, 2, 3)) +
                            '\x88';
  const std::string path = logWith("frame_pose.rawlog", frame);
  const std::string e = readError(path);
  EXPECT_TRUE(asf_test::has(
      e, "record 1: a sensory frame holds a null object or one that is not an observation"))
      << e;
  fs::remove(path);
}

TEST(RawlogGuard, DamagedLengthsBehindADamagedNameAreRefusedToo) {
  // Fuzzing: MRPT reads a class name up to its first NUL and resolves it by the part after
  // the last "::", so "mrp::CActionCollection\0\x01" is a collection; its count of 1839267840
  // made MRPT take 24 GB before the kernel killed it.
  const std::string odo = bytesOf(odometryAction(1.0));
  std::string record = collection({odo}, 1);
  const std::string name = "mrpt::obs::CActionCollection";
  record.replace(0, 1 + name.size() + 1 + 4,
                 std::string("\x98mrp::CActionCollection\0\x01", 25) + '\0' + u32(1839267840));
  const std::string path = logWith("mangled.rawlog", record);
  const std::string e = readError(path);
  EXPECT_TRUE(asf_test::has(e, "record 1: an action collection claims 1839267840 objects")) << e;
  fs::remove(path);
}

TEST(RawlogGuard, ASensorLabelClaimingGigabytesIsRefused) {
  // Fuzzing: MRPT fills a string of the length it reads (4 GB, 5 s) before finding the
  // bytes missing.
  mrpt::obs::CObservationOdometry odo;
  odo.sensorLabel = "ODOM";
  odo.odometry = mrpt::poses::CPose2D(1, 2, 0.5);
  auto s = scan(15);
  s->sensorLabel = "LASER";
  for (const auto& [record, label, whose] :
       {std::tuple{bytesOf(*s), std::string("LASER"), "a 2D scan's"},
        std::tuple{bytesOf(odo), std::string("ODOM"), "an odometry reading's"}}) {
    SCOPED_TRACE(whose);
    const std::string length = u32(static_cast<std::uint32_t>(label.size())) + label;
    const std::size_t at = record.find(length);
    ASSERT_NE(at, std::string::npos)
        << "not MRPT 2.5's layout: the test (and the guard) need updating";
    for (const std::uint32_t claim : {0xffffffffu, 70000u, 65536u}) {
      std::string bad = record;
      bad.replace(at, 4, u32(claim));
      const std::string path = logWith("label.rawlog", bad);
      const std::string e = readError(path);
      // Up to 64 KB is MRPT's to read (and these bytes are missing: a cut record).
      EXPECT_EQ(asf_test::has(e, std::string("record 1: ") + whose + " sensor label claims " +
                                     std::to_string(claim) + " bytes"),
                claim > 65536)
          << e;
      EXPECT_FALSE(e.empty());
      fs::remove(path);
    }
    const std::string path = logWith("label_ok.rawlog", record);
    EXPECT_EQ(readError(path), "");
    fs::remove(path);
  }
}

TEST(RawlogGuard, AMotionModelClaimingBillionsOfParticlesIsRefused) {
  // Fuzzing: MRPT rebuilds an odometry action's PDF when it reads it, drawing the particles of
  // Thrun's model: a damaged count of 996459400 took 24 GB before the kernel killed it.
  CActionRobotMovement2D::TMotionModelOptions thrun;
  thrun.modelSelection = CActionRobotMovement2D::mmThrun;
  thrun.thrunModel.nParticlesCount = 77;
  CActionRobotMovement2D m;
  m.computeFromOdometry(mrpt::poses::CPose2D(0.5, 0, 0.1), thrun);
  const std::string good = bytesOf(m);
  const std::size_t at = good.find(u32(77));
  ASSERT_NE(at, std::string::npos);
  // MRPT resolves a class name by its part after the last "::": fuzzing damaged the raw
  // increment's "mrpt::poses::CPose2D" to this, and MRPT still read a CPose2D.
  std::string mangled = good;
  const std::size_t pose = mangled.find("mrpt::poses::CPose2D");
  ASSERT_NE(pose, std::string::npos);
  mangled.replace(pose, 20,
                  std::string("mrpt:\xff\xff&\x10"
                              "es::CPose2D",
                              20));
  for (const std::uint32_t claim : {996459400u, 1048577u})
    for (const std::string& base : {good, mangled}) {
      std::string bad = base;
      bad.replace(at, 4, u32(claim));
      const std::string path = logWith("particles.rawlog", collection({bad}, 1));
      const std::string e = readError(path);
      EXPECT_TRUE(asf_test::has(e, "record 1: an odometry action's motion model claims " +
                                       std::to_string(claim) + " particles"))
          << e;
      fs::remove(path);
    }
  const std::string path = logWith("particles_ok.rawlog", collection({good, mangled}, 2));
  EXPECT_EQ(readError(path), "");
  fs::remove(path);
}

TEST(RawlogGuard, OldSensoryFramesAreGuardedToo) {
  // CSensoryFrame versions 0 and 1 (older MRPT) put an ID, and version 0 a timestamp, before
  // the count: fuzzing found a version-0 frame claiming 976909154 observations (16 GB). Version
  // 0 also sets each observation's timestamp after reading them: a null one would crash.
  const std::string name = "mrpt::obs::CSensoryFrame";
  auto frame = [&](int version, std::uint32_t count, const std::string& objects) {
    std::string f =
        std::string(1, static_cast<char>(0x80 | name.size())) + name + static_cast<char>(version);
    if (version < 2) f += u32(7);                 // ID
    if (version == 0) f += std::string(8, '\0');  // timestamp
    return f + u32(count) + objects + '\x88';
  };
  const std::string obs = bytesOf(*scan(12));
  const struct {
    int version;
    std::string record;
    const char* says;
  } cases[] = {
      {0, frame(0, 976909154, obs), "a sensory frame claims 976909154 objects"},
      {1, frame(1, 976909154, obs), "a sensory frame claims 976909154 objects"},
      {0, frame(0, 2, obs + kNull), "a version-0 sensory frame holds a null object"},
      {0, frame(0, 1, bytesOf(mrpt::poses::CPose2D(1, 2, 3))),
       "a version-0 sensory frame holds mrpt::poses::CPose2D, not an observation"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.says);
    const std::string path = logWith("old_frame.rawlog", c.record);
    const std::string e = readError(path);
    EXPECT_TRUE(asf_test::has(e, std::string("record 1: ") + c.says)) << e;
    fs::remove(path);
  }
  for (int version : {0, 1}) {  // well-formed: read as before
    const std::string path = logWith("old_frame_ok.rawlog", frame(version, 2, obs + obs));
    EXPECT_EQ(readError(path), "") << "version " << version;
    fs::remove(path);
  }
}

TEST(RawlogGuard, A3dActionClaimingBillionsOfVelocitiesIsRefused) {
  // Fuzzing: a 3D odometry action's velocity vector claimed 1919786758 floats (7.7 GB, which
  // MRPT resizes the vector to before reading).
  const std::string good = bytesOf(mrpt::obs::CActionRobotMovement3D());
  const std::string counts = u32(6) + std::string(6, '\0') + u32(6);
  const std::size_t at = good.find(counts);
  ASSERT_NE(at, std::string::npos)
      << "not MRPT 2.5's layout: the test (and the guard) need updating";
  const struct {
    std::size_t offset;
    const char* says;
  } cases[] = {{at + 10, "claims 1919786758 velocities"}, {at, "claims 1919786758 velocity flags"}};
  for (const auto& c : cases) {
    std::string bad = good;
    bad.replace(c.offset, 4, u32(1919786758u));
    const std::string path = logWith("velocities.rawlog", collection({bad}, 1));
    const std::string e = readError(path);
    EXPECT_TRUE(asf_test::has(e, std::string("record 1: a 3D odometry action ") + c.says)) << e;
    fs::remove(path);
  }
}

TEST(RawlogGuard, ALongDamagedClassNameIsResolvedAsMrptDoes) {
  // Fuzzing: a 116-byte name "mrpt::obs::COb\x9cmrpt::obs::CActionCollection\0..." inside a
  // frame, which MRPT reads as a collection; the guard looked only at reads of up to 64 bytes
  // and let its count of 1922318624 through.
  const std::string name = std::string("mrpt::obs::COb\x9c") + "mrpt::obs::CActionCollection";
  std::string padded = name + std::string(116 - name.size(), '\0');
  const std::string record =
      std::string(1, static_cast<char>(0x80 | padded.size())) + padded + '\0' + u32(1922318624u);
  const std::string path = logWith("long_name.rawlog", record);
  const std::string e = readError(path);
  EXPECT_TRUE(asf_test::has(e, "record 1: an action collection claims 1922318624 objects")) << e;
  fs::remove(path);
}

TEST(RawlogGuard, A3DScanClaimingAHugeRangeImageIsRefused) {
  const std::string sample = "/usr/share/mrpt/datasets/tests_rgbd.rawlog";
  if (!fs::exists(sample)) GTEST_SKIP() << "needs MRPT's sample " << sample << " (Debian: mrpt-common)";
  std::string bytes;
  {
    mrpt::io::CFileGZInputStream in(sample);
    char buf[65536];
    for (std::size_t got; (got = in.Read(buf, sizeof buf)) > 0 && got <= sizeof buf;) bytes.append(buf, got);
  }
  const std::string path = tempPath("rgbd.rawlog");
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  EXPECT_EQ(framesIn(path), 0u) << "3D scans are no 2D frames, and no error";
  // The range image's rows (480) and columns (640) of one of its 3D scans (version 9).
  const std::size_t at = 4371769;
  ASSERT_LT(at + 8, bytes.size());
  ASSERT_EQ(bytes.substr(at, 8), std::string("\xe0\x01\x00\x00\x80\x02\x00\x00", 8))
      << "not the sample this test was written for";
  bytes.replace(at, 4, "\xff\xff\xff\x7f");
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  asf::io::RawlogReader r(path);
  const std::string e = asf_test::errorOf<asf::InputError>([&] {
    while (r.next()) {
    }
  });
  EXPECT_TRUE(asf_test::has(e, "a 3D range scan claims a range image of 2147483647 x 640 pixels"))
      << "[" << e << "]";
  asf::mapping::Map3d map;
  const asf::studies::Map3dFromLogReport rep = asf::studies::insertRawlog3d(path, {}, map, {});
  EXPECT_TRUE(asf_test::has(rep.error, "a 3D range scan claims a range image of 2147483647 x 640"))
      << "[" << rep.error << "]";
  fs::remove(path);
}
