// source_sim2d: a 2D robot simulator on a 2.5D occupancy-grid world (map image or built-in
// room; every obstacle has a height). MRPT simulates the horizontal laser
// (COccupancyGridMap2D::laserScanSimulator on the obstacles taller than the laser) and gives
// the odometry noise model (CActionRobotMovement2D's Gaussian model); an optional tilted laser
// is ray cast over the height field. The robot plans on the *estimated* map, drives in fixed
// steps and never passes through a true obstacle, low or not.
#include <asf/atomic_file.h>
#include <asf/errors.h>
#include <asf/io/occupancy_io.h>
#include <asf/io/rawlog_io.h>
#include <asf/io/recorded_run.h>
#include <asf/source.h>
#include <mrpt/core/Clock.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <deque>
#include <filesystem>
#include <memory>
#include <optional>
#include <random>
#include <sstream>

#include <asf/navigation/grid_path.h>
#include "sim2d_world.h"
#include "source_sim2d_keys.h"

namespace {

constexpr double kDeg = M_PI / 180.0;
using mrpt::poses::CPose2D;

class Sim2dSource final : public asf::Source {
 public:
  void configure(const asf::Params& p, const asf::PluginContext& ctx) override {
    configureWorld(p);
    configureStart(p);
    configureSensors(p);
    configureMotion(p);
    configureRecording(p, ctx);
    // Separate streams: changing the laser does not change the odometry noise (and so the
    // path), which keeps runs comparable across sensor settings.
    motion_rng_.seed(ctx.seed);
    laser_rng_.seed(ctx.seed ^ 0x9e3779b97f4a7c15ULL);
    tilted_rng_.seed(ctx.seed ^ 0xc2b2ae3d27d4eb4fULL);  // its own stream: see scanTilted()
    believed_ = true_pose_;
    step_ = 0;
    status_ = asf::NavStatus::Idle;
    next_scan_time_ = 0;
    if (!p.getString("resume_from").empty()) resumeFrom(p);
  }

  /// Continues an earlier run's recording (`asf run --resume`): its frames copied to ours, the
  /// robot where they end (the map frame stays the first run's), the noise streams where they
  /// were: each recorded move and scan draws again what it drew (as many engine outputs).
  void resumeFrom(const asf::Params& p) {
    const std::string base =
        (std::filesystem::path(p.getString("resume_from")) / p.getString("record_name")).string();
    std::optional<CPose2D> last;
    double last_scan_time = -1;
    std::size_t frames = 0;
    try {
      frames = asf::io::forEachRecordedFrame(base, [&](asf::SensorFrame& f) {
        if (writer_) writer_->write(f), gt_writer_->write(f.timestamp, *f.ground_truth);
        last = *f.ground_truth;
        if (f.odometry.x() != 0 || f.odometry.y() != 0 || f.odometry.phi() != 0)
          sampleNoise(Eigen::Matrix3d::Identity());  // move() drew for a move, never at rest
        if (f.scan) {
          last_scan_ = f.scan, last_scan_time = f.timestamp;
          std::normal_distribution<double> n01(0.0, 1.0);  // as scan(): one per ray
          for (int i = 0; i < rays_; ++i) n01(laser_rng_);
        }
        if (tilted_ && !f.observations3d.empty()) {
          std::normal_distribution<double> n01(0.0, 1.0);  // as scanTilted()
          for (std::size_t i = 0; i < tilted_rays_; ++i) n01(tilted_rng_);
        }
      });
    } catch (const asf::InputError& e) {
      p.fail("resume_from", e.what());
    }
    if (!last) p.fail("resume_from", base + ".rawlog: no frame to continue from");
    true_pose_ = believed_ = *last;
    step_ = static_cast<std::int64_t>(frames);
    if (laser_rate_ > 0) next_scan_time_ = last_scan_time + 1.0 / laser_rate_;
    MRPT_LOG_INFO_STREAM("continuing " << base << ".rawlog after its " << frames << " frames");
  }

