// source_segment_world: a 2D robot simulator on an asf::mapping::SegmentWorld (exact ray casting,
// noisy odometry, straight-line goal following that never passes through walls).
#include <asf/errors.h>
#include <asf/mapping/segment_world.h>
#include <asf/source.h>
#include <mrpt/core/Clock.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <cmath>
#include <memory>
#include <optional>
#include <random>
#include <sstream>

namespace {

constexpr double kDeg = M_PI / 180.0;

class SegmentWorldSource final : public asf::Source {
 public:
  void configure(const asf::Params& p, const asf::PluginContext& ctx) override {
    const std::string world = p.getString("world");
    const double w = p.getDouble("room_width"), h = p.getDouble("room_height");
    const double door = p.getDouble("door_width");
    const std::string walls = p.getString("walls");
    radius_ = p.getDouble("robot_radius");
    if (world == "two_rooms") {
      if (door >= h) p.fail("door_width", "must be smaller than room_height");
      if (door < 2 * radius_)
        MRPT_LOG_WARN_STREAM("door_width " << door << " m is narrower than the robot ("
                                           << 2 * radius_ << " m): the rooms are not connected");
      world_ = asf::mapping::SegmentWorld::twoRooms(w, h, door);
    } else if (world == "rectangle") {
      world_ = asf::mapping::SegmentWorld::rectangle(0, 0, w, h);
    } else {  // custom
      if (walls.empty()) p.fail("walls", "world = custom needs at least one wall");
      try {
        world_ = asf::mapping::SegmentWorld::parse(walls);
      } catch (const asf::ConfigError& e) {
        p.fail("walls", e.what());
      }
      if (world_.walls().empty()) p.fail("walls", "world = custom needs at least one wall");
    }
    if (world != "custom" && !walls.empty())
      MRPT_LOG_WARN_STREAM("key 'walls' is ignored unless world = custom (world = " << world
                                                                                    << ")");

    true_pose_ = mrpt::poses::CPose2D(p.getDouble("start_x"), p.getDouble("start_y"),
                                      p.getDouble("start_phi_deg") * kDeg);
    const asf::Box2 b = world_.bounds();
    const asf::Point2 s{true_pose_.x(), true_pose_.y()};
    if (s.x <= b.min_x || s.x >= b.max_x || s.y <= b.min_y || s.y >= b.max_y)
      p.fail("start_x", "the start position lies outside the world's walls");
    if (world_.collides(s, s, radius_))
      p.fail("start_x", "the start position is closer than robot_radius to a wall");

    rays_ = static_cast<int>(p.getInt("laser_rays"));
    fov_ = p.getDouble("laser_fov_deg") * kDeg;
    max_range_ = p.getDouble("laser_max_range");
    range_sigma_ = p.getDouble("range_sigma");
    sensor_x_ = p.getDouble("sensor_x");
    dt_ = p.getDouble("dt");
    speed_ = p.getDouble("speed");
    turn_rate_ = p.getDouble("turn_rate_deg") * kDeg;
    heading_tol_ = p.getDouble("heading_tolerance_deg") * kDeg;
    odo_sigma_xy_ = p.getDouble("odo_sigma_xy");
    odo_sigma_phi_ = p.getDouble("odo_sigma_phi");
    max_steps_ = p.getInt("max_steps");

    rng_.seed(ctx.seed);
    believed_ = true_pose_;
    step_ = 0;
    status_ = asf::NavStatus::Idle;
    goal_.reset();
  }

  bool isActive() const override { return true; }

  asf::NavStatus navigate(const asf::Goal& goal, const asf::NavigationContext& ctx) override {
    believed_ = ctx.robot_estimate;
    if (!std::isfinite(goal.x) || !std::isfinite(goal.y) || !std::isfinite(goal.tolerance)) {
      goal_.reset();
      status_ = asf::NavStatus::Unreachable;
      return status_;
    }
    goal_ = goal;
    status_ = distanceToGoal() < goal.tolerance ? asf::NavStatus::Reached
                                                : asf::NavStatus::Moving;
    return status_;
  }

