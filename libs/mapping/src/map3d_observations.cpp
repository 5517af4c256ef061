// What Map3d inserts of an observation: the 3D points of each MRPT observation type in the
// sensor frame, and the horizontal slice of them that a 2D front-end reads as a laser scan.
#include <asf/mapping/map3d.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CObservationRotatingScan.h>
#include <mrpt/obs/CObservationVelodyneScan.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace asf::mapping {

namespace {

using Points3 = std::vector<Eigen::Vector3f>;

/// MRPT's scan geometry: N rays evenly over the aperture, centred on the sensor's x axis.
void planarScanPoints(const mrpt::obs::CObservation2DRangeScan& s, Points3& pts) {
  const std::size_t n = s.getScanSize();
  const double a0 = -0.5 * s.aperture;
  const double da = n > 1 ? s.aperture / static_cast<double>(n - 1) : 0.0;
  pts.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!s.getScanRangeValidity(i)) continue;  // no return: no information
    double a = a0 + da * static_cast<double>(i);
    if (!s.rightToLeft) a = -a;
    const double r = s.getScanRange(i);
    pts.emplace_back(static_cast<float>(r * std::cos(a)), static_cast<float>(r * std::sin(a)),
                     0.0f);
  }
}

void velodynePoints(const mrpt::obs::CObservationVelodyneScan& s, Points3& pts) {
  const mrpt::obs::CObservationVelodyneScan::TPointCloud* pc = &s.point_cloud;
  mrpt::obs::CObservationVelodyneScan copy;
  if (pc->size() == 0 && !s.scan_packets.empty()) {
    copy = s;  // generatePointCloud() is not const; the caller's object stays as it was
    copy.generatePointCloud();
    pc = &copy.point_cloud;
  }
  pts.reserve(pc->size());
  for (std::size_t i = 0; i < pc->size(); ++i) pts.emplace_back(pc->x[i], pc->y[i], pc->z[i]);
}

/// The points of a depth camera's observation, or why there are none.
std::string rangeScan3dPoints(const mrpt::obs::CObservation3DRangeScan& s, Points3& pts) {
  s.load();
  if (s.hasPoints3D) {
    pts.reserve(s.points3D_x.size());
    for (std::size_t i = 0; i < s.points3D_x.size(); ++i)
      pts.emplace_back(s.points3D_x[i], s.points3D_y[i], s.points3D_z[i]);
    return "";
  }
  if (!s.hasRangeImage) return "CObservation3DRangeScan with neither points nor ranges";
  mrpt::obs::CObservation3DRangeScan copy = s;  // unprojectInto() loads, so it is not const
  mrpt::maps::CSimplePointsMap local;
  copy.unprojectInto(local);  // sensor frame: takeIntoAccountSensorPoseOnRobot = false
  const auto& xs = local.getPointsBufferRef_x();
  const auto& ys = local.getPointsBufferRef_y();
  const auto& zs = local.getPointsBufferRef_z();
  pts.reserve(xs.size());
  for (std::size_t i = 0; i < xs.size(); ++i) pts.emplace_back(xs[i], ys[i], zs[i]);
  return "";
}

/// One ring is a planar scan (MRPT's fromScan2D): azimuths from the first to the last column.
/// Several rings need their elevation angles, which MRPT 2.5 does not store: why not, then.
std::string rotatingScanPoints(const mrpt::obs::CObservationRotatingScan& s, Points3& pts) {
  if (s.rowCount != 1)
    return "CObservationRotatingScan with " + std::to_string(s.rowCount) +
           " rings is not supported: MRPT 2.5 stores no ring elevation angles in it "
           "(store the CObservationVelodyneScan or a CObservationPointCloud instead)";
  const std::size_t n = s.columnCount;
  const double da = n > 1 ? s.azimuthSpan / static_cast<double>(n - 1) : 0.0;
  for (std::size_t c = 0; c < n; ++c) {
    const auto raw = s.rangeImage(0, c);
    if (raw == 0) continue;  // no return
    const double r = raw * s.rangeResolution, a = s.startAzimuth + da * static_cast<double>(c);
    pts.emplace_back(static_cast<float>(r * std::cos(a)), static_cast<float>(r * std::sin(a)),
                     0.0f);
  }
  return "";
}

}  // namespace

