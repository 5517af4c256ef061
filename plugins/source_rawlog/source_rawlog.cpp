// source_rawlog: replays an MRPT rawlog (action/sensory-frame or observation-only, plain or
// gz) as a passive source, optionally with a ground-truth file.
#include <asf/errors.h>
#include <asf/io/rawlog_io.h>
#include <asf/source.h>
#include <asf/io/rosbag2.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

class RawlogSource final : public asf::Source {
 public:
  void configure(const asf::Params& p, const asf::PluginContext& ctx) override {
    asf::io::RawlogReaderOptions o;
    o.laser_label = p.getString("laser_label");
    o.odometry_model = asf::mapping::OdometryNoiseModel::fromParams(p);
    o.observations3d = p.getBool("observations3d");
    o.scan_from_3d = p.getBool("scan_from_3d");
    o.label_3d = p.getString("label_3d");
    o.slice.min_z = p.getDouble("slice_min_z");
    o.slice.max_z = p.getDouble("slice_max_z");
    o.slice.rays = static_cast<int>(p.getInt("slice_rays"));
    o.slice.max_range = p.getDouble("slice_max_range");
    if (o.slice.min_z >= o.slice.max_z)
      p.fail("slice_max_z", "must be above slice_min_z (" + p.getString("slice_min_z") + ")");
    max_gap_ = p.getDouble("ground_truth_max_gap");
    max_frames_ = p.getInt("max_frames");
    start_frame_ = p.getInt("start_frame");

    std::string file = p.getString("file");
    if (file.empty()) p.fail("file", "a rawlog file is required");
    std::string gt = p.getString("ground_truth");
    if (!p.getString("bag_gt_topic").empty() && !gt.empty())
      p.fail("bag_gt_topic", "ground_truth is given too: one or the other");
    if (asf::io::isRosBag(file)) file = fromBag(p, file, ctx.output_dir, gt);

    // Read here (not in the reader) so a bad ground-truth file is reported against its key.
    gt_.clear();
    if (!gt.empty()) {
      try {
        gt_ = asf::io::readGroundTruth(gt);
      } catch (const asf::InputError& e) {
        p.fail("ground_truth", e.what());
      }
      if (gt_.empty()) p.fail("ground_truth", "the file has no poses");
    }

    file_ = file;
    laser_label_ = o.laser_label;
    try {
      reader_ = std::make_unique<asf::io::RawlogReader>(file, o);
    } catch (const asf::InputError& e) {
      p.fail("file", e.what());
    }
    delivered_ = 0;
    skipped_ = 0;
    ended_ = false;
    clamped_ = 0;
  }

  std::optional<asf::SensorFrame> next() override {
    if (ended_) return std::nullopt;
    if (max_frames_ > 0 && delivered_ >= max_frames_) return end();
    // Skipped lazily: a damaged record among them is an InputError from next(), as any other.
    for (; skipped_ < start_frame_; ++skipped_)
      if (!reader_->next()) return end();
    std::optional<asf::SensorFrame> f = reader_->next();
    if (!f && skipped_ + delivered_ == 0) throw asf::InputError(noFrame());
    if (!f) return end();
    if (delivered_ == 0) {
      // Nothing was delivered before this frame: no increment to report.
      f->odometry = mrpt::poses::CPose2D();
      f->odometry_cov.setZero();
    } else if (f->timestamp < last_t_) {
      // The source contract wants non-decreasing times; real logs sometimes step back a bit.
      if (clamped_++ == 0)
        MRPT_LOG_WARN_STREAM("frame " << delivered_ << ": timestamp " << f->timestamp
                                      << " is before the previous frame's " << last_t_
                                      << "; using the previous one (warned once)");
      f->timestamp = last_t_;
    }
    if (!gt_.empty()) f->ground_truth = asf::io::interpolateGroundTruth(gt_, f->timestamp, max_gap_);
    last_t_ = f->timestamp;
    ++delivered_;
    return f;
  }

