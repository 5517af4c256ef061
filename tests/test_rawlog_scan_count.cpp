// A rawlog whose 2D scan claims an absurd ray count (fuzzing: 4294967295, which MRPT 2.5
// allocates 16.9 GB for and, where that fails, crashes on), or whose sensory frame claims
// millions of observations, is refused by RawlogReader before MRPT allocates, naming the
// record; counts any laser has read as before. Both rawlog layouts, plain and gz.
#include <asf/errors.h>
#include <asf/rawlog_io.h>
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "test_util.h"

namespace fs = std::filesystem;
using mrpt::obs::CObservation2DRangeScan;

namespace {

std::string tempPath(const std::string& name) {
  return (fs::temp_directory_path() / ("asf_scan_count_" + std::to_string(::getpid()) + "_" + name))
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
  asf::RawlogReader r(path);
  std::size_t n = 0;
  while (r.next()) ++n;
  return n;
}

}  // namespace

TEST(RawlogScanCount, ADamagedRayCountIsRefusedBeforeMrptAllocates) {
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

    asf::RawlogReader r(path);
    ASSERT_TRUE(r.next()) << "the first scan is whole";
    const std::string e = asf_test::errorOf<asf::InputError>([&] { r.next(); });
    EXPECT_TRUE(asf_test::has(e, path + ": record 1: a 2D scan claims 4294967295 rays"))
        << "[" << e << "]";

    // A count any laser has (here 1048576, the limit) is MRPT's to read: this one is a lie
    // too, so MRPT finds the bytes missing and the reader says the record is cut.
    bytes.replace(at, 4, std::string("\x00\x00\x10\x00", 4));
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    asf::RawlogReader r2(path);
    ASSERT_TRUE(r2.next());
    const std::string e2 = asf_test::errorOf<asf::InputError>([&] {
      while (r2.next()) {
      }
    });
    EXPECT_FALSE(asf_test::has(e2, "claims")) << e2;
    fs::remove(path);
  }
}

TEST(RawlogScanCount, GzLogsAreGuardedToo) {
  const std::string plain = tempPath("g.rawlog"), gz = tempPath("g.rawlog.gz");
  writeLog(plain, false);
  std::string bytes = readBytes(plain);
  bytes.replace(countOffset(bytes, 2), 4, "\xff\xff\xff\xff");  // the third scan
  {
    mrpt::io::CFileGZOutputStream out(gz);
    out.Write(bytes.data(), bytes.size());
  }
  asf::RawlogReader r(gz);
  ASSERT_TRUE(r.next());
  ASSERT_TRUE(r.next());
  const std::string e = asf_test::errorOf<asf::InputError>([&] { r.next(); });
  EXPECT_TRUE(asf_test::has(e, "record 2: a 2D scan claims 4294967295 rays")) << e;
  fs::remove(plain);
  fs::remove(gz);
}

TEST(RawlogScanCount, ASensoryFrameClaimingMillionsOfObservationsIsRefused) {
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
  asf::RawlogReader r(path);
  ASSERT_TRUE(r.next());
  const std::string e = asf_test::errorOf<asf::InputError>([&] { r.next(); });
  EXPECT_TRUE(asf_test::has(e, "record 1: a sensory frame claims 980615169 objects")) << e;
  fs::remove(path);
}
