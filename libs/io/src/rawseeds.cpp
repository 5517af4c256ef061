#include <asf/atomic_file.h>
#include <asf/errors.h>
#include <asf/io/rawlog_io.h>
#include <asf/text.h>
#include <asf/io/rawseeds.h>
#include <asf/io/text_io.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <ostream>

namespace asf::io {

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr int kSickRays = 181;

std::string lineRef(const LineReader& r) { return r.path() + ":" + std::to_string(r.lineNumber()); }

using Fields = std::vector<std::string_view>;

/// One CSV stream read a record ahead, so streams can be merged by time.
class CsvStream {
 public:
  /// Returns the observation of a line, or null with `why` set.
  using Parser =
      std::function<mrpt::obs::CObservation::Ptr(const Fields&, const Stamp&, std::string& why)>;

  CsvStream(const std::string& path, const std::string& stream, bool strictly_increasing,
            bool skip_bad, Parser parser)
      : reader_(path), strict_(strictly_increasing), skip_(skip_bad), parse_(std::move(parser)) {
    report.stream = stream;
    report.file = path;
  }

  /// Reads the next good record into t/obs; false at the end of the file.
  bool advance() {
    std::string line, why;
    while (reader_.next(line)) {
      ++report.lines;
      const Fields f = splitFields(line, ',');
      if (f.empty() || (!f[0].empty() && f[0].front() == '#')) continue;
      const auto st = parseStamp(f[0]);
      if (!st) {
        bad("timestamp '" + std::string(f[0]) + "' is not a time in seconds");
        continue;
      }
      if (last_ && (strict_ ? *st <= *last_ : *st < *last_)) {
        bad("time " + st->str() + (strict_ ? " does not increase" : " goes backwards") +
            " (previous line: " + last_->str() + ")");
        continue;
      }
      auto o = parse_(f, *st, why);
      if (!o) {
        bad(why);
        continue;
      }
      t = *st;
      obs = std::move(o);
      if (report.records == 0) report.t_first = t.seconds();
      report.t_last = t.seconds();
      ++report.records;
      last_ = t;
      return true;
    }
    obs.reset();
    return false;
  }

  double progress() const { return reader_.progress(); }

  StreamReport report;
  Stamp t;
  mrpt::obs::CObservation::Ptr obs;  ///< null at the end

 private:
  void bad(const std::string& why) {
    if (!skip_) throw InputError(lineRef(reader_) + ": " + why);
    if (report.bad_lines++ == 0) {
      report.first_bad_line = reader_.lineNumber();
      report.first_bad_reason = why;
    }
  }

