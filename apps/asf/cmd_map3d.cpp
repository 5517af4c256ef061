// asf map3d: a rawlog's 3D observations into an OctoMap octree at the robot poses (odometry
// or ground truth), with the 2D projection the pipeline uses, the .bt/.ot files and stats.
#include <asf/abi.h>
#include <asf/atomic_file.h>
#include <asf/config.h>
#include <asf/errors.h>
#include <asf/map3d.h>
#include <asf/rawlog_io.h>
#include <asf/run_report.h>
#include <asf/segmentation_eval.h>
#include <asf/text.h>
#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <tclap/CmdLine.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.h"
#include "plugin_cli.h"

namespace asf::app {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

/// The robot pose of each observation: integrated odometry, or the ground truth.
struct PoseSource {
  std::vector<GroundTruthPose> gt;
  mrpt::poses::CPose2D odo;                     // action logs: composed increments
  std::optional<mrpt::poses::CPose2D> odo_abs;  // observation-only logs: last reading

  std::optional<mrpt::poses::CPose2D> at(const mrpt::obs::CObservation& o) const {
    if (!gt.empty()) return interpolateGroundTruth(gt, mrpt::Clock::toDouble(o.timestamp));
    return odo_abs ? *odo_abs : odo;
  }
};

void writeTextAtomically(const std::string& path, const std::string& text) {
  writeFileAtomically(path, text);
}

}  // namespace

