// ROS 1 or ROS 2 bag -> MRPT rawlog (asf bag2rawlog): the chosen LaserScan and Odometry topics as
// CObservation2DRangeScan and CObservationOdometry records in the bag's order, the laser's
// mounting from /tf_static.
#include <asf/errors.h>
#include <asf/io/ground_truth.h>
#include <asf/text.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3DQuat.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <ostream>
#include <sstream>
#include <stdexcept>

#include "asf/io/rosbag2.h"
#include "asf/io/text_io.h"

namespace asf::io {

namespace {

constexpr const char* kLaserScan = "sensor_msgs/msg/LaserScan";
constexpr const char* kOdometry = "nav_msgs/msg/Odometry";
constexpr const char* kTf = "tf2_msgs/msg/TFMessage";
constexpr const char* kPoseStamped = "geometry_msgs/msg/PoseStamped";

std::string topicList(const BagReader& bag) {
  std::string s;
  for (const auto& t : bag.topics())
    s += (s.empty() ? "" : ", ") + t.name + " (" + t.type + ", " + std::to_string(t.messages) + ")";
  return s.empty() ? "none" : s;
}

/// The topic named `want` (which must be of `type`), or the bag's only topic of `type` when
/// `want` is empty (`exclude`, the ground truth's, not counted); "" when `optional` and there
/// is none.
std::string chooseTopic(const BagReader& bag, const std::string& input, const std::string& want,
                        const char* type, const char* option, bool optional,
                        const std::string& exclude = "") {
  if (!want.empty()) {
    const BagTopic* t = bag.topic(want);
    if (!t) throw InputError(input + ": no topic " + want + "; topics: " + topicList(bag));
    if (t->type != type)
      throw InputError(input + ": topic " + want + " is a " + t->type + ", not a " + type);
    return want;
  }
  std::vector<std::string> found;
  for (const auto& t : bag.topics())
    if (t.type == type && t.name != exclude) found.push_back(t.name);
  if (found.size() == 1) return found[0];
  if (found.empty() && optional) return "";
  std::string names;
  for (const auto& n : found) names += (names.empty() ? "" : ", ") + n;
  throw InputError(input + ": " +
                   (found.empty() ? "no " + std::string(type) + " topic"
                                  : "several " + std::string(type) + " topics (" + names +
                                        "): choose one with " + option) +
                   "; topics: " + topicList(bag));
}

std::string stripSlash(std::string f) {
  while (!f.empty() && f.front() == '/') f.erase(0, 1);
  return f;
}

mrpt::poses::CPose3D poseOf(const TransformMsg& t) {
  return mrpt::poses::CPose3D(mrpt::poses::CPose3DQuat(
      t.x, t.y, t.z, mrpt::math::CQuaternionDouble(t.qw, t.qx, t.qy, t.qz)));
}

double yawOf(double qx, double qy, double qz, double qw) {
  return std::atan2(2 * (qw * qz + qx * qy), 1 - 2 * (qy * qy + qz * qz));
}

mrpt::Clock::time_point clockOf(const RosTime& t) {
  return mrpt::Clock::fromDouble(static_cast<double>(t.sec)) +
         std::chrono::duration_cast<mrpt::Clock::duration>(std::chrono::nanoseconds(t.nanosec));
}

/// base -> laser through the static transforms (child -> parent links).
mrpt::poses::CPose3D laserOnBase(const std::map<std::string, TransformMsg>& up,
                                 const std::string& base, const std::string& laser,
                                 const std::string& input) {
  mrpt::poses::CPose3D pose;  // laser in the frame reached so far
  std::string f = laser;
  for (std::size_t hops = 0; f != base; ++hops) {
    auto it = up.find(f);
    if (it == up.end() || hops > up.size()) {
      std::string have;
      for (const auto& [child, t] : up)
        have += (have.empty() ? "" : ", ") + stripSlash(t.frame_id) + " -> " + child;
      throw InputError(input + ": the laser frame '" + laser + "' has no transform to the base " +
                       "frame '" + base + "' in /tf_static (" + (have.empty() ? "none" : have) +
                       "); give it with --laser-pose X,Y,Z,YAW_DEG or --base-frame");
    }
    pose = poseOf(it->second) + pose;
    f = stripSlash(it->second.frame_id);
  }
  return pose;
}

mrpt::obs::CObservation2DRangeScan toScan(const LaserScanMsg& s, const mrpt::poses::CPose3D& mount,
                                          const std::string& where) {
  const std::size_t n = s.ranges.size();
  if (n < 2) throw InputError(where + ": a scan with " + std::to_string(n) + " ranges");
  if (!(std::isfinite(s.angle_increment) && s.angle_increment != 0))
    throw InputError(where + ": angle_increment " + std::to_string(s.angle_increment));
  mrpt::obs::CObservation2DRangeScan scan;
  scan.sensorLabel = "LASER";
  scan.timestamp = clockOf(s.stamp);
  // MRPT's rays span [-aperture/2, aperture/2] about the sensor's x axis: the scan's middle
  // angle becomes a turn of the sensor pose. angle_max is the last ray's angle when it agrees
  // with the increment (within half a step; then a symmetric scan turns by exactly 0),
  // else angle_min + (n - 1) increment.
  const double inc = s.angle_increment, span = inc * static_cast<double>(n - 1);
  const bool ends_agree = std::abs((double(s.angle_max) - s.angle_min) - span) < std::abs(inc) / 2;
  const double last = ends_agree ? double(s.angle_max) : s.angle_min + span;
  scan.aperture = static_cast<float>(std::abs(last - s.angle_min));
  scan.rightToLeft = inc > 0;
  const double mid = (s.angle_min + last) / 2;
  scan.sensorPose = mid == 0 ? mount : mount + mrpt::poses::CPose3D(0, 0, 0, mid, 0, 0);
  scan.maxRange = s.range_max;
  scan.resizeScan(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float r = s.ranges[i];
    // ROS: readings outside [range_min, range_max] are to be discarded.
    const bool valid = std::isfinite(r) && r >= s.range_min && r <= s.range_max;
    scan.setScanRange(i, valid ? r : s.range_max);
    scan.setScanRangeValidity(i, valid);
  }
  return scan;
}

}  // namespace

bool isRosBag(const std::string& path) {
  std::error_code ec;
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".bag" || ext == ".mcap") return true;
  if (std::filesystem::is_directory(path, ec))
    return std::filesystem::exists(std::filesystem::path(path) / "metadata.yaml", ec);
  return std::filesystem::path(path).extension() == ".db3";
}

