// asf map3d: a rawlog's 3D observations into an OctoMap octree at the robot poses (odometry
// or ground truth), with the 2D projection the pipeline uses, the .bt/.ot files and stats
// (asf/studies/map3d_from_log.h does the insertion; this file parses arguments and writes).
#include <asf/abi.h>
#include <asf/atomic_file.h>
#include <asf/config.h>
#include <asf/errors.h>
#include <asf/io/image_io.h>
#include <asf/mapping/map3d.h>
#include <asf/studies/map3d_from_log.h>
#include <asf/evaluation/segmentation_eval.h>
#include <asf/text.h>
#include <tclap/CmdLine.h>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "plugin_cli.h"

namespace asf::app {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

std::optional<mrpt::poses::CPose3D> parseSensorPose(const std::string& text) {
  if (text.empty()) return std::nullopt;
  try {
    return mrpt::poses::CPose3D::FromString(text);
  } catch (const std::exception&) {
    throw ConfigError("--sensor-pose " + text +
                      ": expected \"[x y z yaw pitch roll]\" (metres, degrees)");
  }
}

/// The [map3d] keys: the INI's section (if any) with the --set overrides.
Params map3dParams(const std::string& config, const std::vector<std::string>& sets) {
  IniConfig ini = config.empty() ? IniConfig::fromText("", "--set") : IniConfig::fromFile(config);
  for (const auto& a : sets) {
    const auto eq = a.find('='), dot = a.find('.');
    if (eq == std::string::npos) throw ConfigError("--set " + a + ": expected key=value");
    if (dot != std::string::npos && dot < eq && lowercase(a.substr(0, dot)) != "map3d")
      throw ConfigError("--set " + a + ": asf map3d has only the [map3d] section");
    ini.applyOverride(dot != std::string::npos && dot < eq ? a : "map3d." + a);
  }
  std::size_t nkeys = 0;
  const KeySpec* keys = mapping::Map3d::keys(nkeys);
  return ini.resolve("map3d", keys, nkeys);
}

/// What map3d.json holds besides the timings of projection and writing.
json reportJson(const std::string& rawlog, const std::string& gt, const Params& params,
                const studies::Map3dFromLogReport& r, const mapping::Map3dStats& s) {
  json j;
  j["rawlog"] = rawlog;
  j["poses"] = gt.empty() ? "odometry" : "ground truth " + gt;
  json jp = json::object();
  for (const auto& [k, v] : params.values()) jp[k] = v.text;
  j["params"] = jp;
  j["records"] = r.records;
  j["observations_inserted"] = r.observations;
  j["inserted_by_class"] = r.inserted_by_class;
  j["skipped"] = r.skipped;
  j["sensor_poses"] = r.sensor_poses;
  j["stats"] = json::parse(s.toJson());
  j["points_per_s"] = r.insert_s > 0 ? r.points / r.insert_s : 0.0;
  j["complete"] = r.error.empty();
  if (!r.error.empty()) j["error"] = r.error;
  return j;
}

void printSummary(const std::string& rawlog, const std::string& dir, const Params& params,
                  const studies::Map3dFromLogReport& r, const mapping::Map3dStats& s,
                  const GridMap& grid, const io::GrayImage& image) {
  std::cout << rawlog << ": " << r.records << " records, " << r.observations
            << " observations inserted, " << r.points << " points in " << formatFixed(r.insert_s, 3)
            << " s (" << formatFixed(r.insert_s > 0 ? r.points / r.insert_s : 0.0, 0)
            << " points/s)\n";
  for (const auto& [why, n] : r.skipped) std::cout << "skipped " << n << ": " << why << "\n";
  for (const auto& [label, pose] : r.sensor_poses)
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
  studies::Map3dFromLogOptions o;
  o.sensor_pose = parseSensorPose(sensor_pose.getValue());
  const Params params = map3dParams(config.getValue(), set.getValue());
  mapping::Map3d map;
  map.configure(params);
  if (!gt.getValue().empty()) o.ground_truth = io::readGroundTruth(gt.getValue());

  const auto t_start = Clock::now();
  const studies::Map3dFromLogReport r = studies::insertRawlog3d(
      rawlog.getValue(), o, map, [](const std::string& line) { std::cerr << line << "\n"; });
  const std::string dir = out.getValue();
  fs::create_directories(dir);
  const auto t_proj0 = Clock::now();
  const GridMap grid = map.project();
  const double t_project = secondsSince(t_proj0);
  const auto t_write0 = Clock::now();
  map.writeBt((fs::path(dir) / "map3d.bt").string());
  map.writeOt((fs::path(dir) / "map3d.ot").string());
  const io::GrayImage image = io::imageFromGrid(grid);  // empty without a grid
  if (grid.grid) io::writeGrayImage((fs::path(dir) / "projected.png").string(), image);
  const double t_write = secondsSince(t_write0);
  const mapping::Map3dStats s = map.stats();

  json j = reportJson(rawlog.getValue(), gt.getValue(), params, r, s);
  j["timings_s"] = {{"read", r.read_s},     {"extract_points", r.extract_s},
                    {"insert", r.insert_s}, {"project", t_project},
                    {"write", t_write},     {"total", secondsSince(t_start)}};
  if (grid.grid)
    j["projected"] = {{"width", image.width},
                      {"height", image.height},
                      {"resolution", params.getDouble("project_resolution")},
                      {"x_min", grid.changed.min_x},
                      {"y_min", grid.changed.min_y}};
  writeFileAtomically((fs::path(dir) / "map3d.json").string(), j.dump(2) + "\n");
  printSummary(rawlog.getValue(), dir, params, r, s, grid, image);
  if (!r.error.empty()) {
    std::cerr << "asf map3d: error: " << r.error << " (the outputs cover the records before it)\n";
    return kError;
  }
  return kOk;
}

}  // namespace asf::app
