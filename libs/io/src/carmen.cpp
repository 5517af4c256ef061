#include <asf/atomic_file.h>
#include <asf/errors.h>
#include <asf/text.h>
#include <asf/io/carmen.h>
#include <asf/io/text_io.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <ostream>
#include <random>
#include <sstream>

namespace asf::io {

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kDefaultMaxRange = 80.0;  // SICK LMS in cm mode; "no echo" reads 81.83

struct LaserLine {
  Stamp t;
  std::vector<double> ranges;
  double aperture = M_PI, max_range = kDefaultMaxRange;
  mrpt::poses::CPose3D sensor_pose;
  mrpt::poses::CPose2D robot;     ///< logged robot pose (ground truth in corrected logs)
  mrpt::poses::CPose2D odometry;  ///< the robot's odometry pose at the scan
};

using Tokens = std::vector<std::string_view>;

std::optional<double> number(const Tokens& tok, std::size_t i, const char* what, std::string& why) {
  const auto v = parseDouble(tok[i]);
  if (!v) why = std::string(what) + " '" + std::string(tok[i]) + "' is not a number";
  return v;
}

std::optional<mrpt::poses::CPose2D> pose(const Tokens& tok, std::size_t i, const char* what,
                                         std::string& why) {
  const auto x = number(tok, i, what, why);
  const auto y = x ? number(tok, i + 1, what, why) : std::nullopt;
  const auto th = y ? number(tok, i + 2, what, why) : std::nullopt;
  if (!th) return std::nullopt;
  return mrpt::poses::CPose2D(*x, *y, *th);
}

bool readRanges(const Tokens& tok, std::size_t first, std::size_t n, std::vector<double>& out,
                std::string& why) {
  out.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto r = parseNumber(tok[first + i]);
    if (!r) {
      why = "range " + std::to_string(i + 1) + " '" + std::string(tok[first + i]) +
            "' is not a number";
      return false;
    }
    out[i] = *r;
  }
  return true;
}

std::optional<Stamp> stamp(const Tokens& tok, std::size_t i, std::string& why) {
  const auto t = parseStamp(tok[i]);
  if (!t) why = "ipc_timestamp '" + std::string(tok[i]) + "' is not a time in seconds";
  return t;
}

struct FlaserParams {
  double offset = 0;                 // robot_frontlaser_offset [m]
  double max_range = 0;              // robot_front_laser_max [m]; 0: unset
  double fov_deg = 0;                // laser_front_laser_fov; 0: unset
  double res_deg = 0;                // laser_front_laser_resolution; 0: unset
  std::string fov_where, res_where;  // file:line of the PARAM lines
  bool checked = false;              // fov and resolution checked against a scan's ray count
};

/// laser_front_laser_fov in degrees (CARMEN's unit); a value of at most 2 pi is implausible
/// in degrees (a laser of 3 degrees?) and read as radians; 0 (unset) for nonsense.
double fovDegrees(double v, const std::string& where, std::vector<std::string>& warnings) {
  if (v > 0 && v <= 2 * M_PI + 1e-3) {
    warnings.push_back(where + ": PARAM laser_front_laser_fov " + formatSignificant(v, 6) +
                       " is implausible in degrees (CARMEN's unit): read as radians, " +
                       formatSignificant(v / kDeg, 6) + " deg");
    return v / kDeg;
  }
  if (v > 0 && v <= 360) return v;
  warnings.push_back(where + ": PARAM laser_front_laser_fov " + formatSignificant(v, 6) +
                     " is not a field of view in (0, 360] deg: ignored");
  return 0;
}