  /// The true world: the built-in room, or a map image with obstacle heights.
  void configureWorld(const asf::Params& p) {
    const std::string image = p.getString("map_image");
    std::vector<asf::sim2d::HeightClass> classes;
    try {
      classes = asf::sim2d::parseHeightClasses(p.getString("obstacle_heights"));
    } catch (const std::invalid_argument& e) {
      p.fail("obstacle_heights", e.what());
    }
    const double wall_height = p.getDouble("wall_height");
    try {
      if (image.empty()) {
        if (!classes.empty())
          MRPT_LOG_WARN(
              "obstacle_heights is ignored without map_image: the built-in room's "
              "walls are wall_height tall");
        world_ = asf::sim2d::World::room(p.getDouble("room_width"), p.getDouble("room_height"),
                                         p.getDouble("resolution"), wall_height);
      } else {
        asf::sim2d::ImageWorldOptions o;
        o.file = image;
        o.resolution = p.getDouble("resolution");
        o.origin_x = p.getDouble("origin_x");
        o.origin_y = p.getDouble("origin_y");
        o.occupied_threshold = p.getDouble("occupied_threshold");
        const std::string unknown = p.getString("map_unknown");
        o.unknown = unknown == "free"   ? asf::sim2d::UnknownCells::Free
                    : unknown == "wall" ? asf::sim2d::UnknownCells::Wall
                                        : asf::sim2d::UnknownCells::Blocked;
        if (asf::io::isOccupancyYaml(image)) applyMapServerYaml(p, image, o);
        o.pad_wall_px = static_cast<int>(p.getInt("pad_wall_px"));
        o.tiles = static_cast<int>(p.getInt("map_tiles"));
        o.wall_height = wall_height;
        o.height_classes = classes;
        world_ = asf::sim2d::World::fromImage(o);
        if (world_.wallCells() == 0)
          MRPT_LOG_WARN_STREAM(image << ": no pixel is darker than occupied_threshold; the "
                                        "world has no walls");
      }
    } catch (const std::runtime_error& e) {
      p.fail("map_image", e.what());
    }
  }

  /// A map_server map (map_image = X.yaml): its image, resolution, origin and pixel classes
  /// (free, occupied, unknown by its thresholds and mode). The keys it sets must not be given.
  void applyMapServerYaml(const asf::Params& p, const std::string& yaml,
                          asf::sim2d::ImageWorldOptions& o) {
    for (const char* k : {"resolution", "origin_x", "origin_y", "occupied_threshold"})
      if (!p.isDefault(k))
        p.fail(k, std::string("map_image is a map_server YAML, which sets ") + k +
                      " (and the free, occupied and unknown gray levels): leave it out");
    asf::io::OccupancyMapInfo info;
    try {
      info = asf::io::readOccupancyYaml(yaml);
    } catch (const asf::InputError& e) {
      p.fail("map_image", e.what());
    }
    o.file = asf::io::occupancyImagePath(yaml, info);
    o.resolution = info.resolution;
    o.origin_x = info.origin_x;
    o.origin_y = info.origin_y;
    std::array<asf::sim2d::PixelClass, 256> classes{};
    for (int v = 0; v < 256; ++v) switch (asf::io::mapServerClass(info, static_cast<std::uint8_t>(v))) {
        case asf::io::MapCell::Free:
          classes[v] = asf::sim2d::PixelClass::Free;
          break;
        case asf::io::MapCell::Occupied:
          classes[v] = asf::sim2d::PixelClass::Wall;
          break;
        case asf::io::MapCell::Unknown:
          classes[v] = asf::sim2d::PixelClass::Unknown;
          break;
      }
    o.classes = classes;
  }

  /// The start pose (clear of the walls by the robot's radius) and the world's truth. A map
  /// image without start_x and start_y: the free cell farthest from any wall.
  void configureStart(const asf::Params& p) {
    radius_ = p.getDouble("robot_radius");
    true_pose_ = CPose2D(p.getDouble("start_x"), p.getDouble("start_y"),
                         p.getDouble("start_phi_deg") * kDeg);
    if (!p.getString("map_image").empty() && p.isDefault("start_x") && p.isDefault("start_y")) {
      const auto far = world_.farthestFromWalls();
      if (!far) p.fail("map_image", "the map has no free cell to start in");
      true_pose_ = CPose2D(far->first.x, far->first.y, true_pose_.phi());
      MRPT_LOG_INFO_STREAM(
          "no start_x / start_y: starting at the free cell farthest from any "
          "wall, ("
          << far->first.x << ", " << far->first.y << "), " << far->second << " m from the nearest");
    }
    if (world_.clearance(true_pose_.x(), true_pose_.y()) < radius_) {
      std::ostringstream os;
      os << "the start (" << true_pose_.x() << ", " << true_pose_.y()
         << ") is inside a wall, outside the map or closer than robot_radius to a wall "
            "(clearance "
         << world_.clearance(true_pose_.x(), true_pose_.y()) << " m)";
      p.fail("start_x", os.str());
    }

    auto truth = std::make_shared<asf::WorldTruth>();
    truth->grid = std::make_shared<const mrpt::maps::COccupancyGridMap2D>(world_.grid());
    truth->map_origin = true_pose_;
    truth->robot_radius = radius_;
    truth_ = std::move(truth);
  }