int cmdMap3d(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Builds a 3D occupancy map (OctoMap) from the 3D observations of a rawlog: "
      "CObservationPointCloud, CObservationVelodyneScan, CObservation3DRangeScan and 2D laser "
      "scans (3D points through their sensorPose, so tilted lasers too), each inserted at the "
      "robot pose of its time (integrated odometry of the log, or --gt), and projects it to "
      "the 2D occupancy grid of the pipeline (voxels in the robot's body band [map3d] "
      "min_height..max_height). Writes DIR/map3d.bt (octovis), DIR/map3d.ot, "
      "DIR/projected.png (free white, occupied black, unknown gray; row 0 = max y) and "
      "DIR/map3d.json (parameters, statistics, timings, points/s).",
      ' ', ASF_VERSION_STRING);
  TCLAP::UnlabeledValueArg<std::string> rawlog("rawlog", "MRPT rawlog (either layout, gz or not)",
                                               true, "", "RAWLOG", cmd);
  TCLAP::ValueArg<std::string> out("o", "out", "Output folder (created)", true, "", "DIR", cmd);
  TCLAP::ValueArg<std::string> config("c", "config",
                                      "INI file whose [map3d] section sets the keys (other "
                                      "sections are ignored)",
                                      false, "", "INI", cmd);
  TCLAP::MultiArg<std::string> set("s", "set", "map3d.key=value or key=value (repeatable)", false,
                                   "KEY=VALUE", cmd);
  TCLAP::ValueArg<std::string> gt("g", "gt",
                                  "Ground-truth file (t x y phi per line): robot poses from it "
                                  "instead of odometry; observations outside it are skipped",
                                  false, "", "GT.txt", cmd);
  TCLAP::ValueArg<std::string> sensor_pose(
      "", "sensor-pose",
      "Pose of the 3D sensor on the robot, replacing the observations' sensorPose (logs that "
      "store the identity): \"[x y z yaw pitch roll]\" in metres and degrees (MRPT's CPose3D "
      "text). z is the sensor's height above the floor. Applies to point clouds, Velodyne and "
      "3D range scans; 2D laser scans keep theirs",
      false, "", "POSE", cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);
  std::optional<mrpt::poses::CPose3D> sensor_override;
  if (!sensor_pose.getValue().empty()) {
    try {
      sensor_override = mrpt::poses::CPose3D::FromString(sensor_pose.getValue());
    } catch (const std::exception&) {
      throw ConfigError("--sensor-pose " + sensor_pose.getValue() +
                        ": expected \"[x y z yaw pitch roll]\" (metres, degrees)");
    }
  }

  IniConfig ini = config.getValue().empty() ? IniConfig::fromText("", "--set")
                                            : IniConfig::fromFile(config.getValue());
  for (const auto& a : set.getValue()) {
    const auto eq = a.find('='), dot = a.find('.');
    if (eq == std::string::npos) throw ConfigError("--set " + a + ": expected key=value");
    if (dot != std::string::npos && dot < eq && lowercase(a.substr(0, dot)) != "map3d")
      throw ConfigError("--set " + a + ": asf map3d has only the [map3d] section");
    ini.applyOverride(dot != std::string::npos && dot < eq ? a : "map3d." + a);
  }
  std::size_t nkeys = 0;
  const KeySpec* keys = Map3d::keys(nkeys);
  const Params params = ini.resolve("map3d", keys, nkeys);
  Map3d map;
  map.configure(params);

  PoseSource poses;
  if (!gt.getValue().empty()) poses.gt = readGroundTruth(gt.getValue());

  const std::string path = rawlog.getValue();
  mrpt::io::CFileGZInputStream in;
  bool ok = false;
  try {
    ok = in.open(path);
  } catch (const std::exception&) {
    // MRPT throws for a missing file instead of returning false.
  }
  if (!ok) throw InputError(path + ": cannot open the rawlog (missing or unreadable)");
  fs::create_directories(out.getValue());
  auto ar = mrpt::serialization::archiveUniquePtrFrom(in);

  std::map<std::string, std::size_t> inserted_by_class, skipped;  // class / reason -> count
  std::map<std::string, std::string> sensor_poses;                // label -> pose on the robot used
  std::size_t records = 0, observations = 0, points = 0;
  double t_read = 0, t_extract = 0, t_insert = 0;
  const auto t_start = Clock::now();
  auto last_progress = t_start;
  std::string error;
  std::vector<Eigen::Vector3f> pts;

  auto handle = [&](const mrpt::obs::CObservation& o) {
    const std::string cls = o.GetRuntimeClass()->className;
    if (dynamic_cast<const mrpt::obs::CObservationOdometry*>(&o)) return;
    const auto t0 = Clock::now();
    mrpt::poses::CPose3D sensor;
    std::string why;
    const bool has_points = Map3d::observationPoints(o, pts, sensor, &why);
    t_extract += secondsSince(t0);
    if (!has_points) {
      ++skipped[why];
      return;
    }
    // By class name: CObservationPointCloud lives in mrpt-maps, which the host does not use.
    if (sensor_override &&
        (cls == "mrpt::obs::CObservationVelodyneScan" ||
         cls == "mrpt::obs::CObservationPointCloud" || cls == "mrpt::obs::CObservation3DRangeScan"))
      sensor = *sensor_override;
    const auto robot = poses.at(o);
    if (!robot) {
      ++skipped["no ground-truth pose at its time"];
      return;
    }
    if (!sensor_poses.count(o.sensorLabel)) sensor_poses[o.sensorLabel] = sensor.asString();
    const auto t1 = Clock::now();
    points += map.insertPoints(pts, mrpt::poses::CPose3D(*robot) + sensor);
    t_insert += secondsSince(t1);
    ++inserted_by_class[cls];
    ++observations;
    if (secondsSince(last_progress) >= 2.0) {
      last_progress = Clock::now();
      std::cerr << "asf map3d: record " << records << ", " << observations << " observations, "
                << points << " points inserted ("
                << formatFixed(points / std::max(t_insert, 1e-9), 0) << " points/s)\n";
    }
  };

  try {
    for (;;) {
      mrpt::serialization::CSerializable::Ptr obj;
      const auto t0 = Clock::now();
      const std::uint64_t record_start = in.getPosition();
      try {
        obj = ar->ReadObject();
      } catch (const mrpt::serialization::CExceptionEOF&) {
        if (in.getPosition() == record_start) break;  // a clean end: between records
        throw InputError(path + ": record " + std::to_string(records) +
                         ": the file ends inside this record (cut at byte " +
                         std::to_string(in.getPosition()) + ")");
      } catch (const std::exception& e) {
        throw InputError(path + ": record " + std::to_string(records) + ": " +
                         mrptExceptionCause(e.what()));
      }
      t_read += secondsSince(t0);
      ++records;
      if (!obj) continue;
      if (auto acts = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj)) {
        if (auto mv = acts->getBestMovementEstimation())
          poses.odo = poses.odo + mv->poseChange->getMeanVal();
      } else if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj)) {
        for (const auto& o : *sf)
          if (o) handle(*o);
      } else if (auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obj)) {
        poses.odo_abs = odo->odometry;
      } else if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj)) {
        handle(*o);
      }
    }
  } catch (const Error& e) {
    // Keep what was inserted: the outputs cover the records before the error.
    error = e.what();
  }

  const auto t_proj0 = Clock::now();
  const GridMap grid = map.project();
  const double t_project = secondsSince(t_proj0);
  const std::string dir = out.getValue();
  const auto t_write0 = Clock::now();
  map.writeBt((fs::path(dir) / "map3d.bt").string());
  map.writeOt((fs::path(dir) / "map3d.ot").string());
  const GrayImage image = imageFromGrid(grid);  // empty without a grid
  if (grid.grid) writeGrayImage((fs::path(dir) / "projected.png").string(), image);
  const double t_write = secondsSince(t_write0);
  const Map3dStats s = map.stats();

  json j;
  j["rawlog"] = path;
  j["poses"] = gt.getValue().empty() ? "odometry" : "ground truth " + gt.getValue();
  json jp = json::object();
  for (const auto& [k, v] : params.values()) jp[k] = v.text;
  j["params"] = jp;
  j["records"] = records;
  j["observations_inserted"] = observations;
  j["inserted_by_class"] = inserted_by_class;
  j["skipped"] = skipped;
  j["sensor_poses"] = sensor_poses;
  j["stats"] = json::parse(s.toJson());
  j["timings_s"] = {{"read", t_read},     {"extract_points", t_extract},
                    {"insert", t_insert}, {"project", t_project},
                    {"write", t_write},   {"total", secondsSince(t_start)}};
  j["points_per_s"] = t_insert > 0 ? points / t_insert : 0.0;
  if (grid.grid)
    j["projected"] = {{"width", image.width},
                      {"height", image.height},
                      {"resolution", params.getDouble("project_resolution")},
                      {"x_min", grid.changed.min_x},
                      {"y_min", grid.changed.min_y}};
  j["complete"] = error.empty();
  if (!error.empty()) j["error"] = error;
  writeTextAtomically((fs::path(dir) / "map3d.json").string(), j.dump(2) + "\n");

  std::cout << path << ": " << records << " records, " << observations << " observations inserted, "
            << points << " points in " << formatFixed(t_insert, 3) << " s ("
            << formatFixed(t_insert > 0 ? points / t_insert : 0.0, 0) << " points/s)\n";
  for (const auto& [why, n] : skipped) std::cout << "skipped " << n << ": " << why << "\n";
  for (const auto& [label, pose] : sensor_poses)
    std::cout << "sensor " << (label.empty() ? "(no label)" : label) << " on the robot at " << pose
              << "\n";
  std::cout << "octree: " << s.occupied_leaves << " occupied / " << s.free_leaves
            << " free leaves, " << formatFixed(s.known_volume_m3, 2) << " m^3 known, "
            << formatFixed(s.memory_bytes / 1048576.0, 2) << " MiB\n";
  if (grid.grid)
    std::cout << "projected: " << image.width << " x " << image.height << " cells of "
              << params.getDouble("project_resolution") << " m\n";
  else
    std::cout << "projected: nothing (empty octree), projected.png not written\n";
  std::cout << "wrote " << dir << "/map3d.bt, map3d.ot, " << (grid.grid ? "projected.png, " : "")
            << "map3d.json\n";
  if (!error.empty()) {
    std::cerr << "asf map3d: error: " << error << " (the outputs cover the records before it)\n";
    return kError;
  }
  return kOk;
}

}  // namespace asf::app
