#pragma once
/// \file rosbag2.h
/// ROS bags to an MRPT rawlog: ROS 2 (rosbag2, sqlite3 storage, CDR messages) and ROS 1
/// (format 2.0, through the official library): the 2D laser
/// (sensor_msgs/msg/LaserScan), the odometry (nav_msgs/msg/Odometry) and the laser's mounting
/// on the robot (tf2_msgs/msg/TFMessage on /tf_static), stamps kept to the 100 ns of MRPT's
/// clock. The messages are decoded here (CDR as the DDS spec and rosidl lay them out), so no
/// ROS installation is needed.
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace asf::io {

/// One topic of a bag.
struct BagTopic {
  std::string name, type, serialization_format;
  std::uint64_t messages = 0;
};

/// How a bag's messages are serialized: ROS 2's CDR, or ROS 1's own (little-endian, packed,
/// strings without a NUL, a header with a sequence number).
enum class Wire { Cdr, Ros1 };

/// A bag's topics and messages, whatever the bag's format.
class BagReader {
 public:
  virtual ~BagReader() = default;
  /// The topics, their types as ROS 2 spells them ("pkg/msg/Type", also for ROS 1 bags).
  virtual const std::vector<BagTopic>& topics() const = 0;
  virtual Wire wire() const = 0;
  /// The topic of that name, or null.
  const BagTopic* topic(const std::string& name) const;
  /// Calls `f(topic, bag_time_ns, data, size)` for every message of `topics`, in the bag's
  /// time order (ties in the order written).
  template <class F>
  void forEach(const std::vector<std::string>& topics, F&& f) const;
  /// Calls `f` for the first message of `topic` only, if any (the rest is not read from an
  /// indexed storage: sqlite3, ROS 1).
  template <class F>
  void forFirst(const std::string& topic, F&& f) const;

 protected:
  /// Returns false to stop the visit.
  using Visitor = bool (*)(void* ctx, const std::string& topic, std::int64_t t,
                           const std::uint8_t* data, std::size_t size);
  virtual void visit(const std::vector<std::string>& topics, Visitor v, void* ctx) const = 0;

 private:
  /// visit() with `f` called for each message; the visit goes on after one iff kAll.
  template <bool kAll, class F>
  void visitWith(const std::vector<std::string>& topics, F& f) const;
};

template <bool kAll, class F>
void BagReader::visitWith(const std::vector<std::string>& topics, F& f) const {
  visit(
      topics,
      [](void* ctx, const std::string& topic, std::int64_t t, const std::uint8_t* d,
         std::size_t n) {
        (*static_cast<F*>(ctx))(topic, t, d, n);
        return kAll;
      },
      &f);
}

template <class F>
void BagReader::forEach(const std::vector<std::string>& topics, F&& f) const {
  visitWith<true>(topics, f);
}

template <class F>
void BagReader::forFirst(const std::string& topic, F&& f) const {
  visitWith<false>({topic}, f);
}

/// A rosbag2 folder (metadata.yaml beside its .db3 files) or one .db3 file, read through
/// SQLite. Throws asf::InputError naming the file: not a bag, a storage other than sqlite3,
/// compressed files or messages.
class Rosbag2Reader final : public BagReader {
 public:
  explicit Rosbag2Reader(const std::string& path);
  ~Rosbag2Reader() override;
  Rosbag2Reader(const Rosbag2Reader&) = delete;
  Rosbag2Reader& operator=(const Rosbag2Reader&) = delete;
  const std::vector<BagTopic>& topics() const override;
  Wire wire() const override { return Wire::Cdr; }

 private:
  struct Impl;
  void visit(const std::vector<std::string>& topics, Visitor v, void* ctx) const override;
  std::unique_ptr<Impl> impl_;
};

/// A ROS 1 bag (format 2.0; chunks plain, bz2 or lz4) through the official ROS 1 library
/// (Debian's librosbag-storage). Throws asf::InputError naming the file.
class Ros1BagReader final : public BagReader {
 public:
  explicit Ros1BagReader(const std::string& path);
  ~Ros1BagReader() override;
  Ros1BagReader(const Ros1BagReader&) = delete;
  Ros1BagReader& operator=(const Ros1BagReader&) = delete;
  const std::vector<BagTopic>& topics() const override;
  Wire wire() const override { return Wire::Ros1; }

 private:
  struct Impl;
  void visit(const std::vector<std::string>& topics, Visitor v, void* ctx) const override;
  std::unique_ptr<Impl> impl_;
};

/// MCAP files (ROS 2's default storage since Iron; chunks plain, lz4 or zstd), read by the
/// MCAP specification. Throws asf::InputError naming the file.
class McapReader final : public BagReader {
 public:
  explicit McapReader(const std::vector<std::string>& files);
  ~McapReader() override;
  McapReader(const McapReader&) = delete;
  McapReader& operator=(const McapReader&) = delete;
  const std::vector<BagTopic>& topics() const override;
  Wire wire() const override { return Wire::Cdr; }

 private:
  struct Impl;
  void visit(const std::vector<std::string>& topics, Visitor v, void* ctx) const override;
  std::unique_ptr<Impl> impl_;
};

/// A ROS 1 bag (*.bag), an MCAP file (*.mcap) or a ROS 2 bag (a folder with metadata.yaml,
/// sqlite3 or mcap storage, or a .db3 file).
std::unique_ptr<BagReader> openBag(const std::string& path);

/// The fields of one serialized message. Cdr: OMG CDR as XCDR1 plain (a 4-byte encapsulation
/// header, CDR_LE or CDR_BE, then the fields aligned to their size from the header's end);
/// Ros1: little-endian, packed, strings without a NUL. Reads past the end throw
/// asf::InputError naming `where`.
class CdrReader {
 public:
  CdrReader(const std::uint8_t* data, std::size_t size, std::string where, Wire wire = Wire::Cdr);
  std::uint8_t u8();
  std::int32_t i32();
  std::uint32_t u32();
  float f32();
  double f64();
  std::string str();            ///< uint32 length (with the NUL), bytes, NUL
  std::vector<float> f32seq();  ///< uint32 count, then the floats
  std::size_t offset() const { return pos_; }

 private:
  void align(std::size_t n);
  const std::uint8_t* need(std::size_t n);
  const std::uint8_t* data_;
  std::size_t size_, pos_ = 4;
  bool swap_ = false;
  Wire wire_;
  std::string where_;
};

struct RosTime {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
};

struct LaserScanMsg {
  RosTime stamp;
  std::string frame_id;
  float angle_min = 0, angle_max = 0, angle_increment = 0, time_increment = 0, scan_time = 0,
        range_min = 0, range_max = 0;
  std::vector<float> ranges, intensities;
};
struct OdometryMsg {
  RosTime stamp;
  std::string frame_id, child_frame_id;
  double x = 0, y = 0, z = 0, qx = 0, qy = 0, qz = 0, qw = 1;
};
struct TransformMsg {
  RosTime stamp;
  std::string frame_id, child_frame_id;
  double x = 0, y = 0, z = 0, qx = 0, qy = 0, qz = 0, qw = 1;
};

LaserScanMsg decodeLaserScan(const std::uint8_t* data, std::size_t size, const std::string& where,
                             Wire wire = Wire::Cdr);
OdometryMsg decodeOdometry(const std::uint8_t* data, std::size_t size, const std::string& where,
                           Wire wire = Wire::Cdr);
/// geometry_msgs/msg/PoseStamped (its pose in an OdometryMsg, no child frame).
OdometryMsg decodePoseStamped(const std::uint8_t* data, std::size_t size, const std::string& where,
                              Wire wire = Wire::Cdr);
std::vector<TransformMsg> decodeTfMessage(const std::uint8_t* data, std::size_t size,
                                          const std::string& where, Wire wire = Wire::Cdr);

struct BagToRawlogOptions {
  std::string input;       ///< ROS 1 .bag, rosbag2 folder or .db3 file
  std::string output;      ///< .rawlog or .rawlog.gz
  std::string scan_topic;  ///< empty: the bag's only LaserScan topic
  /// Empty: the bag's only Odometry topic, else /tf when there is none (the transforms to
  /// the base frame); "/tf": those transforms.
  std::string odom_topic;
  bool odometry = true;    ///< false: scans only
  std::string base_frame;  ///< empty: the odometry's child_frame_id, else "base_link"
  /// The laser on the robot; when unset, from /tf_static (base_frame -> the scans' frame_id).
  std::optional<mrpt::poses::CPose3D> laser_pose;
  /// A ground-truth topic (nav_msgs/msg/Odometry or geometry_msgs/msg/PoseStamped, e.g. a
  /// simulator's /ground_truth) written to `gt_output` as "t x y phi" lines; empty: none.
  std::string gt_topic, gt_output;
  std::ostream* progress = nullptr;
};

struct BagToRawlogReport {
  std::vector<BagTopic> topics;
  std::string scan_topic, odom_topic, laser_frame, base_frame;
  bool odom_from_tf = false;  ///< the odometry from /tf's transforms to the base frame
  mrpt::poses::CPose3D laser_pose;
  std::string laser_pose_from;  ///< "/tf_static", "--laser-pose" or "identity (same frame)"
  std::size_t scans = 0, odometry = 0, rays = 0, gt_poses = 0;
  double aperture_deg = 0;
  double wall_time_s = 0;
};

/// Whether `path` is a ROS bag: a ROS 1 .bag file, a folder with metadata.yaml or a .db3 file.
bool isRosBag(const std::string& path);

/// "X,Y,Z,YAW_DEG" as a pose; throws std::invalid_argument saying what is wrong.
mrpt::poses::CPose3D parseLaserPose(const std::string& text);

/// Converts; throws asf::InputError naming the bag: a missing topic (listing the topics
/// present), a topic of another type, no transform from the base to the laser frame.
BagToRawlogReport bagToRawlog(const BagToRawlogOptions& o);

}  // namespace asf::io
