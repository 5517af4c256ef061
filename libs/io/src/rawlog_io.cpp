// Rawlog and ground-truth I/O (see rawlog_io.h). Everything binary goes through MRPT's
// serialization, so logs written here open in MRPT's tools and vice versa.
#include <asf/errors.h>
#include <asf/io/rawlog_io.h>
#include <mrpt/core/Clock.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CObservationRotatingScan.h>
#include <mrpt/obs/CObservationVelodyneScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <fstream>
#include <sstream>

#include <asf/io/rawlog_guard.h>

#include "checked_output.h"

namespace asf::io {

using mrpt::obs::CActionCollection;
using mrpt::obs::CActionRobotMovement2D;
using mrpt::obs::CObservation2DRangeScan;
using mrpt::obs::CObservationOdometry;
using mrpt::obs::CSensoryFrame;
using mrpt::poses::CPose2D;
using mrpt::poses::CPosePDFGaussian;

namespace {

bool hasTime(const mrpt::Clock::time_point& t) { return t != mrpt::Clock::time_point(); }

/// The classes whose points Map3d::observationPoints knows (2D scans are decided by label).
bool is3dClass(const mrpt::obs::CObservation& o) {
  return dynamic_cast<const mrpt::obs::CObservationPointCloud*>(&o) ||
         dynamic_cast<const mrpt::obs::CObservationVelodyneScan*>(&o) ||
         dynamic_cast<const mrpt::obs::CObservation3DRangeScan*>(&o) ||
         dynamic_cast<const mrpt::obs::CObservationRotatingScan*>(&o);
}

Eigen::Matrix3d toEigen(const mrpt::math::CMatrixDouble33& m) {
  Eigen::Matrix3d e;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) e(r, c) = m(r, c);
  return e;
}

/// MRPT's exception texts nest ("Exception while parsing typed object 'X'" around the cause)
/// and carry call traces. Keeps the cause and the objects it happened in:
/// "(EOF?) Cannot read ... (in CSensoryFrame > CObservation2DRangeScan)".
std::string causeOf(const std::string& what) {
  const std::string kMsg = "Message:", kParsing = "Exception while parsing typed object '";
  std::istringstream is(what);
  std::string line, cause, objects;
  while (std::getline(is, line)) {
    const auto m = line.find(kMsg);
    if (m == std::string::npos) continue;
    std::string text = line.substr(m + kMsg.size());
    text.erase(0, text.find_first_not_of(' '));
    if (text.compare(0, kParsing.size(), kParsing) == 0) {
      const auto end = text.find('\'', kParsing.size());
      const std::string cls = text.substr(kParsing.size(), end - kParsing.size());
      if (end != std::string::npos && !cls.empty() && cls.find(' ') == std::string::npos)
        objects += (objects.empty() ? "" : " > ") + cls;
    } else if (!text.empty()) {
      cause = text;  // the innermost message comes last
    }
  }
  if (cause.empty()) {
    std::istringstream first(what);
    std::getline(first, cause);
  }
  return objects.empty() ? cause : cause + " (in " + objects + ")";
}

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

std::string mrptExceptionCause(const std::string& what) { return causeOf(what); }

// ---------------------------------------------------------------- reader

struct RawlogReader::Impl {
  std::string path;
  RawlogReaderOptions opt;
  mrpt::io::CFileGZInputStream file;
  /// What MRPT reads through: refuses a scan whose damaged ray count would make MRPT
  /// allocate gigabytes (or crash where it cannot) before asf sees the record.
  std::unique_ptr<RawlogGuard> in;
  std::unique_ptr<mrpt::serialization::CArchive> ar;
  std::vector<GroundTruthPose> gt;
  bool ended = false;
  std::size_t records = 0;           // records read so far
  std::optional<std::string> label;  // chosen laser label (set on the first scan if not given)
  std::vector<std::string> labels_seen;
  std::size_t skipped = 0;
  std::size_t unused_3d = 0;
  std::size_t frames = 0;
  double last_t = 0;

  // Action/sensory-frame layout: the movement(s) since the last sensory frame.
  bool have_action = false;
  CPosePDFGaussian action;
  mrpt::Clock::time_point action_t;

  // Observation-only layout: odometry readings not yet assigned to a scan, and the odometry
  // pose of the last emitted scan.
  std::deque<std::pair<mrpt::Clock::time_point, CPose2D>> pending_odo;
  std::optional<CPose2D> odo_now, odo_prev_scan;
  // 3D observations waiting for the next frame (observation-only logs), and the 3D sensor
  // whose observations make the frames (scan_from_3d).
  std::vector<std::shared_ptr<const mrpt::obs::CObservation>> pending_3d;
  std::optional<std::string> label_3d;