bool Map3d::observationPoints(const mrpt::obs::CObservation& obs,
                              std::vector<Eigen::Vector3f>& pts,
                              mrpt::poses::CPose3D& sensor_on_robot, std::string* why) {
  using namespace mrpt::obs;
  pts.clear();
  auto fail = [&](const std::string& w) {
    if (why) *why = w;
    return false;
  };
  obs.getSensorPose(sensor_on_robot);
  if (const auto* s = dynamic_cast<const CObservation2DRangeScan*>(&obs)) {
    planarScanPoints(*s, pts);
    return true;
  }
  if (const auto* s = dynamic_cast<const CObservationPointCloud*>(&obs)) {
    s->load();
    if (!s->pointcloud) return fail("CObservationPointCloud without a point cloud");
    const auto& xs = s->pointcloud->getPointsBufferRef_x();
    const auto& ys = s->pointcloud->getPointsBufferRef_y();
    const auto& zs = s->pointcloud->getPointsBufferRef_z();
    pts.reserve(xs.size());
    for (std::size_t i = 0; i < xs.size(); ++i) pts.emplace_back(xs[i], ys[i], zs[i]);
    return true;
  }
  if (const auto* s = dynamic_cast<const CObservationVelodyneScan*>(&obs)) {
    velodynePoints(*s, pts);
    return true;
  }
  std::string no_points;
  if (const auto* s = dynamic_cast<const CObservation3DRangeScan*>(&obs))
    no_points = rangeScan3dPoints(*s, pts);
  else if (const auto* r = dynamic_cast<const CObservationRotatingScan*>(&obs))
    no_points = rotatingScanPoints(*r, pts);
  else
    no_points = std::string(obs.GetRuntimeClass()->className) + " has no 3D points";
  return no_points.empty() ? true : fail(no_points);
}

std::shared_ptr<mrpt::obs::CObservation2DRangeScan> horizontalSlice(
    const mrpt::obs::CObservation& obs, const SliceOptions& o, std::string* why) {
  std::vector<Eigen::Vector3f> pts;
  mrpt::poses::CPose3D sensor;
  if (!Map3d::observationPoints(obs, pts, sensor, why)) return nullptr;
  const int n = std::max(o.rays, 2);
  const double bin = 2 * M_PI / n;
  std::vector<float> range(static_cast<std::size_t>(n), std::numeric_limits<float>::infinity());
  for (const auto& p : pts) {
    if (!p.allFinite()) continue;
    double x, y, z;  // in the robot frame
    sensor.composePoint(p.x(), p.y(), p.z(), x, y, z);
    if (z < o.min_z || z > o.max_z) continue;
    const double dx = x - sensor.x(), dy = y - sensor.y();
    const double r = std::hypot(dx, dy);
    if (r > o.max_range || r <= 0) continue;
    int i = static_cast<int>(std::floor((std::atan2(dy, dx) + M_PI) / bin));
    i = std::clamp(i, 0, n - 1);
    range[static_cast<std::size_t>(i)] =
        std::min(range[static_cast<std::size_t>(i)], static_cast<float>(r));
  }
  auto scan = std::make_shared<mrpt::obs::CObservation2DRangeScan>();
  scan->aperture = static_cast<float>(2 * M_PI * (n - 1) / n);
  scan->rightToLeft = true;
  scan->maxRange = static_cast<float>(o.max_range);
  scan->sensorPose =
      mrpt::poses::CPose3D(sensor.x(), sensor.y(), 0.5 * (o.min_z + o.max_z), 0, 0, 0);
  scan->sensorLabel = obs.sensorLabel + "_SLICE";
  scan->timestamp = obs.timestamp;
  scan->resizeScan(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const float r = range[static_cast<std::size_t>(i)];
    const bool valid = std::isfinite(r);
    scan->setScanRange(static_cast<std::size_t>(i), valid ? r : static_cast<float>(o.max_range));
    scan->setScanRangeValidity(static_cast<std::size_t>(i), valid);
  }
  return scan;
}

}  // namespace asf::mapping