 private:
  /// A ROS bag is converted to a rawlog first (asf bag2rawlog's conversion), kept in the
  /// output folder as bag.rawlog (in a temporary file without one, removed at the end).
  std::string fromBag(const asf::Params& p, const std::string& bag, const std::string& out_dir,
                      std::string& gt) {
    asf::io::BagToRawlogOptions o;
    o.input = bag;
    o.scan_topic = p.getString("bag_scan_topic");
    o.odom_topic = p.getString("bag_odom_topic");
    o.odometry = o.odom_topic != "none";
    if (!o.odometry) o.odom_topic.clear();
    o.base_frame = p.getString("bag_base_frame");
    if (!p.getString("bag_laser_pose").empty()) try {
        o.laser_pose = asf::io::parseLaserPose(p.getString("bag_laser_pose"));
      } catch (const std::invalid_argument& e) {
        p.fail("bag_laser_pose", e.what());
      }
    o.gt_topic = p.getString("bag_gt_topic");
    if (!out_dir.empty()) {
      o.output = (std::filesystem::path(out_dir) / "bag.rawlog").string();
      if (!o.gt_topic.empty())
        o.gt_output = (std::filesystem::path(out_dir) / "bag.gt.txt").string();
    } else {
      temp_ = (std::filesystem::temp_directory_path() /
               ("asf_bag_" + std::to_string(::getpid()) + "_" +
                std::to_string(reinterpret_cast<std::uintptr_t>(this)) + ".rawlog"))
                  .string();
      o.output = temp_;
      if (!o.gt_topic.empty()) o.gt_output = temp_gt_ = temp_ + ".gt.txt";
    }
    try {
      const auto r = asf::io::bagToRawlog(o);
      MRPT_LOG_INFO_STREAM(bag << ": " << r.scans << " scans from " << r.scan_topic << ", "
                               << r.odometry << " odometry readings"
                               << (r.odom_topic.empty() ? "" : " from " + r.odom_topic)
                               << ", laser pose from " << r.laser_pose_from << " -> " << o.output);
    } catch (const asf::InputError& e) {
      p.fail("file", e.what());
    }
    if (!o.gt_topic.empty()) gt = o.gt_output;
    return o.output;
  }

  // A log that gives no frame at all is not an empty run: say what it holds instead.
  std::string noFrame() const {
    std::ostringstream os;
    os << "[rawlog] file = '" << file_ << "': no frame: it has no 2D laser scan";
    if (!laser_label_.empty()) os << " labelled '" << laser_label_ << "'";
    const std::vector<std::string> labels = reader_->laserLabels();
    if (!labels.empty()) {
      os << " (laser_label; labels in the file:";
      for (const auto& l : labels) os << " '" << l << "'";
      os << ")";
    }
    if (const std::size_t n = reader_->unused3dObservations())
      os << "; it holds 3D observations (" << n << "): scan_from_3d = true slices a 2D scan from them";
    return os.str();
  }

  std::nullopt_t end() {
    ended_ = true;
    return std::nullopt;
  }

  std::unique_ptr<asf::io::RawlogReader> reader_;
  std::vector<asf::io::GroundTruthPose> gt_;
  double max_gap_ = 0.5, last_t_ = 0;
  std::int64_t max_frames_ = 0, start_frame_ = 0, delivered_ = 0, skipped_ = 0;
  std::size_t clamped_ = 0;
  bool ended_ = false;
  std::string file_, laser_label_;
  std::string temp_, temp_gt_;  ///< a converted bag without an output folder (and its GT)

 public:
  ~RawlogSource() override {
    reader_.reset();
    if (!temp_.empty()) std::remove(temp_.c_str());
    if (!temp_gt_.empty()) std::remove(temp_gt_.c_str());
  }
};