  /// Whether `o` is the 3D sensor the frames come from (choosing it if none is yet).
  bool chosen3d(const mrpt::obs::CObservation& o) {
    if (!label_3d) label_3d = o.sensorLabel;
    return o.sensorLabel == *label_3d;
  }

  std::shared_ptr<CObservation2DRangeScan> slice(const mrpt::obs::CObservation& o) {
    std::string why;
    auto scan = mapping::horizontalSlice(o, opt.slice, &why);
    if (!scan) fail(o.sensorLabel + ": no 2D scan from it (scan_from_3d): " + why);
    return scan;
  }

  /// Whether the stream has no byte left (it is read no further: the reader ends).
  bool atEnd() {
    char c;
    try {
      return in->Read(&c, 1) == 0;
    } catch (const std::exception&) {
      return true;
    }
  }

  [[noreturn]] void fail(std::string why) {
    ended = true;
    for (char& c : why)  // damaged bytes end up in MRPT's messages (e.g. a class name)
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
    throw InputError(path + ": record " + std::to_string(records) + ": " + why);
  }

  /// Whether `scan` is the chosen laser (choosing it if none is yet); counts the others.
  bool chosen(const CObservation2DRangeScan& scan, bool count_skipped = true) {
    if (std::find(labels_seen.begin(), labels_seen.end(), scan.sensorLabel) == labels_seen.end())
      labels_seen.push_back(scan.sensorLabel);
    if (!label) label = scan.sensorLabel;
    if (scan.sensorLabel == *label) return true;
    if (count_skipped) ++skipped;
    return false;
  }

  SensorFrame finish(SensorFrame f) {
    if (!gt.empty())
      f.ground_truth = interpolateGroundTruth(gt, f.timestamp, opt.ground_truth_max_gap);
    last_t = f.timestamp;
    ++frames;
    return f;
  }

  void addAction(const CActionCollection& acts) {
    const auto mov = acts.getBestMovementEstimation();
    if (!mov || !mov->poseChange) return;  // e.g. only 3D movements: no 2D odometry
    CPosePDFGaussian g;
    if (auto pg = std::dynamic_pointer_cast<CPosePDFGaussian>(mov->poseChange.get_ptr())) {
      g = *pg;
    } else {
      // Sample-based PDF (MRPT's Thrun model, redrawn at random on load): use the raw
      // reading with our Gaussian model instead, so replays are deterministic.
      g.mean = mov->rawOdometryIncrementReading;
      const Eigen::Matrix3d c = opt.odometry_model.covariance(g.mean);
      for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k) g.cov(r, k) = c(r, k);
    }
    if (have_action) {
      action += g;  // two actions in a row: compose them (mean and first-order covariance)
    } else {
      action = g;
      have_action = true;
    }
    if (hasTime(mov->timestamp)) action_t = mov->timestamp;
  }

  SensorFrame frameFromSensoryFrame(const CSensoryFrame& sf) {
    SensorFrame f;
    for (const auto& o : sf) {
      auto scan = std::dynamic_pointer_cast<CObservation2DRangeScan>(o);
      if (scan && !opt.scan_from_3d && chosen(*scan, /*count_skipped=*/!opt.observations3d)) {
        if (f.scan)
          ++skipped;  // a second scan of the same laser in one step
        else
          f.scan = scan;
        continue;
      }
      if (!scan && !is3dClass(*o)) continue;
      if (opt.scan_from_3d && !scan && !f.scan && chosen3d(*o)) f.scan = slice(*o);
      if (opt.observations3d)
        f.observations3d.push_back(o);
      else if (scan && opt.scan_from_3d)
        ++skipped;
    }
    if (have_action) {
      f.odometry = action.mean;  // as stored: a replay gives back exactly what was written
      f.odometry_cov = toEigen(action.cov);
    } else if (frames > 0) {
      // A later step without a movement: no motion known; say so with the model's spread.
      f.odometry_cov = opt.odometry_model.covariance(CPose2D());
    }
    mrpt::Clock::time_point t;
    if (f.scan && hasTime(f.scan->timestamp))
      t = f.scan->timestamp;
    else if (have_action && hasTime(action_t))
      t = action_t;
    else
      for (const auto& o : sf)
        if (hasTime(o->timestamp)) {
          t = o->timestamp;
          break;
        }
    f.timestamp = hasTime(t) ? mrpt::Clock::toDouble(t) : last_t;
    have_action = false;
    action_t = mrpt::Clock::time_point();
    return f;
  }

