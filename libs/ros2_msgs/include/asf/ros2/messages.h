#pragma once
/// \file messages.h
/// ROS 2 messages as asf reads and writes them, independent of the DDS implementation: plain
/// structs with the fields of the ROS 2 messages asf uses, and their conversions to and from
/// MRPT. Each DDS side (the Cyclone DDS source plugin, the Fast DDS simulated robot) copies its
/// generated types to and from these, so both sides convert the same way.
///
/// Contract:
/// - Units and frames as REP 103 (metres, radians, x forward, y left, z up, counter-clockwise)
///   and REP 105 (map, odom, base_link).
/// - A LaserScan converts to an MRPT scan and back with the same rays, ranges and angles (to
///   float precision); rays that are NaN, infinite or outside [range_min, range_max] are
///   invalid in MRPT and read +inf in ROS.
/// - An occupancy grid converts cell by cell: -1 unknown, 0..100 the occupancy probability in
///   percent; cell (i, j) of the ROS grid is MRPT's cell (cx = i, cy = j), both rows from the
///   lowest y up. MRPT keeps a grid's origin on a multiple of its resolution: a ROS grid
///   whose origin is not moves by less than half a cell.
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace mrpt::maps {
class COccupancyGridMap2D;
}
namespace mrpt::obs {
class CObservation2DRangeScan;
}

namespace asf::ros2 {

/// builtin_interfaces/Time.
struct Stamp {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
};
/// Seconds to a stamp (rounded to the nanosecond; negative times are clamped to 0).
Stamp toStamp(double seconds);
double toSeconds(const Stamp& s);

/// Quaternion (x, y, z, w) of a rotation by `yaw` about z.
std::array<double, 4> quaternionFromYaw(double yaw);
/// The yaw of a quaternion (x, y, z, w) (normalised first).
double yawFromQuaternion(double x, double y, double z, double w);

/// geometry_msgs/Transform as a 3D pose (translation, quaternion), and back.
struct Transform {
  double tx = 0, ty = 0, tz = 0;
  double qx = 0, qy = 0, qz = 0, qw = 1;
};
mrpt::poses::CPose3D poseFromTransform(const Transform& t);
Transform transformFromPose(const mrpt::poses::CPose3D& p);
Transform transformFromPose(const mrpt::poses::CPose2D& p);

/// geometry_msgs/TransformStamped: `child` in `parent` (the pose of child's origin in parent).
struct TransformStamped {
  Stamp stamp;
  std::string parent, child;
  Transform transform;
};

/// nav_msgs/Odometry without its twist: the pose of `child_frame_id` in `frame_id`.
struct Odometry {
  Stamp stamp;
  std::string frame_id, child_frame_id;
  Transform pose;
};

/// A ROS 2 topic name ("/scan", "scan", "/robot1/odom") as the DDS topic ROS 2 uses
/// ("rt/scan", "rt/robot1/odom"). Throws std::invalid_argument naming the topic when it is
/// not a valid ROS 2 name (empty, a trailing '/', "//", characters other than [A-Za-z0-9_/~]).
std::string ddsTopic(const std::string& ros_topic);

/// sensor_msgs/LaserScan without its header.
struct LaserScan {
  Stamp stamp;
  std::string frame_id;
  float angle_min = 0, angle_max = 0, angle_increment = 0;
  float time_increment = 0, scan_time = 0;
  float range_min = 0, range_max = 0;
  std::vector<float> ranges, intensities;
};

/// An MRPT scan as a LaserScan (the scan's own sensorPose is not part of it: that is the
/// base_link -> frame_id transform).
LaserScan laserScanFromMrpt(const mrpt::obs::CObservation2DRangeScan& scan, const Stamp& stamp,
                            const std::string& frame_id);
/// A LaserScan as an MRPT scan with `sensor_pose` (base_link -> the laser frame). MRPT spaces
/// its rays symmetrically about the sensor's x axis: a scan whose angles are not symmetric
/// (angle_min != -angle_max) gets the offset in its sensor pose's yaw. Throws
/// std::invalid_argument saying what is wrong for a scan MRPT cannot hold (no rays, a zero or
/// non-finite increment, intensities of another length).
std::shared_ptr<mrpt::obs::CObservation2DRangeScan> mrptFromLaserScan(
    const LaserScan& msg, const mrpt::poses::CPose3D& sensor_pose, double timestamp);

/// nav_msgs/OccupancyGrid without its header.
struct OccupancyGrid {
  Stamp stamp;
  std::string frame_id;
  float resolution = 0;
  std::uint32_t width = 0, height = 0;
  Transform origin;  ///< pose of cell (0, 0)'s lower-left corner in frame_id
  std::vector<std::int8_t> data;
};

/// The ROS value of an occupancy probability: -1 when within `unknown_band` of 0.5, else
/// round(100 p).
std::int8_t occupancyValue(float p_occupied, float unknown_band = 0.02f);
/// An MRPT grid as an OccupancyGrid (origin at (x_min, y_min), no rotation).
OccupancyGrid occupancyFromMrpt(const mrpt::maps::COccupancyGridMap2D& grid, const Stamp& stamp,
                                const std::string& frame_id);
/// Successive versions of one MRPT grid as OccupancyGrids, the same as occupancyFromMrpt, but
/// only the rows whose cells changed since the previous call are converted again (a map grows
/// and changes around the robot; /map goes out whole).
class OccupancyConverter {
 public:
  const OccupancyGrid& convert(const mrpt::maps::COccupancyGridMap2D& grid, const Stamp& stamp,
                               const std::string& frame_id);
  /// Rows converted by the last call (all of them when the grid's shape changed).
  std::size_t rowsConverted() const { return rows_converted_; }