/// Checks the resolution (degrees; the aperture is rays times it, MRPT's rule) against the
/// first scan's ray count, and against the fov when both are given.
void checkLaserParams(FlaserParams& p, std::size_t rays, std::vector<std::string>& warnings) {
  p.checked = true;
  const double n = static_cast<double>(rays);
  if (p.res_deg > 0 && p.res_deg * n < 10 && p.res_deg / kDeg * n <= 360 + 1e-6) {
    warnings.push_back(p.res_where + ": PARAM laser_front_laser_resolution " +
                       formatSignificant(p.res_deg, 6) + " deg would put " + std::to_string(rays) +
                       " rays in " + formatSignificant(p.res_deg * n, 6) +
                       " deg: read as radians, " + formatSignificant(p.res_deg / kDeg, 6) + " deg");
    p.res_deg /= kDeg;
  } else if (p.res_deg * n > 360 + 1e-6) {
    warnings.push_back(p.res_where + ": PARAM laser_front_laser_resolution " +
                       formatSignificant(p.res_deg, 6) + " deg puts " + std::to_string(rays) +
                       " rays in more than 360 deg: ignored");
    p.res_deg = 0;
  }
  if (p.fov_deg > 0 && p.res_deg > 0 &&
      std::abs(p.fov_deg - p.res_deg * n) > std::max(1.0, 0.02 * p.fov_deg))
    warnings.push_back(
        p.fov_where + ": PARAM laser_front_laser_fov (" + formatSignificant(p.fov_deg, 6) +
        " deg) and laser_front_laser_resolution (" + formatSignificant(p.res_deg, 6) + " deg x " +
        std::to_string(rays) + " rays = " + formatSignificant(p.res_deg * n, 6) +
        " deg) disagree: the fov is used");
}

std::optional<LaserLine> parseFlaser(const Tokens& tok, const FlaserParams& p,
                                     const CarmenToRawlogOptions& opt, bool log_stamps,
                                     std::string& why) {
  const auto n = tok.size() > 1 ? parseInt(tok[1]) : std::nullopt;
  if (!n || *n < 2 || *n > 100000) {
    why = "FLASER: number of readings is not an integer >= 2";
    return std::nullopt;
  }
  const auto N = static_cast<std::size_t>(*n);
  if (tok.size() != N + 11) {
    why = "FLASER with " + std::to_string(N) + " readings has " + std::to_string(N + 11) +
          " fields (n, ranges, x y theta, odom x y theta, ipc_timestamp, host, "
          "logger_timestamp), got " +
          std::to_string(tok.size());
    return std::nullopt;
  }
  LaserLine l;
  if (!readRanges(tok, 2, N, l.ranges, why)) return std::nullopt;
  const auto laser = pose(tok, 2 + N, "laser pose", why);
  const auto odo = laser ? pose(tok, 5 + N, "odometry pose", why) : std::nullopt;
  if (!odo) return std::nullopt;
  if (log_stamps) {
    const auto t = stamp(tok, 8 + N, why);
    if (!t) return std::nullopt;
    l.t = *t;
  }
  // x y theta is the laser's pose; the robot centre is `offset` behind it.
  l.robot = *laser + mrpt::poses::CPose2D(-p.offset, 0, 0);
  l.odometry = *odo;
  l.sensor_pose = mrpt::poses::CPose3D(p.offset, 0, 0, 0, 0, 0);
  const double fov = opt.fov_deg > 0 ? opt.fov_deg
                     : p.fov_deg > 0 ? p.fov_deg
                     : p.res_deg > 0 ? p.res_deg * static_cast<double>(N)
                                     : 180.0;
  l.aperture = fov * kDeg;
  l.max_range = opt.max_range > 0 ? opt.max_range
                : p.max_range > 0 ? p.max_range
                                  : kDefaultMaxRange;
  return l;
}

std::optional<LaserLine> parseRobotLaser(const Tokens& tok, const CarmenToRawlogOptions& opt,
                                         bool log_stamps, std::string& why) {
  const auto n = tok.size() > 9 ? parseInt(tok[8]) : std::nullopt;
  if (!n || *n < 2 || *n > 100000 || tok.size() < static_cast<std::size_t>(*n) + 10) {
    why = "ROBOTLASER1: number of readings (field 9) is not an integer >= 2 followed by them";
    return std::nullopt;
  }
  const auto N = static_cast<std::size_t>(*n);
  const auto m = parseInt(tok[9 + N]);
  if (!m || *m < 0 || *m > 100000) {
    why = "ROBOTLASER1: number of remissions '" + std::string(tok[9 + N]) +
          "' is not an integer >= 0";
    return std::nullopt;
  }
  const auto M = static_cast<std::size_t>(*m);
  if (tok.size() != N + M + 24) {
    why = "ROBOTLASER1 with " + std::to_string(N) + " readings and " + std::to_string(M) +
          " remissions has " + std::to_string(N + M + 24) + " fields, got " +
          std::to_string(tok.size());
    return std::nullopt;
  }
  LaserLine l;
  const auto start = number(tok, 2, "start_angle", why);
  const auto fov = start ? number(tok, 3, "field_of_view", why) : std::nullopt;
  const auto maxr = fov ? number(tok, 5, "maximum_range", why) : std::nullopt;
  if (!maxr || !readRanges(tok, 9, N, l.ranges, why)) return std::nullopt;
  const std::size_t k = 10 + N + M;
  const auto laser = pose(tok, k, "laser pose", why);
  const auto robot = laser ? pose(tok, k + 3, "robot pose", why) : std::nullopt;
  if (!robot) return std::nullopt;
  if (log_stamps) {
    const auto t = stamp(tok, k + 11, why);
    if (!t) return std::nullopt;
    l.t = *t;
  }
  if (!(*fov > 0)) {
    why = "field_of_view " + std::string(tok[3]) + " is not positive";
    return std::nullopt;
  }
  l.robot = *robot;
  l.odometry = *robot;
  l.aperture = *fov;
  l.max_range = opt.max_range > 0 ? opt.max_range : *maxr > 0 ? *maxr : kDefaultMaxRange;
  // Laser on the robot from the two logged poses; MRPT's fan is centred on the sensor's x
  // axis, so a fan not starting at -fov/2 turns the sensor.
  const mrpt::poses::CPose2D rel = *laser - *robot;
  l.sensor_pose = mrpt::poses::CPose3D(rel.x(), rel.y(), 0, rel.phi() + *start + *fov / 2, 0, 0);
  return l;
}

