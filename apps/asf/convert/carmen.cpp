#include <asf/errors.h>
#include <asf_convert/carmen.h>
#include <asf_convert/text_io.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <Eigen/Eigenvalues>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <ostream>
#include <random>

namespace asf::convert {

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

std::optional<double> number(const Tokens& tok, std::size_t i, const char* what,
                             std::string& why) {
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
  double offset = 0;       // robot_frontlaser_offset [m]
  double max_range = 0;    // robot_front_laser_max [m]; 0: unset
  double fov_deg = 0;      // laser_front_laser_fov; 0: unset
  double res_deg = 0;      // laser_front_laser_resolution; 0: unset
};

std::optional<LaserLine> parseFlaser(const Tokens& tok, const FlaserParams& p,
                                     const CarmenToRawlogOptions& opt, std::string& why) {
  const auto n = tok.size() > 1 ? parseInt(tok[1]) : std::nullopt;
  if (!n || *n < 2 || *n > 100000) {
    why = "FLASER: number of readings is not an integer >= 2";
    return std::nullopt;
  }
  const auto N = static_cast<std::size_t>(*n);
  if (tok.size() != N + 11) {
    why = "FLASER with " + std::to_string(N) + " readings has " + std::to_string(N + 11) +
          " fields (n, ranges, x y theta, odom x y theta, ipc_timestamp, host, "
          "logger_timestamp), got " + std::to_string(tok.size());
    return std::nullopt;
  }
  LaserLine l;
  if (!readRanges(tok, 2, N, l.ranges, why)) return std::nullopt;
  const auto laser = pose(tok, 2 + N, "laser pose", why);
  const auto odo = laser ? pose(tok, 5 + N, "odometry pose", why) : std::nullopt;
  const auto t = odo ? stamp(tok, 8 + N, why) : std::nullopt;
  if (!t) return std::nullopt;
  l.t = *t;
  // x y theta is the laser's pose; the robot centre is `offset` behind it.
  l.robot = *laser + mrpt::poses::CPose2D(-p.offset, 0, 0);
  l.odometry = *odo;
  l.sensor_pose = mrpt::poses::CPose3D(p.offset, 0, 0, 0, 0, 0);
  const double fov = opt.fov_deg > 0 ? opt.fov_deg
                     : p.fov_deg > 0 ? p.fov_deg
                     : p.res_deg > 0 ? p.res_deg * static_cast<double>(N)
                                     : 180.0;
  l.aperture = fov * kDeg;
  l.max_range = opt.max_range > 0 ? opt.max_range : p.max_range > 0 ? p.max_range
                                                                      : kDefaultMaxRange;
  return l;
}

std::optional<LaserLine> parseRobotLaser(const Tokens& tok, const CarmenToRawlogOptions& opt,
                                         std::string& why) {
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
  const auto t = robot ? stamp(tok, k + 11, why) : std::nullopt;
  if (!t) return std::nullopt;
  if (!(*fov > 0)) {
    why = "field_of_view " + std::string(tok[3]) + " is not positive";
    return std::nullopt;
  }
  l.t = *t;
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

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

CarmenToRawlogReport carmenToRawlog(const CarmenToRawlogOptions& opt) {
  using Mode = CarmenToRawlogOptions::Odometry;
  const auto t0 = std::chrono::steady_clock::now();
  LineReader in(opt.input);
  ObsRawlogWriter out(opt.output);
  std::unique_ptr<GroundTruthWriter> gt;
  if (!opt.gt_output.empty()) gt = std::make_unique<GroundTruthWriter>(opt.gt_output);

  CarmenToRawlogReport rep;
  FlaserParams params;
  std::mt19937_64 rng(opt.seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::optional<Stamp> last_out, last_scan;
  std::optional<mrpt::poses::CPose2D> prev_robot;
  mrpt::poses::CPose2D synth;
  Progress progress(opt.progress);

  const auto bad = [&](const std::string& why) {
    const std::string where = in.path() + ":" + std::to_string(in.lineNumber());
    if (!opt.skip_bad_lines) throw InputError(where + ": " + why);
    if (rep.bad_lines++ == 0) {
      rep.first_bad_line = in.lineNumber();
      rep.first_bad_reason = why;
    }
  };

  std::string line, why;
  while (in.next(line)) {
    ++rep.lines;
    if (progress.due())
      *progress.stream() << "carmen2rawlog: " << rep.lines << " lines, " << rep.scans
                         << " scans" << std::endl;
    const Tokens tok = splitWhitespace(line);
    if (tok.empty() || tok[0].front() == '#') continue;
    const std::string msg(tok[0]);

    if (msg == "PARAM") {
      if (tok.size() < 3) {
        bad("PARAM without a name and a value");
        continue;
      }
      double* target = tok[1] == "robot_frontlaser_offset"        ? &params.offset
                       : tok[1] == "robot_front_laser_max"        ? &params.max_range
                       : tok[1] == "laser_front_laser_fov"        ? &params.fov_deg
                       : tok[1] == "laser_front_laser_resolution" ? &params.res_deg
                                                                  : nullptr;
      if (!target) continue;
      const auto v = parseDouble(tok[2]);
      if (!v) {
        bad("PARAM " + std::string(tok[1]) + ": value '" + std::string(tok[2]) +
            "' is not a number");
        continue;
      }
      *target = *v;
      continue;
    }

    if (msg == "ODOM") {
      if (opt.odometry != Mode::OdomLines) {
        ++rep.ignored[msg];
        continue;
      }
      if (tok.size() != 10) {
        bad("ODOM has 10 fields (x y theta tv rv accel ipc_timestamp host logger_timestamp), "
            "got " + std::to_string(tok.size()));
        continue;
      }
      why.clear();
      const auto p = pose(tok, 1, "odometry pose", why);
      const auto t = p ? stamp(tok, 7, why) : std::nullopt;
      if (!t) {
        bad(why);
        continue;
      }
      if (last_out && *t < *last_out) {  // e.g. the re-anchoring lines of corrected logs
        ++rep.odom_dropped;
        continue;
      }
      mrpt::obs::CObservationOdometry o;
      o.sensorLabel = "ODOMETRY";
      o.timestamp = t->toClock();
      o.odometry = *p;
      out.write(o);
      ++rep.odometry;
      last_out = *t;
      continue;
    }

    if (msg != "FLASER" && msg != "ROBOTLASER1") {
      ++rep.ignored[msg];
      continue;
    }
    // A log with both kinds carries the same scans twice: keep the first kind seen.
    if (rep.laser_message.empty()) rep.laser_message = msg;
    if (msg != rep.laser_message) {
      ++rep.ignored[msg];
      continue;
    }
    why.clear();
    std::optional<LaserLine> l =
        msg == "FLASER" ? parseFlaser(tok, params, opt, why) : parseRobotLaser(tok, opt, why);
    if (!l) {
      bad(why);
      continue;
    }

    // Keep log order; a scan stamped before the previous record is moved just after it.
    Stamp t = l->t;
    if (last_scan && t <= *last_scan) t = last_scan->plusMicroseconds(1);
    if (last_out && t < *last_out) t = *last_out;
    if (!(t == l->t)) ++rep.raised_timestamps;

    if (opt.odometry != Mode::OdomLines) {
      mrpt::poses::CPose2D odo = l->odometry;
      if (opt.odometry == Mode::Synthetic) {
        if (!prev_robot) {
          synth = l->robot;
        } else {
          const mrpt::poses::CPose2D d = l->robot - *prev_robot;
          Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(opt.model.covariance(d));
          Eigen::Vector3d z(n01(rng), n01(rng), n01(rng));
          const Eigen::Vector3d e = es.eigenvectors() *
                                    es.eigenvalues().cwiseMax(0.0).cwiseSqrt().cwiseProduct(z);
          synth = synth + mrpt::poses::CPose2D(d.x() + e[0], d.y() + e[1], d.phi() + e[2]);
          synth.normalizePhi();
        }
        odo = synth;
      }
      mrpt::obs::CObservationOdometry o;
      o.sensorLabel = "ODOMETRY";
      o.timestamp = t.toClock();
      o.odometry = odo;
      out.write(o);
      ++rep.odometry;
    }
    prev_robot = l->robot;

    mrpt::obs::CObservation2DRangeScan scan;
    scan.sensorLabel = msg;
    scan.timestamp = t.toClock();
    scan.aperture = static_cast<float>(l->aperture);
    scan.rightToLeft = true;
    scan.maxRange = static_cast<float>(l->max_range);
    scan.sensorPose = l->sensor_pose;
    scan.resizeScan(l->ranges.size());
    for (std::size_t i = 0; i < l->ranges.size(); ++i) {
      const double r = l->ranges[i];
      const bool valid = std::isfinite(r) && r > 0 && r < l->max_range;
      scan.setScanRange(i, static_cast<float>(valid ? r : l->max_range));
      scan.setScanRangeValidity(i, valid);
    }
    out.write(scan);
    if (rep.scans++ == 0) {
      rep.rays = l->ranges.size();
      rep.aperture_deg = l->aperture / kDeg;
    }
    if (gt) {
      gt->write(t.seconds(), l->robot);
      ++rep.gt_poses;
    }
    last_scan = t;
    last_out = t;
  }
  if (rep.scans == 0)
    throw InputError(opt.input + ": no FLASER or ROBOTLASER1 line: not a CARMEN laser log?");
  out.close();
  if (gt) gt->flush();
  rep.wall_time_s = secondsSince(t0);
  return rep;
}

}  // namespace asf::convert
