// Tests of the rawlog source plugin, loaded through the registry like the host does.
#include <asf/config.h>
#include <asf/errors.h>
#include <asf/io/rawlog_io.h>
#include <asf/framework/registry.h>
#include <asf/source.h>
#include <gtest/gtest.h>
#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/serialization/CArchive.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using mrpt::poses::CPose2D;

namespace {

std::shared_ptr<const asf::framework::PluginInfo> info() {
  static auto i = asf::framework::Registry::loadFile(ASF_TEST_PLUGIN_DIR "/source_rawlog.so");
  return i;
}

asf::framework::PluginHandle<asf::Source> make(const std::map<std::string, std::string>& kv) {
  auto h = asf::framework::Registry::create<asf::Source>(info());
  h->setMinLoggingLevel(mrpt::system::LVL_ERROR);
  h->configure(asf::Params::fromSpecs("rawlog", info()->descriptor->keys,
                                      info()->descriptor->num_keys, kv),
               asf::PluginContext{});
  return h;
}

std::string configError(const std::map<std::string, std::string>& kv) {
  try {
    make(kv);
  } catch (const asf::ConfigError& e) {
    return e.what();
  }
  return "(no ConfigError)";
}

bool has(const std::string& hay, const std::string& needle) {
  return hay.find(needle) != std::string::npos;
}

class TempDir {
 public:
  TempDir() {
    const auto* t = testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() / ("asf_source_rawlog_" + std::string(t->name()) + "_" +
                                         std::to_string(::getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

std::shared_ptr<mrpt::obs::CObservation2DRangeScan> scan(const std::string& label, double t,
                                                         float r) {
  auto s = std::make_shared<mrpt::obs::CObservation2DRangeScan>();
  s->sensorLabel = label;
  s->timestamp = mrpt::Clock::fromDouble(t);
  s->aperture = static_cast<float>(M_PI);
  s->maxRange = 10;
  s->resizeScan(5);
  for (std::size_t i = 0; i < 5; ++i) {
    s->setScanRange(i, r);
    s->setScanRangeValidity(i, true);
  }
  return s;
}

/// Frame k: time 100 + k/2 (unless given), 0.1 m forward and 0.05 rad turn, a scan whose
/// ranges are k + 1.
std::vector<asf::SensorFrame> writeLog(const std::string& path, int n,
                                       const std::vector<double>& times = {}) {
  std::vector<asf::SensorFrame> frames;
  asf::io::RawlogWriter w(path);
  for (int k = 0; k < n; ++k) {
    asf::SensorFrame f;
    f.timestamp = times.empty() ? 100 + 0.5 * k : times[static_cast<std::size_t>(k)];
    f.odometry = CPose2D(0.1, 0, 0.05);
    f.odometry_cov = Eigen::Vector3d(1e-4, 2e-4, 3e-4).asDiagonal();
    f.scan = scan("LASER", f.timestamp, static_cast<float>(k + 1));
    w.write(f);
    frames.push_back(f);
  }
  return frames;
}

std::vector<asf::SensorFrame> drain(asf::Source& s, int limit = 100000) {
  std::vector<asf::SensorFrame> out;
  for (int k = 0; k < limit; ++k) {
    auto f = s.next();
    if (!f) break;
    out.push_back(*f);
  }
  return out;
}

TEST(SourceRawlog, DescriptorAndPassiveContract) {
  EXPECT_STREQ(info()->descriptor->name, "rawlog");
  EXPECT_EQ(info()->kind(), asf::PluginKind::Source);
  TempDir dir;
  writeLog(dir.file("a.rawlog"), 2);
  auto s = make({{"file", dir.file("a.rawlog")}});
  EXPECT_FALSE(s->isActive());
  asf::Goal g;
  g.x = 1;
  EXPECT_EQ(s->navigate(g, {}), asf::NavStatus::Unreachable);
  EXPECT_TRUE(s->next());  // the goal is ignored; frames go on
}

TEST(SourceRawlog, ReplaysEveryFrameThenEnds) {
  TempDir dir;
  const auto written = writeLog(dir.file("a.rawlog.gz"), 6);
  auto s = make({{"file", dir.file("a.rawlog.gz")}});
  const auto f = drain(*s);
  ASSERT_EQ(f.size(), 6u);
  // First frame: nothing delivered before it, so no increment.
  EXPECT_EQ(f[0].odometry.x(), 0.0);
  EXPECT_EQ(f[0].odometry.phi(), 0.0);
  EXPECT_TRUE(f[0].odometry_cov.isZero());
  for (std::size_t k = 0; k < f.size(); ++k) {
    EXPECT_DOUBLE_EQ(f[k].timestamp, written[k].timestamp) << k;
    ASSERT_TRUE(f[k].scan);
    EXPECT_EQ(f[k].scan->getScanRange(0), static_cast<float>(k + 1));
    EXPECT_FALSE(f[k].ground_truth);
    if (k == 0) continue;
    EXPECT_EQ(f[k].odometry.x(), 0.1);
    // CPose2D(x, y, phi) runs phi through wrapToPi, which moves 0.05 by 2e-16: compare with
    // the pose written, not the literal.
    EXPECT_EQ(f[k].odometry.phi(), written[k].odometry.phi());
    EXPECT_EQ(f[k].odometry_cov, written[k].odometry_cov);
  }
  EXPECT_FALSE(s->next());
  EXPECT_FALSE(s->next());
}

TEST(SourceRawlog, StartFrameAndMaxFrames) {
  TempDir dir;
  const auto written = writeLog(dir.file("a.rawlog"), 10);
  auto s = make({{"file", dir.file("a.rawlog")}, {"start_frame", "3"}, {"max_frames", "4"}});
  const auto f = drain(*s);
  ASSERT_EQ(f.size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_DOUBLE_EQ(f[k].timestamp, written[k + 3].timestamp);
    EXPECT_EQ(f[k].scan->getScanRange(0), static_cast<float>(k + 4));
  }
  EXPECT_TRUE(f[0].odometry_cov.isZero());  // the first delivered frame, not the log's
  EXPECT_EQ(f[1].odometry.x(), 0.1);
  EXPECT_FALSE(s->next());

  EXPECT_EQ(drain(*make({{"file", dir.file("a.rawlog")}, {"start_frame", "10"}})).size(), 0u);
  EXPECT_EQ(drain(*make({{"file", dir.file("a.rawlog")}, {"start_frame", "8"}})).size(), 2u);
  EXPECT_EQ(drain(*make({{"file", dir.file("a.rawlog")}, {"max_frames", "20"}})).size(), 10u);
}

TEST(SourceRawlog, LaserLabelSelectsAmongLasers) {
  TempDir dir;
  const std::string path = dir.file("obs.rawlog.gz");
  {
    mrpt::io::CFileGZOutputStream out(path);
    auto ar = mrpt::serialization::archiveFrom(out);
    for (int k = 0; k < 4; ++k) {
      mrpt::obs::CObservationOdometry o;
      o.timestamp = mrpt::Clock::fromDouble(10 + k);
      o.odometry = CPose2D(0.5 * k, 0, 0);
      ar << o << *scan("FRONT", 10.1 + k, 1) << *scan("REAR", 10.2 + k, 2);
    }
  }
  auto rear = drain(*make({{"file", path}, {"laser_label", "REAR"}, {"odo_a1", "0.1"}}));
  ASSERT_EQ(rear.size(), 4u);
  for (const auto& f : rear) EXPECT_EQ(f.scan->sensorLabel, "REAR");
  EXPECT_NEAR(rear[2].odometry.x(), 0.5, 1e-12);
  // The model's covariance with the configured odo_a1: sigma_xy = 0.01 + 0.1 * 0.5.
  EXPECT_NEAR(rear[2].odometry_cov(0, 0), 0.06 * 0.06, 1e-12);
  auto first = drain(*make({{"file", path}}));
  ASSERT_EQ(first.size(), 4u);
  EXPECT_EQ(first[0].scan->sensorLabel, "FRONT");
  // A label no scan has gives no frame: an error naming the labels there are.
  try {
    drain(*make({{"file", path}, {"laser_label", "SIDE"}}));
    ADD_FAILURE() << "no error for laser_label = SIDE";
  } catch (const asf::InputError& e) {
    EXPECT_NE(
        std::string(e.what()).find("no 2D laser scan labelled 'SIDE' (laser_label; labels in the "
                                   "file: 'FRONT' 'REAR')"),
        std::string::npos)
        << e.what();
  }
}

TEST(SourceRawlog, GroundTruthFileAndItsErrors) {
  TempDir dir;
  writeLog(dir.file("a.rawlog"), 4);  // times 100, 100.5, 101, 101.5
  {
    std::ofstream gt(dir.file("gt.txt"));
    gt << "# t x y phi\n99.5 0 0 0\n100.5 1 2 0.5\n101.2 3 2 0.5\n";
  }
  auto f = drain(*make({{"file", dir.file("a.rawlog")}, {"ground_truth", dir.file("gt.txt")},
                        {"ground_truth_max_gap", "1.0"}}));
  ASSERT_EQ(f.size(), 4u);
  ASSERT_TRUE(f[0].ground_truth);
  EXPECT_NEAR(f[0].ground_truth->x(), 0.5, 1e-9);
  EXPECT_NEAR(f[1].ground_truth->y(), 2, 1e-9);
  ASSERT_TRUE(f[2].ground_truth);
  EXPECT_NEAR(f[2].ground_truth->x(), 1 + 2 * (0.5 / 0.7), 1e-9);
  EXPECT_FALSE(f[3].ground_truth);  // after the last line
  // Default max gap 0.5 s: the 1 s and 0.7 s gaps give nothing.
  f = drain(*make({{"file", dir.file("a.rawlog")}, {"ground_truth", dir.file("gt.txt")}}));
  EXPECT_FALSE(f[0].ground_truth);
  EXPECT_TRUE(f[1].ground_truth);  // on a line
  EXPECT_FALSE(f[2].ground_truth);

  {
    std::ofstream gt(dir.file("bad.txt"));
    gt << "100 0 0 0\n100.5 x 0 0\n";
  }
  const std::string e = configError({{"file", dir.file("a.rawlog")},
                                     {"ground_truth", dir.file("bad.txt")}});
  EXPECT_TRUE(has(e, "ground_truth")) << e;
  EXPECT_TRUE(has(e, dir.file("bad.txt") + ":2:")) << e;
}

TEST(SourceRawlog, MissingFileIsAConfigErrorNamingKeyAndFile) {
  TempDir dir;
  const std::string missing = dir.file("none.rawlog");
  const std::string e = configError({{"file", missing}});
  EXPECT_TRUE(has(e, "file")) << e;
  EXPECT_TRUE(has(e, missing)) << e;
  EXPECT_TRUE(has(configError({}), "missing required key 'file'")) << configError({});
  EXPECT_TRUE(has(configError({{"file", dir.file("a.rawlog")}, {"max_frames", "-1"}}),
                  "max_frames"));
}

TEST(SourceRawlog, DamagedLogThrowsInputErrorFromNext) {
  TempDir dir;
  const std::string path = dir.file("a.rawlog");
  writeLog(path, 8);
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const std::string cut = dir.file("cut.rawlog");
  {
    std::ofstream out(cut, std::ios::binary);
    // Half-way plus a little: 8 equal frames end a record exactly half-way, and a log cut
    // between records cannot be told from a shorter log.
    out << bytes.substr(0, bytes.size() / 2 + 10);
  }
  auto s = make({{"file", cut}, {"start_frame", "1"}});
  int n = 0;
  std::string msg;
  try {
    while (s->next()) ++n;
  } catch (const asf::InputError& e) {
    msg = e.what();
  }
  // Frames 1-3 delivered; the action of frame 4 (record 8) is cut.
  EXPECT_TRUE(has(msg, cut + ": record 8: ")) << msg;
  EXPECT_EQ(n, 3);
  EXPECT_FALSE(s->next());
}

TEST(SourceRawlog, TimestampsNeverGoBackwards) {
  TempDir dir;
  writeLog(dir.file("a.rawlog"), 4, {5.0, 6.0, 5.5, 7.0});
  const auto f = drain(*make({{"file", dir.file("a.rawlog")}}));
  ASSERT_EQ(f.size(), 4u);
  EXPECT_EQ(f[2].timestamp, 6.0);  // held at the previous frame's time
  EXPECT_EQ(f[3].timestamp, 7.0);
}

TEST(SourceRawlog, RelativePathsResolveAgainstTheIniFolder) {
  TempDir dir;
  fs::create_directories(dir.path() / "logs");
  writeLog((dir.path() / "logs" / "a.rawlog").string(), 3);
  const std::string ini = dir.file("run.ini");
  {
    std::ofstream out(ini);
    out << "[rawlog]\nfile = logs/a.rawlog\n";
  }
  const auto cfg = asf::IniConfig::fromFile(ini);
  auto h = asf::framework::Registry::create<asf::Source>(info());
  h->configure(cfg.resolve("rawlog", info()->descriptor->keys, info()->descriptor->num_keys),
               asf::PluginContext{});
  EXPECT_EQ(drain(*h).size(), 3u);
}

}  // namespace