/// The laser stamps of a log (first pass): the laser message is the first FLASER or
/// ROBOTLASER1; every message ends with "ipc_timestamp ipc_hostname logger_timestamp".
struct StampSurvey {
  std::size_t scans = 0, bad = 0, not_increasing = 0, increasing = 0;
  std::size_t first_bad_line = 0;
  std::string first_bad;
  double median_step = 0;  ///< of the increasing steps [s]
};

StampSurvey surveyStamps(const std::string& path) {
  StampSurvey s;
  LineReader in(path);
  std::string line, kind;
  std::optional<Stamp> prev;
  std::vector<double> steps;
  while (in.next(line)) {
    const Tokens tok = splitWhitespace(line);
    if (tok.size() < 4 || (tok[0] != "FLASER" && tok[0] != "ROBOTLASER1")) continue;
    if (kind.empty()) kind = std::string(tok[0]);
    if (tok[0] != kind) continue;
    ++s.scans;
    const auto t = parseStamp(tok[tok.size() - 3]);
    if (!t) {
      if (s.bad++ == 0) {
        s.first_bad_line = in.lineNumber();
        s.first_bad = std::string(tok[tok.size() - 3]);
      }
      continue;
    }
    if (prev && *prev < *t) {
      ++s.increasing;
      steps.push_back(t->seconds() - prev->seconds());
    } else if (prev) {
      ++s.not_increasing;
    }
    prev = t;
  }
  if (!steps.empty()) {
    std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
    s.median_step = steps[steps.size() / 2];
  }
  return s;
}

/// One conversion: the state carried from line to line.
class Converter {
 public:
  using Mode = CarmenToRawlogOptions::Odometry;

  explicit Converter(const CarmenToRawlogOptions& opt)
      : opt_(opt), in_(opt.input), out_(opt.output), rng_(opt.seed), progress_(opt.progress) {
    if (!opt.gt_output.empty()) {
      // Put in place after the rawlog: a failed conversion keeps the ground truth there was.
      gt_target_ = std::make_unique<AtomicOutput>(opt.gt_output, "ground truth");
      gt_ = std::make_unique<GroundTruthWriter>(gt_target_->file());
    }
    chooseTimestamps();
  }

  CarmenToRawlogReport run() {
    std::string line;
    while (in_.next(line)) {
      ++rep_.lines;
      if (progress_.due())
        *progress_.stream() << "carmen2rawlog: " << rep_.lines << " lines, " << rep_.scans
                            << " scans" << std::endl;
      const Tokens tok = splitWhitespace(line);
      if (tok.empty() || tok[0].front() == '#') continue;
      const std::string msg(tok[0]);
      if (msg == "PARAM")
        param(tok);
      else if (msg == "ODOM")
        odom(tok);
      else if (msg == "FLASER" || msg == "ROBOTLASER1")
        laser(msg, tok);
      else
        ++rep_.ignored[msg];
    }
    if (rep_.scans == 0)
      throw InputError(opt_.input + ": no FLASER or ROBOTLASER1 line: not a CARMEN laser log?");
    out_.close();
    if (gt_) {
      gt_.reset();  // every line was flushed and checked
      gt_target_->commit();
    }
    return rep_;
  }