  /// The horizontal laser and the optional tilted one.
  void configureSensors(const asf::Params& p) {
    rays_ = static_cast<int>(p.getInt("laser_rays"));
    fov_ = p.getDouble("laser_fov_deg") * kDeg;
    max_range_ = p.getDouble("laser_max_range");
    range_sigma_ = p.getDouble("range_sigma");
    laser_rate_ = p.getDouble("laser_rate");
    sensor_pose_ =
        mrpt::poses::CPose3D(p.getDouble("sensor_x"), p.getDouble("sensor_y"),
                             p.getDouble("sensor_z"), p.getDouble("sensor_yaw_deg") * kDeg, 0, 0);
    // The horizontal laser sees only the obstacles taller than its height. With all of them
    // taller (the default) it scans the true grid itself, as before heights existed.
    laser_grid_ = world_.gridTallerThan(sensor_pose_.z());
    if (laser_grid_ && world_.cellsNotTallerThan(sensor_pose_.z()) > 0) {
      MRPT_LOG_INFO_STREAM(world_.cellsNotTallerThan(sensor_pose_.z())
                           << " obstacle cells are not taller than sensor_z = " << sensor_pose_.z()
                           << " m: the horizontal laser does not see them");
      if (world_.cellsNotTallerThan(sensor_pose_.z()) == world_.wallCells())
        MRPT_LOG_WARN_STREAM("no obstacle is taller than sensor_z = "
                             << sensor_pose_.z() << " m: the horizontal laser sees nothing");
    }
    tilted_ = p.getBool("tilted_laser");
    tilted_rays_ = static_cast<std::size_t>(p.getInt("tilted_rays"));
    tilted_fov_ = p.getDouble("tilted_fov_deg") * kDeg;
    tilted_max_range_ = p.getDouble("tilted_max_range");
    tilted_sigma_ = p.getDouble("tilted_range_sigma");
    if (tilted_sigma_ < 0) tilted_sigma_ = range_sigma_;
    // MRPT's CPose3D(x, y, z, yaw, pitch, roll): a positive pitch turns the sensor's x axis
    // down (towards -z), so the downward tilt is the pitch as given.
    tilted_pose_ = mrpt::poses::CPose3D(
        p.getDouble("tilted_x"), p.getDouble("tilted_y"), p.getDouble("tilted_z"),
        p.getDouble("tilted_yaw_deg") * kDeg, p.getDouble("tilted_pitch_deg") * kDeg, 0);
  }

  /// Motion, odometry noise and the navigation on the estimated map.
  void configureMotion(const asf::Params& p) {
    dt_ = p.getDouble("dt");
    step_length_ = p.getDouble("step_length");
    turn_step_ = p.getDouble("turn_step_deg") * kDeg;
    heading_tol_ = p.getDouble("heading_tolerance_deg") * kDeg;
    model_ = asf::mapping::OdometryNoiseModel::fromParams(p);
    // Plans keep a margin beyond the true radius: obstacles are known to a cell, and a path
    // that grazes the lethal boundary touches the true wall.
    nav_.robot_radius = radius_ + p.getDouble("nav_safety_margin");
    nav_.inflation_margin = p.getDouble("nav_inflation_margin");
    nav_.occupied_threshold = p.getDouble("nav_occupied_threshold");
    nav_.unknown_blocked = p.getString("nav_unknown") == "blocked";
    nav_.unknown_cost = p.getDouble("nav_unknown_cost");
    max_steps_ = p.getInt("max_steps");
    recovery_backup_ = p.getDouble("recovery_backup");
    replan_every_ = p.getInt("replan_every");
  }