  SensorFrame frameFromScan(const CObservation2DRangeScan::Ptr& scan) {
    // The odometry pose of this scan: the last reading at or before its time.
    while (!pending_odo.empty() &&
           (!hasTime(scan->timestamp) || !hasTime(pending_odo.front().first) ||
            pending_odo.front().first <= scan->timestamp)) {
      odo_now = pending_odo.front().second;
      pending_odo.pop_front();
    }
    SensorFrame f;
    f.scan = scan;
    f.observations3d = std::move(pending_3d);
    pending_3d.clear();
    f.timestamp = hasTime(scan->timestamp) ? mrpt::Clock::toDouble(scan->timestamp) : last_t;
    if (frames > 0) {
      if (odo_now && odo_prev_scan) f.odometry = *odo_now - *odo_prev_scan;
      f.odometry.normalizePhi();
      f.odometry_cov = opt.odometry_model.covariance(f.odometry);
    }
    odo_prev_scan = odo_now;
    return f;
  }
};

RawlogReader::RawlogReader(const std::string& path, RawlogReaderOptions options)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  impl_->opt = std::move(options);
  bool ok = false;
  try {
    ok = impl_->file.open(path);
  } catch (const std::exception&) {
    // MRPT throws for a missing file (std::filesystem) instead of returning false.
  }
  if (!ok) throw InputError(path + ": cannot open the rawlog (missing or unreadable)");
  impl_->in = std::make_unique<RawlogGuard>(impl_->file);
  impl_->ar = mrpt::serialization::archiveUniquePtrFrom(*impl_->in);
  if (!impl_->opt.laser_label.empty()) impl_->label = impl_->opt.laser_label;
  if (!impl_->opt.label_3d.empty()) impl_->label_3d = impl_->opt.label_3d;
  if (!impl_->opt.ground_truth_file.empty())
    impl_->gt = readGroundTruth(impl_->opt.ground_truth_file);
}

RawlogReader::~RawlogReader() = default;

std::optional<SensorFrame> RawlogReader::next() {
  Impl& m = *impl_;
  while (!m.ended) {
    mrpt::serialization::CSerializable::Ptr obj;
    const std::uint64_t record_start = m.in->getPosition();
    try {
      obj = m.ar->ReadObject();
    } catch (const mrpt::serialization::CExceptionEOF&) {
      // MRPT says EOF wherever the bytes ran out: a clean end only between records.
      if (m.in->getPosition() != record_start)
        m.fail("the file ends inside this record (cut at byte " +
               std::to_string(m.in->getPosition()) + "; a copy or a write that did not finish?)");
      m.ended = true;
      break;
    } catch (const RawlogRefusal& e) {
      m.fail(e.what());
    } catch (const std::bad_alloc&) {
      m.fail("corrupt record (a length field asks for more memory than available)");
    } catch (const std::exception& e) {
      if (!m.in->refusal().empty()) m.fail(m.in->refusal());  // MRPT wrapped the guard's
      // Inside a nested object (a scan in a sensory frame) MRPT's EOF arrives wrapped in
      // another exception: the bytes ran out when nothing is left to read.
      if (m.atEnd())
        m.fail("the file ends inside this record (cut at byte " +
               std::to_string(m.in->getPosition()) + "; a copy or a write that did not finish?)");
      m.fail(mrptExceptionCause(e.what()));
    }
    // MRPT reads an object of another class (or a null one) in a frame as a null pointer.
    if (auto sf = std::dynamic_pointer_cast<CSensoryFrame>(obj);
        sf && std::any_of(sf->begin(), sf->end(), [](const auto& o) { return !o; }))
      m.fail("a sensory frame holds a null object or one that is not an observation");
    ++m.records;
    if (!obj) continue;  // a serialized null pointer
    if (auto acts = std::dynamic_pointer_cast<CActionCollection>(obj)) {
      m.addAction(*acts);
    } else if (auto sf = std::dynamic_pointer_cast<CSensoryFrame>(obj)) {
      return m.finish(m.frameFromSensoryFrame(*sf));
    } else if (auto odo = std::dynamic_pointer_cast<CObservationOdometry>(obj)) {
      m.pending_odo.emplace_back(odo->timestamp, odo->odometry);
    } else if (auto scan = std::dynamic_pointer_cast<CObservation2DRangeScan>(obj)) {
      if (!m.opt.scan_from_3d && m.chosen(*scan, !m.opt.observations3d))
        return m.finish(m.frameFromScan(scan));
      if (m.opt.observations3d)
        m.pending_3d.push_back(scan);
      else if (m.opt.scan_from_3d)
        ++m.skipped;
    } else if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj); o && is3dClass(*o)) {
      if (!m.opt.observations3d && !m.opt.scan_from_3d) ++m.unused_3d;
      if (m.opt.observations3d) m.pending_3d.push_back(o);
      if (m.opt.scan_from_3d && m.chosen3d(*o)) return m.finish(m.frameFromScan(m.slice(*o)));
    }
    // Anything else (other sensors, metadata) is not used.
  }
  return std::nullopt;
}