 private:
  std::string where() const { return in_.path() + ":" + std::to_string(in_.lineNumber()); }

  void bad(const std::string& why) {
    if (!opt_.skip_bad_lines) throw InputError(where() + ": " + why);
    if (rep_.bad_lines++ == 0) {
      rep_.first_bad_line = in_.lineNumber();
      rep_.first_bad_reason = why;
    }
  }

  /// Auto and Order survey the log's laser stamps first (a second read of the file).
  void chooseTimestamps() {
    using T = CarmenToRawlogOptions::Timestamps;
    if (opt_.timestamps == T::Log) return;
    const StampSurvey sv = surveyStamps(opt_.input);
    rep_.stamps_bad = sv.bad;
    rep_.stamps_not_increasing = sv.not_increasing;
    const std::size_t steps = sv.increasing + sv.not_increasing;
    by_order_ = opt_.timestamps == T::Order || sv.bad > 0 || sv.not_increasing * 10 > steps;
    rep_.stamped_by_order = by_order_;
    if (!by_order_) return;
    const bool steady = sv.increasing > 0 && 2 * sv.increasing >= steps;
    period_ = opt_.scan_period_s > 0 ? opt_.scan_period_s : steady ? sv.median_step : 1.0;
    rep_.scan_period_s = period_;
    if (opt_.timestamps == T::Order) return;
    std::string why = opt_.input + ": of " + std::to_string(sv.scans) + " laser timestamps, ";
    if (sv.bad)
      why += std::to_string(sv.bad) + " are not a time in seconds (first: line " +
             std::to_string(sv.first_bad_line) + ", '" + sv.first_bad + "'), ";
    why += std::to_string(sv.not_increasing) + " are not after the one before: scans stamped " +
           "from the log's order, " + formatSignificant(period_, 6) + " s apart" +
           (opt_.scan_period_s > 0 ? ""
            : steady               ? " (the median step)"
                                   : " (no steady step)");
    rep_.warnings.push_back(why);
  }

  void param(const Tokens& tok) {
    if (tok.size() < 3) return bad("PARAM without a name and a value");
    double* target = tok[1] == "robot_frontlaser_offset"        ? &params_.offset
                     : tok[1] == "robot_front_laser_max"        ? &params_.max_range
                     : tok[1] == "laser_front_laser_fov"        ? &params_.fov_deg
                     : tok[1] == "laser_front_laser_resolution" ? &params_.res_deg
                                                                : nullptr;
    if (!target) return;
    const auto v = parseDouble(tok[2]);
    if (!v)
      return bad("PARAM " + std::string(tok[1]) + ": value '" + std::string(tok[2]) +
                 "' is not a number");
    *target = *v;
    if (target == &params_.fov_deg) {
      params_.fov_where = where();
      params_.fov_deg = fovDegrees(*v, where(), rep_.warnings);
    }
    if (target == &params_.res_deg) params_.res_where = where();
    if (target == &params_.fov_deg || target == &params_.res_deg) params_.checked = false;
  }

  void odom(const Tokens& tok) {
    if (opt_.odometry != Mode::OdomLines) {
      ++rep_.ignored["ODOM"];
      return;
    }
    if (tok.size() != 10)
      return bad(
          "ODOM has 10 fields (x y theta tv rv accel ipc_timestamp host "
          "logger_timestamp), got " +
          std::to_string(tok.size()));
    std::string why;
    const auto p = pose(tok, 1, "odometry pose", why);
    std::optional<Stamp> t;
    if (p && by_order_)  // after the record before it, in log order
      t = last_out_ ? last_out_->plusMicroseconds(1) : Stamp::fromSeconds(period_ / 2);
    else if (p)
      t = stamp(tok, 7, why);
    if (!t) return bad(why);
    if (last_out_ && *t < *last_out_) {  // e.g. the re-anchoring lines of corrected logs
      ++rep_.odom_dropped;
      return;
    }
    mrpt::obs::CObservationOdometry o;
    o.sensorLabel = "ODOMETRY";
    o.timestamp = t->toClock();
    o.odometry = *p;
    out_.write(o);
    ++rep_.odometry;
    last_out_ = *t;
  }