  /// The rawlog and ground truth the run records ([sim2d] record).
  void configureRecording(const asf::Params& p, const asf::PluginContext& ctx) {
    const bool record = p.getBool("record");
    const std::string name = p.getString("record_name");
    if (record && name.empty()) p.fail("record_name", "must not be empty when record = true");
    if (record && !ctx.output_dir.empty()) {
      const std::filesystem::path base = std::filesystem::path(ctx.output_dir) / name;
      rawlog_path_ = base.string() + ".rawlog";
      gt_path_ = base.string() + ".gt.txt";
      const std::string resume = p.getString("resume_from");
      namespace fs = std::filesystem;
      if (!resume.empty() &&
          fs::weakly_canonical(fs::path(resume) / name) == fs::weakly_canonical(base))
        p.fail("resume_from",
               "is this run's own output folder: the recording to continue would "
               "be overwritten before it is read (use another output folder)");
      writer_ = std::make_unique<asf::io::RawlogWriter>(rawlog_path_);
      gt_writer_ = std::make_unique<asf::io::GroundTruthWriter>(gt_path_);
    }
  }

  ~Sim2dSource() override {
    if (collisions_)
      MRPT_LOG_WARN_STREAM(collisions_ << " moves were stopped by walls during the run");
    if (writer_)
      MRPT_LOG_INFO_STREAM("recorded " << writer_->framesWritten() << " frames to " << rawlog_path_
                                       << " (ground truth: " << gt_path_ << ")");
  }

  void endRecording() override {
    asf::closeEach({{"", [&] { if (writer_) writer_->close(); }},
                    {"", [&] { if (gt_writer_) gt_writer_->close(); }}});
  }

  bool isActive() const override { return true; }

  // The base's limits are its own navigation's: a step_length and a turn_step per dt.
  bool driveVelocity(const asf::BaseVelocity& v) override {
    const double fwd = step_length_ / dt_, turn = turn_step_ / dt_;
    auto limit = [](double x, double m) { return std::isfinite(x) ? std::clamp(x, -m, m) : 0.0; };
    velocity_ = asf::BaseVelocity{limit(v.forward, fwd), limit(v.turn, turn)};
    goal_.reset();
    path_.clear();
    backup_left_ = 0;
    escape_heading_.reset();
    status_ = asf::NavStatus::Idle;
    return true;
  }

  asf::NavStatus navigate(const asf::Goal& goal, const asf::NavigationContext& ctx) override {
    velocity_.reset();
    believed_ = ctx.robot_estimate;
    path_.clear();
    goal_.reset();
    if (!std::isfinite(goal.x) || !std::isfinite(goal.y) || !std::isfinite(goal.tolerance) ||
        goal.tolerance < 0) {
      status_ = asf::NavStatus::Unreachable;
      return status_;
    }
    goal_ = goal;
    if (std::hypot(goal.x - believed_.x(), goal.y - believed_.y()) <= goal.tolerance) {
      status_ = asf::NavStatus::Reached;
      return status_;
    }
    plan_grid_ = ctx.map ? ctx.map->grid : nullptr;
    goal_steps_ = 0;
    if (collided_) {
      // Recovery, as navigation stacks do: back away from the wall first, then plan from
      // there (planning from against the wall tends to lead straight back into it).
      collided_ = false;
      backup_left_ = recovery_backup_;
      status_ = asf::NavStatus::Moving;
      return status_;
    }
    status_ = plan() ? asf::NavStatus::Moving : asf::NavStatus::Unreachable;
    return status_;
  }

  asf::NavStatus status() const override { return status_; }
  std::shared_ptr<const asf::WorldTruth> worldTruth() const override { return truth_; }

  std::optional<asf::SensorFrame> next() override {
    if (step_ >= max_steps_) return std::nullopt;
    asf::SensorFrame f;
    // The timestamp goes through MRPT's clock so a recorded rawlog replays it exactly.
    f.timestamp = mrpt::Clock::toDouble(mrpt::Clock::fromDouble(static_cast<double>(step_) * dt_));
    if (step_ > 0) move(f);
    f.ground_truth = true_pose_;
    if (laser_rate_ <= 0 || f.timestamp + 1e-9 >= next_scan_time_) {
      f.scan = scan(f.timestamp);
      last_scan_ = f.scan;
      if (tilted_) f.observations3d.push_back(scanTilted(f.timestamp));
      if (laser_rate_ > 0) next_scan_time_ += 1.0 / laser_rate_;
    }
    if (writer_) {
      writer_->write(f);
      gt_writer_->write(f.timestamp, true_pose_);
    }
    ++step_;
    return f;
  }

