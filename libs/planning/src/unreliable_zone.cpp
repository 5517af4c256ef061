#include <asf/errors.h>
#include <asf/io/rawlog_io.h>
#include <asf/sensor_frame.h>
#include <asf/planning/unreliable_zone.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>
#include <utility>

namespace asf::planning {

KeyframeLog readKeyframeLog(const std::string& rawlog, const std::vector<double>& keyframe_times,
                            const std::string& laser_label, double tolerance) {
  KeyframeLog out;
  const std::size_t n = keyframe_times.size();
  out.scan.resize(n);
  out.odometry.assign(n, mrpt::poses::CPose2D());
  out.odometry_cov.assign(n, Eigen::Matrix3d::Zero());
  io::RawlogReaderOptions ro;
  ro.laser_label = laser_label;
  io::RawlogReader reader(rawlog, ro);
  mrpt::poses::CPose2D acc;
  Eigen::Matrix3d acc_cov = Eigen::Matrix3d::Zero();
  std::size_t next = 0;
  double last_t = -INFINITY;
  while (next < n) {
    std::optional<SensorFrame> f = reader.next();
    if (!f) break;
    ++out.frames_read;
    last_t = f->timestamp;
    if (next > 0) {
      // The increment of every frame after node next-1 up to and including node next's.
      Eigen::Matrix3d c;
      acc = composeWithCov(acc, acc_cov, f->odometry, f->odometry_cov, c);
      acc_cov = c;
    }
    const double want = keyframe_times[next];
    if (std::abs(f->timestamp - want) > tolerance) {
      if (f->timestamp > want + tolerance) break;  // passed it: no frame has that time
      continue;
    }
    out.scan[next] = f->scan;
    if (next > 0) {
      out.odometry[next] = acc;
      out.odometry_cov[next] = acc_cov;
    }
    acc = mrpt::poses::CPose2D();
    acc_cov.setZero();
    ++next;
  }
  if (next < n) {
    std::ostringstream os;
    os.precision(17);
    os << rawlog << ": no frame at node " << next << "'s time " << keyframe_times[next] << " s ("
       << out.frames_read << " frames read, the last at " << last_t
       << " s): not the log of this run, or keyframe times not increasing";
    throw InputError(os.str());
  }
  return out;
}

PoseGraph readRunWithScans(const std::string& graph_file, std::string keyframes_file,
                           const std::string& rawlog, const std::string& laser_label,
                           KeyframeLog* log) {
  PoseGraph g = readG2o(graph_file);
  if (keyframes_file.empty())
    keyframes_file = (std::filesystem::path(graph_file).parent_path() / "keyframes.txt").string();
  const std::vector<io::GroundTruthPose> rows = io::readGroundTruth(keyframes_file);
  if (rows.size() != g.size())
    throw InputError(keyframes_file + ": " + std::to_string(rows.size()) + " keyframes for the " +
                     std::to_string(g.size()) + " nodes of " + graph_file);
  std::vector<double> times;
  for (const auto& r : rows) times.push_back(r.t);
  KeyframeLog k = readKeyframeLog(rawlog, times, laser_label);
  for (NodeId v = 0; v < g.size(); ++v) {
    g.nodes[v].scan = k.scan[v];
    g.nodes[v].timestamp = times[v];
  }
  if (log) *log = std::move(k);
  return g;
}

namespace {

/// An edge between consecutive keyframes that is not a loop closure: what the robot's
/// odometry gives when the scans are gone.
bool sequential(const PoseEdge& e) {
  return (e.from + 1 == e.to || e.to + 1 == e.from) && e.kind != EdgeKind::LoopClosure;
}

/// The consecutive edge (i-1, i) as the zone leaves it.
PoseEdge zoneEdge(const PoseEdge& e, const ZoneMaskOptions& o, const KeyframeLog* log) {
  static const mapping::OdometryNoiseModel model;
  const Eigen::Matrix3d floor = 1e-12 * Eigen::Matrix3d::Identity();
  PoseEdge out = e;
  switch (o.covariance) {
    case ZoneCovariance::WheelOdometry: {
      const NodeId to = std::max(e.from, e.to);
      out.from = to - 1;
      out.to = to;
      out.mean = log->odometry[to];
      out.information = edgeInformation(out.mean, o.factor * log->odometry_cov[to], floor);
      out.kind = EdgeKind::Odometry;
      break;
    }
    case ZoneCovariance::OdometryModel:
      out.information = edgeInformation(e.mean, o.factor * model.covariance(e.mean), floor);
      out.kind = EdgeKind::Odometry;
      break;
    case ZoneCovariance::Scaled:
      out.information = e.information / o.factor;
      break;
  }
  return out;
}

}  // namespace

PoseGraph maskZone(const PoseGraph& g, const std::vector<char>& in_zone, const ZoneMaskOptions& o,
                   const KeyframeLog* log, ZoneMaskReport* report) {
  const std::size_t n = g.size();
  if (in_zone.size() != n)
    throw Error("maskZone: in_zone has " + std::to_string(in_zone.size()) + " entries for " +
                std::to_string(n) + " nodes");
  if (o.covariance == ZoneCovariance::WheelOdometry &&
      (!log || log->odometry.size() != n || log->odometry_cov.size() != n))
    throw Error(
        "maskZone: wheel-odometry zone edges need the run's log, one "
        "entry per node");
  ZoneMaskReport r;
  PoseGraph out = g;
  out.edges.clear();
  for (NodeId v = 0; v < n; ++v) {
    if (!in_zone[v]) continue;
    ++r.zone_nodes;
    if (out.nodes[v].scan) ++r.scans_removed;
    out.nodes[v].scan.reset();
  }
  std::set<NodeId> replaced;  // the later node of each consecutive pair already emitted
  for (const PoseEdge& e : g.edges) {
    const bool a = e.from < n && in_zone[e.from], b = e.to < n && in_zone[e.to];
    if (!(o.touching ? (a || b) : (a && b))) {
      out.edges.push_back(e);
      continue;
    }
    if (!sequential(e)) {
      if (o.drop_loop_closures) {
        ++r.loop_closures_dropped;
        continue;
      }
      // Graph-only variants: the log has no odometry between non-consecutive nodes.
      ZoneMaskOptions oc = o;
      if (oc.covariance == ZoneCovariance::WheelOdometry) oc.covariance = ZoneCovariance::Scaled;
      out.edges.push_back(zoneEdge(e, oc, log));
      ++r.edges_replaced;
      continue;
    }
    // With the log, a consecutive pair gets one odometry edge, whatever the run had there.
    if (o.covariance == ZoneCovariance::WheelOdometry &&
        !replaced.insert(std::max(e.from, e.to)).second) {
      ++r.duplicate_edges_dropped;
      continue;
    }
    out.edges.push_back(zoneEdge(e, o, log));
    ++r.edges_replaced;
  }
  ++out.revision;
  if (report) *report = r;
  return out;
}

}  // namespace asf::planning