mrpt::poses::CPose3D parseLaserPose(const std::string& text) {
  std::istringstream is(text);
  std::string part;
  std::vector<double> v;
  while (std::getline(is, part, ',')) {
    const std::optional<double> x = parseDouble(trim(part));
    if (!x) throw std::invalid_argument("'" + part + "' is not a number (expected X,Y,Z,YAW_DEG)");
    v.push_back(*x);
  }
  if (v.size() != 4) throw std::invalid_argument("expected X,Y,Z,YAW_DEG (four numbers)");
  return mrpt::poses::CPose3D(v[0], v[1], v[2], v[3] * M_PI / 180, 0, 0);
}

namespace {

/// The topics to read (the odometry's from /tf when no Odometry topic: the transforms from
/// the odometry frame to the robot's base).
void chooseTopics(const BagReader& bag, const BagToRawlogOptions& o, BagToRawlogReport& rep) {
  const char* format = bag.wire() == Wire::Cdr ? "cdr" : "ros1";
  for (const auto& t : bag.topics())
    if (t.serialization_format != format &&
        (t.type == kLaserScan || t.type == kOdometry || t.type == kTf))
      throw InputError(o.input + ": topic " + t.name + " is serialized as '" +
                       t.serialization_format + "', not " + format);
  rep.scan_topic = chooseTopic(bag, o.input, o.scan_topic, kLaserScan, "--scan-topic", false);
  if (!o.gt_topic.empty()) {
    const BagTopic* g = bag.topic(o.gt_topic);
    if (!g) throw InputError(o.input + ": no topic " + o.gt_topic + "; topics: " + topicList(bag));
    if (g->type != kOdometry && g->type != kPoseStamped)
      throw InputError(o.input + ": ground-truth topic " + o.gt_topic + " is a " + g->type +
                       ", not a " + kOdometry + " or " + kPoseStamped);
  }
  if (!o.odometry) return;
  const BagTopic* tf = bag.topic("/tf");
  if (o.odom_topic == "/tf" ||
      (o.odom_topic.empty() && tf && tf->type == kTf &&
       chooseTopic(bag, o.input, "", kOdometry, "", true, o.gt_topic).empty())) {
    if (!tf || tf->type != kTf)
      throw InputError(o.input + ": no /tf topic of " + kTf + " for the odometry");
    rep.odom_topic = "/tf";
    rep.odom_from_tf = true;
    return;
  }
  rep.odom_topic =
      chooseTopic(bag, o.input, o.odom_topic, kOdometry, "--odom-topic", true, o.gt_topic);
  if (!o.gt_topic.empty() && o.gt_topic == rep.odom_topic)
    throw InputError(o.input + ": the ground-truth topic " + o.gt_topic +
                     " is also the odometry topic");
}

/// The scans' frame and the robot's base frame (given, else the odometry's child frame, else
/// base_link).
void chooseFrames(const BagReader& bag, const BagToRawlogOptions& o, BagToRawlogReport& rep) {
  const Wire wire = bag.wire();
  bag.forFirst(
      rep.scan_topic, [&](const std::string&, std::int64_t, const std::uint8_t* d, std::size_t n) {
        rep.laser_frame =
            stripSlash(decodeLaserScan(d, n, o.input + ": " + rep.scan_topic, wire).frame_id);
      });
  rep.base_frame = o.base_frame;
  if (rep.base_frame.empty() && !rep.odom_topic.empty() && !rep.odom_from_tf)
    bag.forFirst(rep.odom_topic, [&](const std::string&, std::int64_t, const std::uint8_t* d,
                                     std::size_t n) {
      rep.base_frame =
          stripSlash(decodeOdometry(d, n, o.input + ": " + rep.odom_topic, wire).child_frame_id);
    });
  if (rep.base_frame.empty()) rep.base_frame = "base_link";
  rep.base_frame = stripSlash(rep.base_frame);
}

/// The laser on the robot: given, the identity (scans in the base frame), or /tf_static.
void chooseMount(const BagReader& bag, const BagToRawlogOptions& o, BagToRawlogReport& rep) {
  if (o.laser_pose) {
    rep.laser_pose = *o.laser_pose;
    rep.laser_pose_from = "--laser-pose";
    return;
  }
  if (rep.laser_frame == rep.base_frame) {
    rep.laser_pose_from = "identity (the scans are in the base frame)";
    return;
  }
  std::map<std::string, TransformMsg> up;  // child -> its transform from the parent
  const BagTopic* tf = bag.topic("/tf_static");
  if (tf && tf->type == kTf)
    bag.forEach({"/tf_static"},
                [&](const std::string&, std::int64_t, const std::uint8_t* d, std::size_t n) {
                  for (const auto& t : decodeTfMessage(d, n, o.input + ": /tf_static", bag.wire()))
                    up[stripSlash(t.child_frame_id)] = t;
                });
  rep.laser_pose = laserOnBase(up, rep.base_frame, rep.laser_frame, o.input);
  rep.laser_pose_from = "/tf_static";
}

void writeOdometry(ObsRawlogWriter& out, const RosTime& stamp, double x, double y, double yaw) {
  mrpt::obs::CObservationOdometry obs;
  obs.sensorLabel = "ODOMETRY";
  obs.timestamp = clockOf(stamp);
  obs.odometry = mrpt::poses::CPose2D(x, y, yaw);
  out.write(obs);
}

}  // namespace

