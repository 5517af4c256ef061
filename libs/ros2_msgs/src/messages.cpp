// ROS 2 messages to and from MRPT, for both DDS sides (messages.h).
#include <asf/ros2/messages.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/core/Clock.h>
#include <mrpt/math/CQuaternion.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <type_traits>

namespace asf::ros2 {

Stamp toStamp(double seconds) {
  if (!(seconds > 0)) return {};
  const auto ns = static_cast<std::int64_t>(std::llround(seconds * 1e9));
  return {static_cast<std::int32_t>(ns / 1000000000), static_cast<std::uint32_t>(ns % 1000000000)};
}

double toSeconds(const Stamp& s) { return s.sec + 1e-9 * s.nanosec; }

std::array<double, 4> quaternionFromYaw(double yaw) {
  return {0.0, 0.0, std::sin(0.5 * yaw), std::cos(0.5 * yaw)};
}

double yawFromQuaternion(double x, double y, double z, double w) {
  const double n = std::sqrt(x * x + y * y + z * z + w * w);
  if (!(n > 0)) return 0;
  x /= n, y /= n, z /= n, w /= n;
  return std::atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z));
}

mrpt::poses::CPose3D poseFromTransform(const Transform& t) {
  const double n = std::sqrt(t.qx * t.qx + t.qy * t.qy + t.qz * t.qz + t.qw * t.qw);
  // A zero quaternion (an unset message) reads as no rotation.
  if (!(n > 0) || !std::isfinite(n)) return mrpt::poses::CPose3D(t.tx, t.ty, t.tz, 0, 0, 0);
  const mrpt::math::CQuaternionDouble q(t.qw / n, t.qx / n, t.qy / n, t.qz / n);
  return mrpt::poses::CPose3D(q, t.tx, t.ty, t.tz);
}

Transform transformFromPose(const mrpt::poses::CPose3D& p) {
  mrpt::math::CQuaternionDouble q;
  p.getAsQuaternion(q);
  return {p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.r()};
}

Transform transformFromPose(const mrpt::poses::CPose2D& p) {
  const auto q = quaternionFromYaw(p.phi());
  return {p.x(), p.y(), 0.0, q[0], q[1], q[2], q[3]};
}

std::string ddsTopic(const std::string& ros_topic) {
  auto bad = [&](const char* why) {
    return std::invalid_argument("'" + ros_topic + "' is not a ROS 2 topic name: " + why);
  };
  if (ros_topic.empty() || ros_topic == "/") throw bad("it is empty");
  for (char c : ros_topic)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '/')
      throw bad("only letters, digits, '_' and '/' may appear");
  if (ros_topic.back() == '/') throw bad("it ends in '/'");
  if (ros_topic.find("//") != std::string::npos) throw bad("it holds '//'");
  const std::string rel = ros_topic.front() == '/' ? ros_topic.substr(1) : ros_topic;
  if (std::isdigit(static_cast<unsigned char>(rel.front()))) throw bad("it starts with a digit");
  return "rt/" + rel;
}

LaserScan laserScanFromMrpt(const mrpt::obs::CObservation2DRangeScan& scan, const Stamp& stamp,
                            const std::string& frame_id) {
  LaserScan m;
  m.stamp = stamp;
  m.frame_id = frame_id;
  const std::size_t n = scan.getScanSize();
  const double half = 0.5 * scan.aperture;
  const double inc = n > 1 ? scan.aperture / static_cast<double>(n - 1) : 0.0;
  m.angle_min = static_cast<float>(scan.rightToLeft ? -half : half);
  m.angle_max = static_cast<float>(scan.rightToLeft ? half : -half);
  m.angle_increment = static_cast<float>(scan.rightToLeft ? inc : -inc);
  m.range_min = 0.0f;
  m.range_max = scan.maxRange;
  m.ranges.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    m.ranges[i] = scan.getScanRangeValidity(i) ? scan.getScanRange(i)
                                               : std::numeric_limits<float>::infinity();
  if (scan.hasIntensity()) {
    m.intensities.resize(n);
    for (std::size_t i = 0; i < n; ++i) m.intensities[i] = static_cast<float>(scan.getScanIntensity(i));
  }
  return m;
}