 private:
  // Plans from the believed pose to goal_ on the map given to navigate() plus the latest
  // scan; false (and the reason logged) when there is no path.
  bool plan(bool first = true) {
    const asf::navigation::NavPlan p =
        asf::navigation::planPath(plan_grid_.get(), {believed_.x(), believed_.y()}, {goal_->x, goal_->y},
                             goal_->tolerance, nav_, scanObstacles());
    if (!p.found) {
      MRPT_LOG_INFO_STREAM("goal (" << goal_->x << ", " << goal_->y
                                    << ") unreachable: " << p.reason);
      return false;
    }
    path_.assign(p.waypoints.begin(), p.waypoints.end());
    since_plan_ = 0;
    if (!first) return true;
    // A generous step budget against oscillation: three times the straight driving and
    // turning the path needs.
    goal_budget_ = goal_steps_ +
                   static_cast<std::int64_t>(3 * (p.length / step_length_ +
                                                  (p.waypoints.size() + 1) * M_PI / turn_step_)) +
                   100;
    return true;
  }

  // Heading (map frame, from the believed pose) of the longest valid ray of the latest scan:
  // where there is the most room.
  std::optional<double> openHeading() const {
    if (!last_scan_) return std::nullopt;
    double best = -1, heading = 0;
    for (std::size_t i = 0; i < last_scan_->getScanSize(); ++i) {
      const double r =
          last_scan_->getScanRangeValidity(i) ? last_scan_->getScanRange(i) : max_range_;
      if (r > best) {
        best = r;
        heading = believed_.phi() + last_scan_->sensorPose.yaw() + last_scan_->getScanAngle(i);
      }
    }
    return mrpt::math::wrapToPi(heading);
  }

  // The latest scan's endpoints placed with the believed pose (asf::navigation::scanEndpoints).
  std::vector<asf::Point2> scanObstacles() const {
    return last_scan_ ? asf::navigation::scanEndpoints(*last_scan_, believed_) : std::vector<asf::Point2>{};
  }

  // The next command (forward, turn) from the believed pose towards the current waypoint.
  CPose2D command() {
    if (backup_left_ > 0) {
      // Recovery: back up straight; when the first back-up step was stopped too (the robot
      // is wedged, e.g. across a narrow passage), turn towards the most open direction of
      // the latest scan and drive that way instead (a disc robot can always turn).
      if (!escape_heading_) {
        const double back = std::min(step_length_, backup_left_);
        backup_left_ -= back;
        if (backup_left_ <= 1e-12 && !plan()) status_ = asf::NavStatus::Unreachable;
        return CPose2D(-back, 0, 0);
      }
      const double err = mrpt::math::wrapToPi(*escape_heading_ - believed_.phi());
      if (std::abs(err) > heading_tol_)
        return CPose2D(0, 0, std::copysign(std::min(std::abs(err), turn_step_), err));
      const double fwd = std::min(step_length_, backup_left_);
      backup_left_ -= fwd;
      if (backup_left_ <= 1e-12) {
        escape_heading_.reset();
        if (!plan()) status_ = asf::NavStatus::Unreachable;
      }
      return CPose2D(fwd, 0, 0);
    }
    // Replan now and then: the latest scan corrects the path where the map has drifted.
    if (replan_every_ > 0 && ++since_plan_ >= replan_every_ && !path_.empty() && !plan(false)) {
      status_ = asf::NavStatus::Blocked;
      return {};
    }
    while (!path_.empty()) {
      const asf::Point2& w = path_.front();
      const double d = std::hypot(w.x - believed_.x(), w.y - believed_.y());
      if (d > 0.5 * step_length_ && d > 1e-6) break;
      path_.pop_front();
    }
    if (path_.empty()) {
      status_ = asf::NavStatus::Reached;
      return {};
    }
    if (++goal_steps_ > goal_budget_) {
      MRPT_LOG_WARN_STREAM("stuck: no progress towards (" << goal_->x << ", " << goal_->y
                                                          << ") after " << goal_budget_
                                                          << " steps");
      status_ = asf::NavStatus::Blocked;
      return {};
    }
    const asf::Point2& w = path_.front();
    const double d = std::hypot(w.x - believed_.x(), w.y - believed_.y());
    const double err = mrpt::math::wrapToPi(std::atan2(w.y - believed_.y(), w.x - believed_.x()) -
                                            believed_.phi());
    const double turn = std::copysign(std::min(std::abs(err), turn_step_), err);
    if (std::abs(err) > heading_tol_) return CPose2D(0, 0, turn);
    // Drive and correct the heading in the same step, so the robot stays on the planned
    // segment instead of drifting sideways by up to the heading tolerance.
    return CPose2D(std::min(step_length_, d), 0, turn);
  }