  void laser(const std::string& msg, const Tokens& tok) {
    // A log with both kinds carries the same scans twice: keep the first kind seen.
    if (rep_.laser_message.empty()) rep_.laser_message = msg;
    if (msg != rep_.laser_message) {
      ++rep_.ignored[msg];
      return;
    }
    if (msg == "FLASER" && !params_.checked && tok.size() > 1) {
      const auto n = parseInt(tok[1]);
      if (n && *n >= 2 && *n <= 100000)
        checkLaserParams(params_, static_cast<std::size_t>(*n), rep_.warnings);
    }
    std::string why;
    std::optional<LaserLine> l = msg == "FLASER" ? parseFlaser(tok, params_, opt_, !by_order_, why)
                                                 : parseRobotLaser(tok, opt_, !by_order_, why);
    if (!l) return bad(why);
    // Keep log order; a scan stamped before the previous record is moved just after it.
    Stamp t = by_order_ ? Stamp::fromSeconds(static_cast<double>(rep_.scans + 1) * period_) : l->t;
    const Stamp wanted = t;
    if (last_scan_ && t <= *last_scan_) t = last_scan_->plusMicroseconds(1);
    if (last_out_ && t < *last_out_) t = *last_out_;
    if (!(t == wanted)) ++rep_.raised_timestamps;
    if (opt_.odometry != Mode::OdomLines) writeOdometry(*l, t);
    prev_robot_ = l->robot;
    writeScan(msg, *l, t);
    if (gt_) {
      gt_->write(t.seconds(), l->robot);
      ++rep_.gt_poses;
    }
    last_scan_ = t;
    last_out_ = t;
  }

  void writeOdometry(const LaserLine& l, const Stamp& t) {
    mrpt::poses::CPose2D odo = l.odometry;
    if (opt_.odometry == Mode::Synthetic) {
      if (!prev_robot_) {
        synth_ = l.robot;
      } else {
        const mrpt::poses::CPose2D d = l.robot - *prev_robot_;
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(opt_.model.covariance(d));
        Eigen::Vector3d z(n01_(rng_), n01_(rng_), n01_(rng_));
        const Eigen::Vector3d e =
            es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).cwiseSqrt().cwiseProduct(z);
        synth_ = synth_ + mrpt::poses::CPose2D(d.x() + e[0], d.y() + e[1], d.phi() + e[2]);
        synth_.normalizePhi();
      }
      odo = synth_;
    }
    mrpt::obs::CObservationOdometry o;
    o.sensorLabel = "ODOMETRY";
    o.timestamp = t.toClock();
    o.odometry = odo;
    out_.write(o);
    ++rep_.odometry;
  }

  void writeScan(const std::string& msg, const LaserLine& l, const Stamp& t) {
    mrpt::obs::CObservation2DRangeScan scan;
    scan.sensorLabel = msg;
    scan.timestamp = t.toClock();
    scan.aperture = static_cast<float>(l.aperture);
    scan.rightToLeft = true;
    scan.maxRange = static_cast<float>(l.max_range);
    scan.sensorPose = l.sensor_pose;
    scan.resizeScan(l.ranges.size());
    for (std::size_t i = 0; i < l.ranges.size(); ++i) {
      const double r = l.ranges[i];
      const bool valid = std::isfinite(r) && r > 0 && r < l.max_range;
      scan.setScanRange(i, static_cast<float>(valid ? r : l.max_range));
      scan.setScanRangeValidity(i, valid);
    }
    out_.write(scan);
    if (rep_.scans++ == 0) {
      rep_.rays = l.ranges.size();
      rep_.aperture_deg = l.aperture / kDeg;
    }
  }

  const CarmenToRawlogOptions& opt_;
  LineReader in_;
  ObsRawlogWriter out_;
  std::unique_ptr<AtomicOutput> gt_target_;
  std::unique_ptr<GroundTruthWriter> gt_;
  CarmenToRawlogReport rep_;
  FlaserParams params_;
  bool by_order_ = false;
  double period_ = 1;
  std::mt19937_64 rng_;
  std::normal_distribution<double> n01_{0.0, 1.0};
  std::optional<Stamp> last_out_, last_scan_;
  std::optional<mrpt::poses::CPose2D> prev_robot_;
  mrpt::poses::CPose2D synth_;
  Progress progress_;
};

}  // namespace

CarmenToRawlogReport carmenToRawlog(const CarmenToRawlogOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  CarmenToRawlogReport rep = Converter(opt).run();
  rep.wall_time_s = secondsSince(t0);
  return rep;
}

}  // namespace asf::io
