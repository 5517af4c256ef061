#include <asf/errors.h>
#include <asf/studies/map3d_from_log.h>
#include <asf/text.h>
#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <chrono>

#include <asf/io/rawlog_guard.h>

namespace asf::studies {

namespace {

using Clock = std::chrono::steady_clock;

/// The robot pose of each observation: integrated odometry, or the ground truth.
struct PoseSource {
  const std::vector<io::GroundTruthPose>& gt;
  mrpt::poses::CPose2D odo;                     // action logs: composed increments
  std::optional<mrpt::poses::CPose2D> odo_abs;  // observation-only logs: last reading

  std::optional<mrpt::poses::CPose2D> at(const mrpt::obs::CObservation& o) const {
    if (!gt.empty()) return io::interpolateGroundTruth(gt, mrpt::Clock::toDouble(o.timestamp));
    return odo_abs ? *odo_abs : odo;
  }
};

class LogInserter {
 public:
  LogInserter(const Map3dFromLogOptions& o, mapping::Map3d& map,
              const std::function<void(const std::string&)>& progress)
      : o_(o), map_(map), progress_(progress), poses_{o.ground_truth, {}, {}} {}

  /// One record of the log: odometry, or observations to insert.
  void record(const mrpt::serialization::CSerializable::Ptr& obj) {
    if (auto acts = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj)) {
      if (auto mv = acts->getBestMovementEstimation())
        poses_.odo = poses_.odo + mv->poseChange->getMeanVal();
    } else if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj)) {
      for (const auto& ob : *sf)
        if (ob) observation(*ob);
    } else if (auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obj)) {
      poses_.odo_abs = odo->odometry;
    } else if (auto ob = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj)) {
      observation(*ob);
    }
  }
  Map3dFromLogReport r;

 private:
  void observation(const mrpt::obs::CObservation& ob) {
    const std::string cls = ob.GetRuntimeClass()->className;
    if (dynamic_cast<const mrpt::obs::CObservationOdometry*>(&ob)) return;
    const auto t0 = Clock::now();
    mrpt::poses::CPose3D sensor;
    std::string why;
    const bool has_points = mapping::Map3d::observationPoints(ob, pts_, sensor, &why);
    r.extract_s += secondsSince(t0);
    if (!has_points) {
      ++r.skipped[why];
      return;
    }
    // By class name: CObservationPointCloud lives in mrpt-maps.
    if (o_.sensor_pose &&
        (cls == "mrpt::obs::CObservationVelodyneScan" ||
         cls == "mrpt::obs::CObservationPointCloud" || cls == "mrpt::obs::CObservation3DRangeScan"))
      sensor = *o_.sensor_pose;
    const auto robot = poses_.at(ob);
    if (!robot) {
      ++r.skipped["no ground-truth pose at its time"];
      return;
    }
    if (!r.sensor_poses.count(ob.sensorLabel)) r.sensor_poses[ob.sensorLabel] = sensor.asString();
    const auto t1 = Clock::now();
    r.points += map_.insertPoints(pts_, mrpt::poses::CPose3D(*robot) + sensor);
    r.insert_s += secondsSince(t1);
    ++r.inserted_by_class[cls];
    ++r.observations;
    if (progress_ && secondsSince(last_progress_) >= 2.0) {
      last_progress_ = Clock::now();
      progress_("asf map3d: record " + std::to_string(r.records) + ", " +
                std::to_string(r.observations) + " observations, " + std::to_string(r.points) +
                " points inserted (" + formatFixed(r.points / std::max(r.insert_s, 1e-9), 0) +
                " points/s)");
    }
  }

  const Map3dFromLogOptions& o_;
  mapping::Map3d& map_;
  const std::function<void(const std::string&)>& progress_;
  PoseSource poses_;
  std::vector<Eigen::Vector3f> pts_;
  Clock::time_point last_progress_ = Clock::now();
};

}  // namespace

Map3dFromLogReport insertRawlog3d(const std::string& path, const Map3dFromLogOptions& o, mapping::Map3d& map,
                                  const std::function<void(const std::string&)>& progress) {
  mrpt::io::CFileGZInputStream in;
  bool ok = false;
  try {
    ok = in.open(path);
  } catch (const std::exception&) {
    // MRPT throws for a missing file instead of returning false.
  }
  if (!ok) throw InputError(path + ": cannot open the rawlog (missing or unreadable)");
  io::RawlogGuard guard(in);  // refuses records MRPT would crash on, as RawlogReader does
  auto ar = mrpt::serialization::archiveUniquePtrFrom(guard);
  LogInserter ins(o, map, progress);
  Map3dFromLogReport& r = ins.r;
  try {
    for (;;) {
      mrpt::serialization::CSerializable::Ptr obj;
      const auto t0 = Clock::now();
      const std::uint64_t record_start = guard.getPosition();
      try {
        obj = ar->ReadObject();
      } catch (const mrpt::serialization::CExceptionEOF&) {
        if (guard.getPosition() == record_start) break;  // a clean end: between records
        throw InputError(path + ": record " + std::to_string(r.records) +
                         ": the file ends inside this record (cut at byte " +
                         std::to_string(guard.getPosition()) + ")");
      } catch (const std::exception& e) {
        // MRPT wraps what the guard throws: its refusal says why.
        throw InputError(path + ": record " + std::to_string(r.records) + ": " +
                         (guard.refusal().empty() ? io::mrptExceptionCause(e.what()) : guard.refusal()));
      }
      r.read_s += secondsSince(t0);
      ++r.records;
      if (obj) ins.record(obj);
    }
  } catch (const Error& e) {
    // Keep what was inserted: the outputs cover the records before the error.
    r.error = e.what();
  }
  return r;
}

}  // namespace asf::studies