  LineReader reader_;
  bool strict_, skip_;
  Parser parse_;
  std::optional<Stamp> last_;
};

std::string fieldCount(const Fields& f) { return std::to_string(f.size()) + " fields"; }

CsvStream::Parser laserParser(const std::string& stream) {
  const mrpt::poses::CPose3D pose = rawseedsLaserPose(stream);
  return [pose, stream](const Fields& f, const Stamp& t,
                        std::string& why) -> mrpt::obs::CObservation::Ptr {
    if (f.size() < 3) {
      why = "expected timestamp, number of ranges, angular offset, R1..RN; got " + fieldCount(f);
      return nullptr;
    }
    const auto n = parseInt(f[1]);
    if (!n || *n < 2 || *n > 100000) {
      why = "number of ranges '" + std::string(f[1]) + "' is not an integer >= 2";
      return nullptr;
    }
    if (f.size() != static_cast<std::size_t>(3 + *n)) {
      why = std::to_string(*n) + " ranges announced, " + std::to_string(f.size() - 3) + " found";
      return nullptr;
    }
    const auto offset = parseDouble(f[2]);
    if (!offset) {
      why = "angular offset '" + std::string(f[2]) + "' is not a number";
      return nullptr;
    }
    auto scan = std::make_shared<mrpt::obs::CObservation2DRangeScan>();
    scan->sensorLabel = stream;
    scan->timestamp = t.toClock();
    scan->aperture = static_cast<float>(M_PI);
    scan->rightToLeft = true;
    scan->maxRange = static_cast<float>(kSickMaxRange);
    // The offset (interlaced SICK modes, quarter degrees) turns the whole fan.
    scan->sensorPose = pose + mrpt::poses::CPose3D(0, 0, 0, *offset * 0.25 * kDeg, 0, 0);
    scan->resizeScan(static_cast<std::size_t>(*n));
    for (std::size_t i = 0; i < static_cast<std::size_t>(*n); ++i) {
      const auto r = parseNumber(f[3 + i]);
      if (!r) {
        why =
            "range R" + std::to_string(i + 1) + " '" + std::string(f[3 + i]) + "' is not a number";
        return nullptr;
      }
      const bool valid = std::isfinite(*r) && *r > 0 && *r < kSickMaxRange;
      scan->setScanRange(i, static_cast<float>(valid ? *r : kSickMaxRange));
      scan->setScanRangeValidity(i, valid);
    }
    return scan;
  };
}

CsvStream::Parser odometryParser() {
  return [](const Fields& f, const Stamp& t, std::string& why) -> mrpt::obs::CObservation::Ptr {
    if (f.size() != 7) {
      why = "expected 7 fields (timestamp, counter, ticks left, ticks right, X, Y, Theta), got " +
            std::to_string(f.size());
      return nullptr;
    }
    static const char* kNames[] = {"",     "rolling counter", "ticks left", "ticks right", "X", "Y",
                                   "Theta"};
    double v[7];
    for (int i = 1; i < 7; ++i) {
      const auto d = parseDouble(f[static_cast<std::size_t>(i)]);
      if (!d) {
        why = std::string(kNames[i]) + " '" + std::string(f[static_cast<std::size_t>(i)]) +
              "' is not a number";
        return nullptr;
      }
      v[i] = *d;
    }
    auto o = std::make_shared<mrpt::obs::CObservationOdometry>();
    o->sensorLabel = "ODOMETRY_XYT";
    o->timestamp = t.toClock();
    o->odometry = mrpt::poses::CPose2D(v[4], v[5], v[6]);
    if (std::abs(v[2]) < 2e9 && std::abs(v[3]) < 2e9) {
      o->hasEncodersInfo = true;
      o->encoderLeftTicks = static_cast<std::int32_t>(std::llround(v[2]));
      o->encoderRightTicks = static_cast<std::int32_t>(std::llround(v[3]));
    }
    return o;
  };
}

// Ground-truth lines become CObservationOdometry carriers of the pose (never written to the
// rawlog; only their pose and time are used).
CsvStream::Parser groundTruthParser() {
  return [](const Fields& f, const Stamp& t, std::string& why) -> mrpt::obs::CObservation::Ptr {
    if (f.size() != 13 && f.size() != 4) {
      why =
          "expected 13 fields (timestamp, X, Y, Theta, 9 covariance terms) or 4 "
          "(GT-extended: timestamp, X, Y, Theta), got " +
          std::to_string(f.size());
      return nullptr;
    }
    double v[13];
    for (std::size_t i = 1; i < f.size(); ++i) {
      const auto d = parseDouble(f[i]);
      if (!d) {
        why = "field " + std::to_string(i + 1) + " '" + std::string(f[i]) + "' is not a number";
        return nullptr;
      }
      v[i] = *d;
    }
    auto o = std::make_shared<mrpt::obs::CObservationOdometry>();
    o->timestamp = t.toClock();
    o->odometry = mrpt::poses::CPose2D(v[1], v[2], v[3]);
    return o;
  };
}

/// A text output written as asf::AtomicOutput writes: to "<path>.tmp", renamed by close();
/// removed if never closed (a device is written in place).
class TextOut {
 public:
  explicit TextOut(const std::string& path) : path_(path), target_(path, "CSV stream") {
    if (path.size() > 4 && path.compare(path.size() - 4, 4, ".bz2") == 0)
      bz_ = std::make_unique<Bz2Writer>(target_.file());
    else if (!(f_ = std::fopen(target_.file().c_str(), "wb")))
      throw InputError(path + ": cannot open for writing");
  }
  ~TextOut() {
    bz_.reset();
    if (f_) std::fclose(f_);
  }
  void line(const std::string& s) {
    buf_ += s;
    buf_ += '\n';
    if (buf_.size() > (1 << 20)) flush();
  }
  void close() {
    flush();
    if (bz_) bz_->close();
    if (f_ && std::fclose(f_) != 0) {
      f_ = nullptr;
      throw InputError(path_ + ": write error");
    }
    f_ = nullptr;
    target_.commit();
  }

 private:
  void flush() {
    if (bz_)
      bz_->write(buf_);
    else if (std::fwrite(buf_.data(), 1, buf_.size(), f_) != buf_.size())
      throw InputError(path_ + ": write error");
    buf_.clear();
  }
  std::string path_, buf_;
  AtomicOutput target_;
  std::unique_ptr<Bz2Writer> bz_;
  FILE* f_ = nullptr;
};

std::string percent(double p) {
  if (p < 0) return "?";
  char b[16];
  std::snprintf(b, sizeof b, "%.0f%%", 100 * p);
  return b;
}

}  // namespace