  // One control step: the true pose moves by the command unless a wall is in the way, the
  // odometry reads the true increment with noise from the motion model, and the believed
  // pose integrates that reading.
  void move(asf::SensorFrame& f) {
    CPose2D u;
    if (velocity_) u = velocityStep(*velocity_);
    else if (goal_ && status_ == asf::NavStatus::Moving) u = command();
    if (u.x() != 0) {
      const CPose2D to = true_pose_ + u;
      if (world_.sweepCollides({true_pose_.x(), true_pose_.y()}, {to.x(), to.y()}, radius_)) {
        ++collisions_;
        collided_ = true;
        // Stopped while backing up (or escaping): escape towards open space next time.
        if (backup_left_ > 0 || escape_heading_) escape_heading_ = openHeading();
        backup_left_ = 0;
        if (!velocity_ || !pushing_)  // a velocity held against a wall: said once
          MRPT_LOG_WARN_STREAM("blocked: moving " << u.x() << " m from (" << true_pose_.x() << ", "
                                                  << true_pose_.y() << ") would hit a wall");
        pushing_ = velocity_.has_value();
        status_ = asf::NavStatus::Blocked;
        u = CPose2D();
      } else {
        pushing_ = false;
      }
    }
    true_pose_ = true_pose_ + u;
    true_pose_.normalizePhi();

    CPose2D reading;  // a robot at rest reads exactly zero
    if (u.x() != 0 || u.y() != 0 || u.phi() != 0) {
      const Eigen::Vector3d e = sampleNoise(model_.covariance(u));
      reading = CPose2D(u.x() + e.x(), u.y() + e.y(), u.phi() + e.z());
    }
    f.odometry = reading;
    f.odometry_cov = model_.covariance(reading);
    believed_ = believed_ + reading;
    believed_.normalizePhi();
  }

  // One step of the base at a velocity: the exact arc of a unicycle over dt.
  CPose2D velocityStep(const asf::BaseVelocity& v) const {
    const double d = v.forward * dt_, a = v.turn * dt_;
    if (std::abs(a) < 1e-12) return CPose2D(d, 0, 0);
    return CPose2D(d * std::sin(a) / a, d * (1 - std::cos(a)) / a, a);
  }

  Eigen::Vector3d sampleNoise(const Eigen::Matrix3d& cov) {
    // cov = V D V^T; x = V sqrt(D) z works for singular covariances too.
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    std::normal_distribution<double> n01(0.0, 1.0);
    Eigen::Vector3d z(n01(motion_rng_), n01(motion_rng_), n01(motion_rng_));
    return es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() * z;
  }

  std::shared_ptr<const mrpt::obs::CObservation2DRangeScan> scan(double t) {
    auto obs = std::make_shared<mrpt::obs::CObservation2DRangeScan>();
    obs->sensorLabel = "LASER";
    obs->timestamp = mrpt::Clock::fromDouble(t);
    obs->aperture = static_cast<float>(fov_);
    obs->rightToLeft = true;
    obs->maxRange = static_cast<float>(max_range_);
    obs->stdError = static_cast<float>(range_sigma_);
    obs->sensorPose = sensor_pose_;
    (laser_grid_ ? *laser_grid_ : world_.grid())
        .laserScanSimulator(*obs, true_pose_, 0.5f, static_cast<std::size_t>(rays_));
    std::normal_distribution<double> n01(0.0, 1.0);
    for (std::size_t i = 0; i < obs->getScanSize(); ++i) {
      const double noise = range_sigma_ * n01(laser_rng_);  // one draw per ray: stable streams
      if (!obs->getScanRangeValidity(i)) {
        obs->setScanRange(i, static_cast<float>(max_range_));
        continue;
      }
      const double z = obs->getScanRange(i) + noise;
      const bool valid = z > 0 && z < max_range_;
      obs->setScanRange(i, static_cast<float>(valid ? z : max_range_));
      obs->setScanRangeValidity(i, valid);
    }
    return obs;
  }