std::shared_ptr<mrpt::obs::CObservation2DRangeScan> mrptFromLaserScan(
    const LaserScan& msg, const mrpt::poses::CPose3D& sensor_pose, double timestamp) {
  const std::size_t n = msg.ranges.size();
  if (n < 2) throw std::invalid_argument("a scan needs at least 2 rays (has " + std::to_string(n) + ")");
  if (!std::isfinite(msg.angle_increment) || msg.angle_increment == 0 ||
      !std::isfinite(msg.angle_min))
    throw std::invalid_argument("angle_min and angle_increment must be finite, the increment not 0");
  if (!msg.intensities.empty() && msg.intensities.size() != n)
    throw std::invalid_argument("intensities has " + std::to_string(msg.intensities.size()) +
                                " values for " + std::to_string(n) + " ranges");
  if (!(msg.range_max > 0) || !std::isfinite(msg.range_max))
    throw std::invalid_argument("range_max must be a positive number");
  auto obs = std::make_shared<mrpt::obs::CObservation2DRangeScan>();
  obs->sensorLabel = "LASER";
  obs->timestamp = mrpt::Clock::fromDouble(timestamp);
  const double span = static_cast<double>(msg.angle_increment) * static_cast<double>(n - 1);
  obs->aperture = static_cast<float>(std::abs(span));
  obs->rightToLeft = msg.angle_increment > 0;
  obs->maxRange = msg.range_max;
  // MRPT's rays are symmetric about the sensor's x axis: the centre of the ROS fan goes into
  // the sensor pose.
  const double centre = static_cast<double>(msg.angle_min) + 0.5 * span;
  obs->sensorPose = sensor_pose + mrpt::poses::CPose3D(0, 0, 0, centre, 0, 0);
  obs->resizeScan(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float r = msg.ranges[i];
    const bool valid = std::isfinite(r) && r >= msg.range_min && r <= msg.range_max && r > 0;
    obs->setScanRange(i, valid ? r : msg.range_max);
    obs->setScanRangeValidity(i, valid);
  }
  if (!msg.intensities.empty()) {
    obs->setScanHasIntensity(true);
    for (std::size_t i = 0; i < n; ++i)
      obs->setScanIntensity(i, static_cast<int>(std::lround(msg.intensities[i])));
  }
  return obs;
}

std::int8_t occupancyValue(float p_occupied, float unknown_band) {
  if (std::abs(p_occupied - 0.5f) < unknown_band) return -1;
  const long v = std::lround(100.0 * static_cast<double>(p_occupied));
  return static_cast<std::int8_t>(std::clamp<long>(v, 0, 100));
}

namespace {
using Cell = mrpt::maps::COccupancyGridMap2D::cellType;
using CellBits = std::make_unsigned_t<Cell>;
static_assert(sizeof(Cell) <= 2, "MRPT's occupancy cells are 8 or 16 bit");

// MRPT stores each cell as a small log-odds integer: one table from every stored value to its
// ROS value, then a pass over the raw cells (row-major, cy * width + cx, as ROS).
const std::vector<std::int8_t>& rosValueOfCell() {
  static const std::vector<std::int8_t> lut = [] {
    std::vector<std::int8_t> t(std::size_t(1) << (8 * sizeof(Cell)));
    for (std::size_t i = 0; i < t.size(); ++i) {
      const auto v = static_cast<Cell>(static_cast<CellBits>(i));
      t[i] = occupancyValue(1.0f - mrpt::maps::COccupancyGridMap2D::l2p(v));
    }
    return t;
  }();
  return lut;
}
}  // namespace

OccupancyGrid occupancyFromMrpt(const mrpt::maps::COccupancyGridMap2D& grid, const Stamp& stamp,
                                const std::string& frame_id) {
  return OccupancyConverter().convert(grid, stamp, frame_id);
}

const OccupancyGrid& OccupancyConverter::convert(const mrpt::maps::COccupancyGridMap2D& grid,
                                                 const Stamp& stamp, const std::string& frame_id) {
  const auto width = static_cast<std::uint32_t>(grid.getSizeX());
  const auto height = static_cast<std::uint32_t>(grid.getSizeY());
  const std::vector<Cell>& raw = grid.getRawMap();
  const std::size_t row_bytes = std::size_t(width) * sizeof(Cell);
  const bool same_shape = out_.width == width && out_.height == height &&
                          out_.resolution == grid.getResolution() && out_.origin.tx == grid.getXMin() &&
                          out_.origin.ty == grid.getYMin() && previous_.size() == row_bytes * height;
  out_.stamp = stamp;
  out_.frame_id = frame_id;
  out_.resolution = grid.getResolution();
  out_.width = width;
  out_.height = height;
  out_.origin = Transform{};
  out_.origin.tx = grid.getXMin();
  out_.origin.ty = grid.getYMin();
  out_.data.resize(raw.size());
  if (!same_shape) previous_.assign(row_bytes * height, 0);
  const auto* bytes = reinterpret_cast<const unsigned char*>(raw.data());
  const std::vector<std::int8_t>& lut = rosValueOfCell();
  rows_converted_ = 0;
  for (std::size_t y = 0; y < height; ++y) {
    unsigned char* seen = previous_.data() + y * row_bytes;
    if (same_shape && std::memcmp(seen, bytes + y * row_bytes, row_bytes) == 0) continue;
    std::memcpy(seen, bytes + y * row_bytes, row_bytes);
    const Cell* in = raw.data() + y * width;
    std::int8_t* out = out_.data.data() + y * width;
    for (std::size_t x = 0; x < width; ++x) out[x] = lut[static_cast<CellBits>(in[x])];
    ++rows_converted_;
  }
  return out_;
}