  asf::NavStatus status() const override { return status_; }

  std::optional<asf::SensorFrame> next() override {
    if (step_ >= max_steps_) return std::nullopt;
    asf::SensorFrame f;
    f.timestamp = static_cast<double>(step_) * dt_;
    if (step_ > 0) move(f);
    f.ground_truth = true_pose_;
    f.scan = scan(f.timestamp);
    ++step_;
    return f;
  }

 private:
  double distanceToGoal() const {
    return std::hypot(goal_->x - believed_.x(), goal_->y - believed_.y());
  }

  // One control step: command from the believed pose, true pose moves by the command,
  // odometry measures it with noise, the believed pose integrates the measurement.
  void move(asf::SensorFrame& f) {
    double forward = 0, turn = 0;
    if (goal_ && status_ == asf::NavStatus::Moving) {
      const double dist = distanceToGoal();
      if (dist < goal_->tolerance) {
        status_ = asf::NavStatus::Reached;
      } else {
        const double bearing = std::atan2(goal_->y - believed_.y(), goal_->x - believed_.x());
        const double err = mrpt::math::wrapToPi(bearing - believed_.phi());
        if (std::abs(err) > heading_tol_)
          turn = std::copysign(std::min(std::abs(err), turn_rate_ * dt_), err);
        else
          forward = std::min(speed_ * dt_, dist);
      }
    }
    if (forward > 0) {
      const mrpt::poses::CPose2D next = true_pose_ + mrpt::poses::CPose2D(forward, 0, 0);
      if (world_.collides({true_pose_.x(), true_pose_.y()}, {next.x(), next.y()}, radius_)) {
        MRPT_LOG_WARN_STREAM("blocked: moving " << forward << " m from (" << true_pose_.x()
                                                << ", " << true_pose_.y()
                                                << ") would hit a wall; stopping");
        status_ = asf::NavStatus::Blocked;
        forward = 0;
      }
    }
    const mrpt::poses::CPose2D u(forward, 0, turn);  // commanded == true increment
    true_pose_ = true_pose_ + u;
    true_pose_.normalizePhi();

    const double sxy = odo_sigma_xy_ * std::abs(forward);
    const double sphi = odo_sigma_phi_ * (std::abs(turn) + std::abs(forward));
    std::normal_distribution<double> n01(0.0, 1.0);
    const double nx = sxy * n01(rng_), ny = sxy * n01(rng_), nphi = sphi * n01(rng_);
    f.odometry = mrpt::poses::CPose2D(u.x() + nx, u.y() + ny, u.phi() + nphi);
    f.odometry_cov = Eigen::Vector3d(sxy * sxy, sxy * sxy, sphi * sphi).asDiagonal();
    believed_ = believed_ + f.odometry;
    believed_.normalizePhi();
  }

  std::shared_ptr<const mrpt::obs::CObservation2DRangeScan> scan(double t) {
    auto obs = std::make_shared<mrpt::obs::CObservation2DRangeScan>();
    obs->sensorLabel = "LASER";
    obs->timestamp = mrpt::Clock::fromDouble(t);
    obs->aperture = static_cast<float>(fov_);
    obs->rightToLeft = true;
    obs->maxRange = static_cast<float>(max_range_);
    obs->stdError = static_cast<float>(range_sigma_);
    obs->sensorPose = mrpt::poses::CPose3D(sensor_x_, 0, 0, 0, 0, 0);
    obs->resizeScan(static_cast<std::size_t>(rays_));
    const mrpt::poses::CPose2D laser = true_pose_ + mrpt::poses::CPose2D(sensor_x_, 0, 0);
    std::normal_distribution<double> n01(0.0, 1.0);
    for (int i = 0; i < rays_; ++i) {
      const double a = laser.phi() + obs->getScanAngle(static_cast<std::size_t>(i));
      const double r = world_.castRay(laser.x(), laser.y(), a, max_range_);
      const double noise = range_sigma_ * n01(rng_);  // drawn for every ray: stable streams
      const double z = r + noise;
      const bool valid = r < max_range_ && z > 0 && z < max_range_;
      obs->setScanRange(static_cast<std::size_t>(i),
                        static_cast<float>(valid ? z : max_range_));
      obs->setScanRangeValidity(static_cast<std::size_t>(i), valid);
    }
    return obs;
  }