  // The tilted laser: exact ranges by ray casting over the height field from the true pose,
  // then Gaussian noise from its own random stream (so enabling it changes neither the
  // odometry nor the horizontal laser's draws); rays with no echo read maxRange, invalid.
  std::shared_ptr<const mrpt::obs::CObservation> scanTilted(double t) {
    auto obs = std::make_shared<mrpt::obs::CObservation2DRangeScan>();
    obs->sensorLabel = "TILTED_LASER";
    obs->timestamp = mrpt::Clock::fromDouble(t);
    obs->aperture = static_cast<float>(tilted_fov_);
    obs->rightToLeft = true;
    obs->maxRange = static_cast<float>(tilted_max_range_);
    obs->stdError = static_cast<float>(tilted_sigma_);
    obs->sensorPose = tilted_pose_;
    world_.simulateScan3D(*obs, true_pose_, tilted_rays_);
    std::normal_distribution<double> n01(0.0, 1.0);
    for (std::size_t i = 0; i < obs->getScanSize(); ++i) {
      const double noise = tilted_sigma_ * n01(tilted_rng_);  // one draw per ray
      if (!obs->getScanRangeValidity(i)) continue;
      const double z = obs->getScanRange(i) + noise;
      const bool valid = z > 0 && z < tilted_max_range_;
      obs->setScanRange(i, static_cast<float>(valid ? z : tilted_max_range_));
      obs->setScanRangeValidity(i, valid);
    }
    return obs;
  }

  asf::sim2d::World world_;
  // The obstacles the horizontal laser sees (taller than sensor_z); null = world_.grid().
  std::shared_ptr<const mrpt::maps::COccupancyGridMap2D> laser_grid_;
  bool tilted_ = false;
  std::size_t tilted_rays_ = 0;
  double tilted_fov_ = 0, tilted_max_range_ = 0, tilted_sigma_ = 0;
  mrpt::poses::CPose3D tilted_pose_;
  std::mt19937_64 tilted_rng_;
  std::shared_ptr<const asf::WorldTruth> truth_;  // a copy of the world for evaluation
  asf::navigation::NavOptions nav_;
  asf::mapping::OdometryNoiseModel model_;
  CPose2D true_pose_, believed_;
  mrpt::poses::CPose3D sensor_pose_;
  std::optional<asf::Goal> goal_;
  std::shared_ptr<const mrpt::obs::CObservation2DRangeScan> last_scan_;
  std::shared_ptr<const mrpt::maps::COccupancyGridMap2D> plan_grid_;
  bool collided_ = false;
  std::optional<asf::BaseVelocity> velocity_;  // driving by velocity (driveVelocity) until a goal
  bool pushing_ = false;  // the velocity's last step was stopped by a wall
  double backup_left_ = 0, recovery_backup_ = 0;
  std::optional<double> escape_heading_;  // set when backing up failed too
  std::int64_t since_plan_ = 0, replan_every_ = 0;
  std::deque<asf::Point2> path_;
  asf::NavStatus status_ = asf::NavStatus::Idle;
  std::mt19937_64 motion_rng_, laser_rng_;
  std::int64_t step_ = 0, max_steps_ = 0, goal_steps_ = 0, goal_budget_ = 0, collisions_ = 0;
  int rays_ = 0;
  double fov_ = 0, max_range_ = 0, range_sigma_ = 0, laser_rate_ = 0, next_scan_time_ = 0;
  double dt_ = 0, step_length_ = 0, turn_step_ = 0, heading_tol_ = 0, radius_ = 0;
  std::string rawlog_path_, gt_path_;
  std::unique_ptr<asf::io::RawlogWriter> writer_;
  std::unique_ptr<asf::io::GroundTruthWriter> gt_writer_;
};

}  // namespace

ASF_PLUGIN(Sim2dSource, asf::PluginKind::Source, "sim2d", "1.0.0",
           "2D simulator on a map image: MRPT laser and odometry models, A* navigation on the "
           "estimated map, rawlog recording",
           asf::ThreadSafety::ThreadCompatible, kKeys)