std::size_t RawlogReader::recordIndex() const {
  return impl_->records == 0 ? 0 : impl_->records - 1;
}

std::vector<std::string> RawlogReader::laserLabels() const { return impl_->labels_seen; }

std::size_t RawlogReader::skippedScans() const { return impl_->skipped; }

std::size_t RawlogReader::unused3dObservations() const { return impl_->unused_3d; }

// ---------------------------------------------------------------- writer

struct RawlogWriter::Impl {
  std::string path;
  bool gz = false;
  std::size_t flush_every = 50;
  std::size_t written = 0;
  std::unique_ptr<CheckedFileOutput> out;  // reports every lost write, MRPT's streams do not

  void open(bool append) { out = std::make_unique<CheckedFileOutput>(path, gz, path, append); }

  void close() {
    if (!out) return;
    auto o = std::move(out);
    o->close();  // throws when the last buffer or the close failed
  }
};

RawlogWriter::RawlogWriter(const std::string& path, std::size_t flush_every)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  impl_->gz = endsWith(path, ".gz");
  impl_->flush_every = flush_every;
  try {
    impl_->open(false);
  } catch (const InputError&) {
    throw InputError(path + ": cannot create the rawlog");
  }
}

RawlogWriter::~RawlogWriter() {
  try {
    impl_->close();
  } catch (...) {
  }
}

void RawlogWriter::write(const SensorFrame& frame) {
  const auto t = mrpt::Clock::fromDouble(frame.timestamp);

  CActionRobotMovement2D mov;
  // emScan2DMatching, not emOdometry: for emOdometry MRPT serializes only the raw reading and
  // its motion-model parameters and recomputes the covariance on load, losing ours.
  mov.estimationMethod = CActionRobotMovement2D::emScan2DMatching;
  mov.rawOdometryIncrementReading = frame.odometry;
  mov.hasEncodersInfo = false;
  mrpt::math::CMatrixDouble33 cov;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) cov(r, c) = frame.odometry_cov(r, c);
  mov.poseChange = CPosePDFGaussian::Create(frame.odometry, cov);
  mov.timestamp = t;
  CActionCollection acts;
  acts.insert(mov);

  CSensoryFrame sf;
  if (frame.scan) {
    // The reader takes the frame time from the scan: stamp it with the frame's time so the
    // replay gives back exactly what was written.
    auto scan = std::make_shared<CObservation2DRangeScan>(*frame.scan);
    scan->timestamp = t;
    sf.insert(scan);
  }
  // MRPT's serialization is not const: the observations are copied (shared, not deep) into
  // the frame as they are.
  for (const auto& o : frame.observations3d)
    if (o) sf.insert(std::const_pointer_cast<mrpt::obs::CObservation>(o));
  // Closed, or closed by a failed flush: say so rather than write to nothing.
  if (!impl_->out) throw Error(impl_->path + ": not open for writing (closed, or a write failed)");
  try {
    auto ar = mrpt::serialization::archiveFrom(*impl_->out);
    ar << acts << sf;
  } catch (const std::exception& e) {
    throw Error(impl_->path + ": write failed: " + mrptExceptionCause(e.what()));
  }
  ++impl_->written;
  if (impl_->flush_every > 0 && impl_->written % impl_->flush_every == 0) flush();
}

void RawlogWriter::flush() {
  // Close and reopen for appending: for .gz this ends the gzip member, so what was written
  // reads back after a crash (gzip readers, MRPT's too, read the members as one stream).
  impl_->close();
  try {
    impl_->open(true);
  } catch (const InputError&) {
    throw Error(impl_->path + ": cannot reopen the rawlog for appending");
  }
}

void RawlogWriter::close() { impl_->close(); }

std::size_t RawlogWriter::framesWritten() const { return impl_->written; }

}  // namespace asf::io