BagToRawlogReport bagToRawlog(const BagToRawlogOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::unique_ptr<BagReader> reader = openBag(o.input);
  const BagReader& bag = *reader;
  const Wire wire = bag.wire();
  BagToRawlogReport rep;
  rep.topics = bag.topics();
  chooseTopics(bag, o, rep);
  chooseFrames(bag, o, rep);
  chooseMount(bag, o, rep);

  ObsRawlogWriter out(o.output);
  std::vector<std::string> topics{rep.scan_topic};
  if (!rep.odom_topic.empty()) topics.push_back(rep.odom_topic);
  std::unique_ptr<GroundTruthWriter> gt;
  const bool gt_pose_stamped = !o.gt_topic.empty() && bag.topic(o.gt_topic)->type == kPoseStamped;
  if (!o.gt_topic.empty()) {
    if (o.gt_output.empty()) throw InputError(o.input + ": a ground-truth topic needs a file");
    gt = std::make_unique<GroundTruthWriter>(o.gt_output);
    topics.push_back(o.gt_topic);
  }
  Progress progress(o.progress);
  bag.forEach(
      topics, [&](const std::string& topic, std::int64_t, const std::uint8_t* d, std::size_t n) {
        const std::string where = o.input + ": " + topic + " message";
        if (gt && topic == o.gt_topic) {
          const OdometryMsg m = gt_pose_stamped ? decodePoseStamped(d, n, where, wire)
                                                : decodeOdometry(d, n, where, wire);
          gt->write(static_cast<double>(m.stamp.sec) + m.stamp.nanosec * 1e-9,
                    mrpt::poses::CPose2D(m.x, m.y, yawOf(m.qx, m.qy, m.qz, m.qw)));
          ++rep.gt_poses;
        } else if (topic == rep.scan_topic) {
          const LaserScanMsg s = decodeLaserScan(d, n, where, wire);
          out.write(toScan(s, rep.laser_pose, where));
          if (rep.scans++ == 0) {
            rep.rays = s.ranges.size();
            rep.aperture_deg =
                std::abs(s.angle_increment) * static_cast<double>(s.ranges.size() - 1) * 180 / M_PI;
          }
        } else if (rep.odom_from_tf) {
          for (const auto& t : decodeTfMessage(d, n, where, wire))
            if (stripSlash(t.child_frame_id) == rep.base_frame) {
              writeOdometry(out, t.stamp, t.x, t.y, yawOf(t.qx, t.qy, t.qz, t.qw));
              ++rep.odometry;
            }
        } else {
          const OdometryMsg m = decodeOdometry(d, n, where, wire);
          writeOdometry(out, m.stamp, m.x, m.y, yawOf(m.qx, m.qy, m.qz, m.qw));
          ++rep.odometry;
        }
        if (o.progress && progress.due())
          *o.progress << "bag2rawlog: " << rep.scans << " scans, " << rep.odometry << " odometry"
                      << std::endl;
      });
  if (rep.odom_from_tf && rep.odometry == 0)
    throw InputError(o.input + ": /tf has no transform to the base frame '" + rep.base_frame +
                     "' for the odometry (give --base-frame, or --no-odometry)");
  out.close();
  rep.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

}  // namespace asf::io
