#include <asf/errors.h>
#include <asf/place_recognition.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/slam/CICP.h>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <random>

namespace asf {

namespace {

std::uint64_t mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

/// Points of a scan in the robot frame (the scan's sensor pose applied), valid rays only.
void addScan(mrpt::maps::CSimplePointsMap& m, const mrpt::obs::CObservation2DRangeScan& s,
             const mrpt::poses::CPose2D& robot) {
  const mrpt::poses::CPose2D sensor = robot + mrpt::poses::CPose2D(s.sensorPose);
  for (std::size_t i = 0; i < s.getScanSize(); ++i) {
    if (!s.getScanRangeValidity(i)) continue;
    const double r = s.getScanRange(i), a = s.getScanAngle(i);
    double x, y;
    sensor.composePoint(r * std::cos(a), r * std::sin(a), x, y);
    m.insertPoint(static_cast<float>(x), static_cast<float>(y), 0.f);
  }
}

}  // namespace

double recognitionProbability(const PoseGraph& g, NodeId n, const RecognitionMcOptions& o) {
  if (n >= g.nodes.size() || !g.nodes[n].scan || o.samples <= 0) return 0;
  const PoseNode& node = g.nodes[n];
  mrpt::maps::CSimplePointsMap local;
  for (const PoseNode& other : g.nodes) {
    if (other.id == n || !other.scan) continue;
    if (std::hypot(other.pose.x() - node.pose.x(), other.pose.y() - node.pose.y()) > o.map_radius)
      continue;
    addScan(local, *other.scan, other.pose);
  }
  if (local.size() == 0) return 0;

  std::mt19937_64 rng(mix(o.seed ^ mix(static_cast<std::uint64_t>(n) + 1)));
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const auto& scan = *node.scan;
  const std::size_t rays = scan.getScanSize();
  mrpt::slam::CICP icp;
  icp.options.ICP_algorithm = mrpt::slam::icpLevenbergMarquardt;
  icp.options.maxIterations = 80;
  icp.options.thresholdDist = 0.75;
  icp.options.thresholdAng = 0.15;
  icp.options.smallestThresholdDist = 0.05;
  icp.options.doRANSAC = false;

  int ok = 0;
  for (int s = 0; s < o.samples; ++s) {
    // What the robot sees: the node's scan with a sector occluded and some clutter.
    mrpt::obs::CObservation2DRangeScan seen = scan;
    const std::size_t hidden = static_cast<std::size_t>(o.occlusion * u01(rng) * rays);
    const std::size_t first = rays ? static_cast<std::size_t>(u01(rng) * rays) % rays : 0;
    for (std::size_t k = 0; k < hidden; ++k) seen.setScanRangeValidity((first + k) % rays, false);
    for (std::size_t i = 0; i < rays; ++i)
      if (seen.getScanRangeValidity(i) && u01(rng) < o.clutter)
        seen.setScanRange(i, static_cast<float>(seen.getScanRange(i) * u01(rng)));
    mrpt::maps::CSimplePointsMap cur;
    addScan(cur, seen, mrpt::poses::CPose2D());
    if (cur.size() < 10) continue;  // nothing left to align: a failure
    // Where the robot believes it is: anywhere in the window around the node.
    const mrpt::poses::CPose2D guess(node.pose.x() + (2 * u01(rng) - 1) * o.half_x,
                                     node.pose.y() + (2 * u01(rng) - 1) * o.half_y,
                                     node.pose.phi() + (2 * u01(rng) - 1) * o.half_phi);
    mrpt::slam::CICP::TReturnInfo info;
    const auto pdf = icp.AlignPDF(&local, &cur, mrpt::poses::CPosePDFGaussian(guess), info);
    const mrpt::poses::CPose2D got = pdf->getMeanVal();
    const double dxy = std::hypot(got.x() - node.pose.x(), got.y() - node.pose.y());
    const double dphi = std::abs(mrpt::math::wrapToPi(got.phi() - node.pose.phi()));
    if (dxy <= o.success_xy && dphi <= o.success_phi) ++ok;
  }
  return static_cast<double>(ok) / o.samples;
}

void writeRecognitionProbabilities(const std::string& path, const std::map<NodeId, double>& p) {
  std::ofstream f(path);
  f << "# node_id p_recognition (Monte Carlo place recognition, asf)\n" << std::setprecision(6);
  for (const auto& [n, v] : p) f << n << ' ' << v << '\n';
  if (!f) throw Error(path + ": cannot write the recognition probabilities");
}

}  // namespace asf