  asf::mapping::SegmentWorld world_;
  mrpt::poses::CPose2D true_pose_, believed_;
  std::optional<asf::Goal> goal_;
  asf::NavStatus status_ = asf::NavStatus::Idle;
  std::mt19937_64 rng_;
  std::int64_t step_ = 0, max_steps_ = 0;
  int rays_ = 0;
  double fov_ = 0, max_range_ = 0, range_sigma_ = 0, sensor_x_ = 0, dt_ = 0, speed_ = 0;
  double turn_rate_ = 0, heading_tol_ = 0, radius_ = 0, odo_sigma_xy_ = 0, odo_sigma_phi_ = 0;
};

const asf::KeySpec kKeys[] = {
    asf::keyEnum("world", "two_rooms", "two_rooms|rectangle|custom",
                 "World layout: two rooms joined by a door, one rectangular room, or `walls`"),
    asf::keyDouble("room_width", "5.0", "Width of each room (two_rooms) or of the rectangle [m]",
                   0.5, 1000),
    asf::keyDouble("room_height", "4.0", "Height of the rooms / rectangle [m]", 0.5, 1000),
    asf::keyDouble("door_width", "1.0", "Door in the middle of the shared wall (two_rooms) [m]",
                   0, 1000),
    asf::keyString("walls", "",
                   "Walls for world = custom: 'x1 y1 x2 y2; x1 y1 x2 y2; ...' [m]"),
    asf::keyDouble("start_x", "1.0", "True start position x, world frame [m]"),
    asf::keyDouble("start_y", "1.0", "True start position y, world frame [m]"),
    asf::keyDouble("start_phi_deg", "0", "True start heading [deg]", -360, 360),
    asf::keyInt("laser_rays", "181", "Number of laser rays per scan", 2, 100000),
    asf::keyDouble("laser_fov_deg", "180", "Laser field of view, centred ahead [deg]", 1, 360),
    asf::keyDouble("laser_max_range", "8.0", "Laser maximum range; farther = invalid ray [m]",
                   0.1, 1000),
    asf::keyDouble("range_sigma", "0.01", "Std of the Gaussian range noise [m]", 0, 10),
    asf::keyDouble("sensor_x", "0.1", "Laser position ahead of the robot centre [m]", -10, 10),
    asf::keyDouble("dt", "0.1", "Simulated time per step [s]", 1e-4, 100),
    asf::keyDouble("speed", "0.5", "Forward speed while driving [m/s]", 1e-3, 100),
    asf::keyDouble("turn_rate_deg", "90", "Turn rate while rotating in place [deg/s]", 1e-3,
                   10000),
    asf::keyDouble("heading_tolerance_deg", "10",
                   "Drive forward once the heading error is below this [deg]", 0.01, 90),
    asf::keyDouble("robot_radius", "0.2", "Robot radius: never closer than this to a wall [m]",
                   0.01, 100),
    asf::keyDouble("odo_sigma_xy", "0.02", "Odometry x/y noise std per metre driven [m/m]", 0,
                   1),
    asf::keyDouble("odo_sigma_phi", "0.01",
                   "Odometry heading noise std per radian turned plus per metre driven "
                   "[rad/rad, rad/m]",
                   0, 1),
    asf::keyInt("max_steps", "20000", "Frames produced before the stream ends", 1, 1e12),
};

}  // namespace

ASF_PLUGIN(SegmentWorldSource, asf::PluginKind::Source, "segment_world", "1.0.0",
           "2D simulator: exact laser on wall segments, noisy odometry, straight-line driving",
           asf::ThreadSafety::ThreadCompatible, kKeys)