const asf::KeySpec kKeys[] = {
    asf::keyPath(
        "file", nullptr,
        "Rawlog to replay: .rawlog or .rawlog.gz, action/sensory-frame or "
        "observation-only; or a ROS bag (ROS 1 .bag, rosbag2 folder, .db3 or .mcap; bag_* keys)"),
    asf::keyString("bag_scan_topic", "",
                   "ROS bag: the sensor_msgs/msg/LaserScan topic; empty: the bag's only one"),
    asf::keyString("bag_odom_topic", "",
                   "ROS bag: the nav_msgs/msg/Odometry topic; empty: the bag's only one; "
                   "none: no odometry"),
    asf::keyString("bag_base_frame", "",
                   "ROS bag: the robot's frame; empty: the odometry's child_frame_id, else "
                   "base_link"),
    asf::keyString("bag_gt_topic", "",
                   "ROS bag: a ground-truth topic (Odometry or PoseStamped) used as "
                   "ground_truth (written beside bag.rawlog as bag.gt.txt)"),
    asf::keyString("bag_laser_pose", "",
                   "ROS bag: the laser on the robot as 'X,Y,Z,YAW_DEG' instead of /tf_static"),
    asf::keyString("laser_label", "",
                   "sensorLabel of the 2D laser to use; empty: the first laser in the log"),
    asf::keyPath("ground_truth", "",
                 "Optional ground-truth file, lines 'timestamp x y phi' [s, m, m, rad]"),
    asf::keyDouble("ground_truth_max_gap", "0.5",
                   "No ground truth between GT lines farther apart than this [s]", 0, 1e6),
    asf::keyDouble("odo_a1", "0.01",
                   "Odometry model for logs without covariance: xy std per metre [m/m]", 0, 10),
    asf::keyDouble("odo_a2", "0.001", "Odometry model: xy std per degree turned [m/deg]", 0, 10),
    asf::keyDouble("odo_a3", "1.0", "Odometry model: heading std per metre [deg/m]", 0, 1000),
    asf::keyDouble("odo_a4", "0.05", "Odometry model: heading std per degree turned [deg/deg]", 0,
                   10),
    asf::keyDouble("odo_min_std_xy", "0.01", "Odometry model: xy std added to every step [m]", 0,
                   10),
    asf::keyDouble("odo_min_std_phi_deg", "0.2",
                   "Odometry model: heading std added to every step [deg]", 0, 180),
    asf::keyBool("observations3d", "false",
                 "Attach each step's 3D observations (point clouds, Velodyne, 3D range scans, "
                 "lasers other than laser_label) to the frame, for [pipeline] map3d"),
    asf::keyBool("scan_from_3d", "false",
                 "Frames come from the 3D sensor (label_3d); their 2D scan is a horizontal "
                 "slice of its points (for a robot without a 2D laser)"),
    asf::keyString("label_3d", "",
                   "sensorLabel of the 3D sensor for scan_from_3d; empty: the first one seen"),
    asf::keyDouble("slice_min_z", "0.1",
                   "scan_from_3d: bottom of the height band, above the robot base [m]", -100, 100),
    asf::keyDouble("slice_max_z", "1.0", "scan_from_3d: top of the height band [m]", -100, 100),
    asf::keyInt("slice_rays", "720", "scan_from_3d: rays of the sliced scan over 360 deg", 8,
                100000),
    asf::keyDouble("slice_max_range", "30.0", "scan_from_3d: points farther are left out [m]", 0.1,
                   1000),
    asf::keyInt("max_frames", "0", "Frames delivered before the stream ends; 0: all", 0, 1e12),
    asf::keyInt("start_frame", "0", "Frames of the log skipped before the first one delivered", 0,
                1e12),
};

}  // namespace

ASF_PLUGIN(
    RawlogSource, asf::PluginKind::Source, "rawlog", "1.0.0",
    "Replays an MRPT rawlog (plain or gz, both layouts) or a ROS 1 / ROS 2 bag, with optional "
    "ground truth",
    asf::ThreadSafety::ThreadCompatible, kKeys)