 private:
  OccupancyGrid out_;
  std::vector<unsigned char> previous_;  ///< the raw cells the last call converted, as bytes
  std::size_t rows_converted_ = 0;
};
/// An OccupancyGrid as an MRPT grid: unknown cells 0.5, the others value / 100. Throws
/// std::invalid_argument for a grid MRPT cannot hold (data of another size than width x
/// height, a resolution <= 0, a rotated origin).
std::shared_ptr<mrpt::maps::COccupancyGridMap2D> mrptFromOccupancy(const OccupancyGrid& msg);

/// visualization_msgs/Marker, the fields asf fills (no texture, mesh or lifetime: they go out
/// empty, which rviz reads as none and forever).
struct Marker {
  enum Type : std::int32_t {
    Arrow = 0, Cube = 1, Sphere = 2, LineStrip = 4, LineList = 5, SphereList = 7, Points = 8,
    Text = 9
  };
  enum Action : std::int32_t { Add = 0, Delete = 2, DeleteAll = 3 };
  Stamp stamp;
  std::string frame_id, ns, text;
  std::int32_t id = 0, type = Points, action = Add;
  Transform pose;
  std::array<double, 3> scale{1, 1, 1};
  std::array<float, 4> color{1, 1, 1, 1};  ///< r, g, b, a
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<float, 4>> colors;  ///< per point, or empty
};

/// action_msgs/GoalStatus values.
enum class GoalState : std::int8_t {
  Unknown = 0,
  Accepted = 1,
  Executing = 2,
  Canceling = 3,
  Succeeded = 4,
  Canceled = 5,
  Aborted = 6,
};
const char* goalStateName(std::int8_t status);

/// Discovery limited to this machine's loopback interface, as the tests and benchmarks run:
/// the Cyclone DDS configuration (XML for dds_create_domain or CYCLONEDDS_URI): interface lo,
/// no multicast, one unicast peer 127.0.0.1, participant indices up to `max_participants`.
std::string cycloneLoopbackXml(int max_participants = 10);

}  // namespace asf::ros2