std::shared_ptr<mrpt::maps::COccupancyGridMap2D> mrptFromOccupancy(const OccupancyGrid& msg) {
  if (!(msg.resolution > 0) || !std::isfinite(msg.resolution))
    throw std::invalid_argument("resolution must be > 0");
  if (msg.data.size() != static_cast<std::size_t>(msg.width) * msg.height || msg.width == 0 ||
      msg.height == 0) {
    std::ostringstream os;
    os << "data has " << msg.data.size() << " cells for " << msg.width << " x " << msg.height;
    throw std::invalid_argument(os.str());
  }
  if (std::abs(yawFromQuaternion(msg.origin.qx, msg.origin.qy, msg.origin.qz, msg.origin.qw)) > 1e-6)
    throw std::invalid_argument("a rotated origin is not supported");
  const double res = msg.resolution;
  // MRPT places cell cx at [x_min + cx res, x_min + (cx + 1) res), and rounds x_min to a
  // multiple of the resolution: an origin off that lattice moves by less than half a cell.
  auto grid = std::make_shared<mrpt::maps::COccupancyGridMap2D>(
      static_cast<float>(msg.origin.tx), static_cast<float>(msg.origin.tx + msg.width * res),
      static_cast<float>(msg.origin.ty), static_cast<float>(msg.origin.ty + msg.height * res),
      static_cast<float>(res));
  if (grid->getSizeX() != msg.width || grid->getSizeY() != msg.height) {
    std::ostringstream os;
    os << "MRPT made a grid of " << grid->getSizeX() << " x " << grid->getSizeY() << " for "
       << msg.width << " x " << msg.height;
    throw std::logic_error(os.str());
  }
  // One table from the 256 ROS values to MRPT's stored log-odds, then a pass over the cells
  // (both row-major from the lowest y): a map arrives every second.
  using Cell = mrpt::maps::COccupancyGridMap2D::cellType;
  std::array<Cell, 256> lut{};
  for (int v = -128; v < 128; ++v) {
    const float p_occ = (v < 0 || v > 100) ? 0.5f : 0.01f * static_cast<float>(v);
    lut[static_cast<std::uint8_t>(v)] = mrpt::maps::COccupancyGridMap2D::p2l(1.0f - p_occ);
  }
  for (std::uint32_t cy = 0; cy < msg.height; ++cy) {
    Cell* row = grid->getRow(static_cast<int>(cy));
    const std::int8_t* in = msg.data.data() + static_cast<std::size_t>(cy) * msg.width;
    for (std::uint32_t cx = 0; cx < msg.width; ++cx) row[cx] = lut[static_cast<std::uint8_t>(in[cx])];
  }
  return grid;
}

const char* goalStateName(std::int8_t status) {
  switch (static_cast<GoalState>(status)) {
    case GoalState::Unknown: return "unknown";
    case GoalState::Accepted: return "accepted";
    case GoalState::Executing: return "executing";
    case GoalState::Canceling: return "canceling";
    case GoalState::Succeeded: return "succeeded";
    case GoalState::Canceled: return "canceled";
    case GoalState::Aborted: return "aborted";
  }
  return "invalid";
}

std::string cycloneLoopbackXml(int max_participants) {
  std::ostringstream os;
  os << "<CycloneDDS><Domain Id=\"any\"><General>"
        "<Interfaces><NetworkInterface name=\"lo\"/></Interfaces>"
        "<AllowMulticast>false</AllowMulticast>"
        // Loopback carries 64 kB datagrams: a map goes out in a few of them, not hundreds.
        "<MaxMessageSize>65000B</MaxMessageSize><FragmentSize>60000B</FragmentSize></General>"
        "<Discovery><ParticipantIndex>auto</ParticipantIndex>"
        "<MaxAutoParticipantIndex>"
     << max_participants
     << "</MaxAutoParticipantIndex><Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery>"
        "</Domain></CycloneDDS>";
  return os.str();
}

}  // namespace asf::ros2