mrpt::poses::CPose3D rawseedsLaserPose(const std::string& stream) {
  if (stream == "SICK_FRONT") return mrpt::poses::CPose3D(0.080, 0.0, 0.450, 0, 0, 0);
  if (stream == "SICK_REAR") return mrpt::poses::CPose3D(-0.463, 0.001, 0.450, M_PI, 0, 0);
  throw InputError("laser stream '" + stream +
                   "' is not supported: use SICK_FRONT and/or SICK_REAR (the Hokuyo streams "
                   "are tilted and have another line format)");
}

std::string findRawseedsStream(const std::string& dir, const std::string& dataset,
                               const std::string& stream) {
  const std::string base = (std::filesystem::path(dir) / (dataset + "-" + stream)).string();
  for (const char* ext : {".csv", ".csv.bz2"})
    if (std::filesystem::is_regular_file(base + ext)) return base + ext;
  throw InputError("stream " + stream + " not found: neither " + base + ".csv nor " + base +
                   ".csv.bz2 exists");
}

RawseedsToRawlogReport rawseedsToRawlog(const RawseedsToRawlogOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  if (opt.lasers.empty()) throw InputError("rawseeds2rawlog: no laser stream given");
  for (std::size_t i = 0; i < opt.lasers.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (opt.lasers[i] == opt.lasers[j])
        throw InputError("laser stream " + opt.lasers[i] + " given twice");
  if (opt.gt_stream != "GROUNDTRUTH" && opt.gt_stream != "GT-extended")
    throw InputError("ground-truth stream '" + opt.gt_stream +
                     "' unknown: use GROUNDTRUTH or GT-extended");

  // Find every file before writing anything: a missing stream fails fast.
  const std::string odo_file = findRawseedsStream(opt.dir, opt.dataset, "ODOMETRY_XYT");
  std::vector<std::string> laser_files;
  for (const auto& l : opt.lasers) {
    rawseedsLaserPose(l);  // throws for unsupported streams
    laser_files.push_back(findRawseedsStream(opt.dir, opt.dataset, l));
  }
  std::string gt_file;
  if (!opt.gt_output.empty()) gt_file = findRawseedsStream(opt.dir, opt.dataset, opt.gt_stream);

  // Priority on equal times: odometry first, so a scan sees the odometry of its instant.
  std::vector<std::unique_ptr<CsvStream>> streams;
  streams.push_back(std::make_unique<CsvStream>(odo_file, "ODOMETRY_XYT", false, opt.skip_bad_lines,
                                                odometryParser()));
  for (std::size_t i = 0; i < opt.lasers.size(); ++i)
    streams.push_back(std::make_unique<CsvStream>(laser_files[i], opt.lasers[i], false,
                                                  opt.skip_bad_lines, laserParser(opt.lasers[i])));

  RawseedsToRawlogReport rep;
  Progress progress(opt.progress);
  {
    ObsRawlogWriter out(opt.output);
    for (auto& s : streams) s->advance();
    for (;;) {
      CsvStream* best = nullptr;
      for (auto& s : streams)
        if (s->obs && (!best || s->t < best->t)) best = s.get();
      if (!best) break;
      out.write(*best->obs);
      if (best == streams[0].get())
        ++rep.odometry;
      else
        ++rep.scans;
      best->advance();
      if (progress.due()) {
        *progress.stream() << "rawseeds2rawlog: t = " << best->t.str();
        for (auto& s : streams)
          *progress.stream() << " | " << s->report.stream << " " << percent(s->progress()) << " ("
                             << s->report.lines << " lines)";
        *progress.stream() << std::endl;
      }
    }
    out.close();
  }
  for (auto& s : streams) rep.streams.push_back(s->report);

  if (!gt_file.empty()) {
    rep.streams.push_back(
        rawseedsGroundTruthToFile(gt_file, opt.gt_output, opt.skip_bad_lines, opt.progress));
    rep.gt_poses = rep.streams.back().records;
  }
  rep.wall_time_s = secondsSince(t0);
  return rep;
}

StreamReport rawseedsGroundTruthToFile(const std::string& csv, const std::string& output,
                                       bool skip_bad_lines, std::ostream* progress_os) {
  const std::string name = std::filesystem::path(csv).filename().string();
  const std::string stream =
      name.find("GT-extended") != std::string::npos ? "GT-extended" : "GROUNDTRUTH";
  CsvStream gt(csv, stream, true, skip_bad_lines, groundTruthParser());
  GroundTruthWriter w(output);
  Progress progress(progress_os);
  while (gt.advance()) {
    const auto& o = static_cast<const mrpt::obs::CObservationOdometry&>(*gt.obs);
    w.write(gt.t.seconds(), o.odometry);
    if (progress.due())
      *progress.stream() << "rawseeds2rawlog: " << stream << " " << percent(gt.progress()) << " ("
                         << gt.report.lines << " lines)" << std::endl;
  }
  w.flush();
  return gt.report;
}

RawlogToRawseedsReport rawlogToRawseeds(const RawlogToRawseedsOptions& opt) {
  RawlogReaderOptions ro;
  ro.laser_label = opt.laser_label;
  RawlogReader reader(opt.rawlog, ro);
  std::vector<GroundTruthPose> gt;
  if (!opt.gt_input.empty()) gt = readGroundTruth(opt.gt_input);

  std::error_code ec;
  std::filesystem::create_directories(opt.dir, ec);
  if (ec) throw InputError(opt.dir + ": cannot create the folder: " + ec.message());
  const std::string ext = opt.bz2 ? ".csv.bz2" : ".csv";
  const auto name = [&](const char* stream) {
    return (std::filesystem::path(opt.dir) / (opt.dataset + "-" + stream + ext)).string();
  };

  RawlogToRawseedsReport rep;
  TextOut laser(name("SICK_FRONT")), odo(name("ODOMETRY_XYT"));
  mrpt::poses::CPose2D pose;  // odometry integrated from the identity
  std::int16_t counter = 0;
  while (auto f = reader.next()) {
    ++rep.frames;
    if (!(f->timestamp >= 0))
      throw InputError(opt.rawlog + ": record " + std::to_string(reader.recordIndex()) +
                       ": timestamp " + std::to_string(f->timestamp) +
                       " is negative; Rawseeds times are seconds since 1970");
    const std::string t = Stamp::fromSeconds(f->timestamp).str();
    pose = pose + f->odometry;
    pose.normalizePhi();
    odo.line(t + "," + std::to_string(counter) + ",0,0," + fixed(pose.x()) + "," + fixed(pose.y()) +
             "," + fixed(pose.phi()));
    ++rep.odometry_lines;
    // The robot's counter is an int16 that wraps around.
    counter = static_cast<std::int16_t>(counter == INT16_MAX ? INT16_MIN : counter + 1);

    if (!f->scan) continue;
    const auto& s = *f->scan;
    const std::size_t n = s.getScanSize();
    if (n != kSickRays || std::abs(s.aperture - M_PI) > 1e-4) {
      throw InputError(opt.rawlog + ": record " + std::to_string(reader.recordIndex()) +
                       ": scan '" + s.sensorLabel + "' has " + std::to_string(n) + " rays over " +
                       fixed(s.aperture / kDeg, 2) +
                       " degrees; a Rawseeds SICK stream holds 181 rays over 180 degrees");
    }
    std::string l = t + ",181,0";
    l.reserve(l.size() + 181 * 10);
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = s.rightToLeft ? k : n - 1 - k;  // R1 is the rightmost ray
      const float r = s.getScanRange(i);
      l += ',';
      l += s.getScanRangeValidity(i) && r > 0 && r < kSickMaxRange ? fixed(r) : "0.000000";
    }
    laser.line(l);
    ++rep.scans;
  }
  laser.close();
  odo.close();
  rep.files = {name("SICK_FRONT"), name("ODOMETRY_XYT")};
  if (!opt.gt_input.empty()) {
    TextOut g(name("GROUNDTRUTH"));
    const std::string cov =
        "0.000001,0.000000,0.000000,0.000000,0.000001,0.000000,0.000000,"
        "0.000000,0.000001";
    for (const auto& p : gt) {
      if (!(p.t >= 0))
        throw InputError(opt.gt_input + ": negative timestamp " + std::to_string(p.t));
      g.line(Stamp::fromSeconds(p.t).str() + "," + fixed(p.pose.x()) + "," + fixed(p.pose.y()) +
             "," + fixed(mrpt::math::wrapToPi(p.pose.phi())) + "," + cov);
      ++rep.gt_lines;
    }
    g.close();
    rep.files.push_back(name("GROUNDTRUTH"));
  }
  return rep;
}

}  // namespace asf::io
