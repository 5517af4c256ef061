#include <asf/atomic_file.h>
#include <asf/errors.h>
#include <asf/planning/place_recognition.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/slam/CICP.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <mutex>
#include <thread>
#include <sstream>
#include <iomanip>
#include <random>

namespace asf::planning {

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

std::vector<std::pair<float, float>> pointsOf(const mrpt::maps::CSimplePointsMap& m) {
  std::vector<std::pair<float, float>> out;
  out.reserve(m.size());
  for (std::size_t i = 0; i < m.size(); ++i) {
    float x, y;
    m.getPoint(i, x, y);
    out.emplace_back(x, y);
  }
  return out;
}

}  // namespace

RecognitionTrial recognitionTrial(const PoseGraph& g, NodeId n, const RecognitionMcOptions& o) {
  RecognitionTrial t;
  t.node = n;
  if (n >= g.nodes.size() || !g.nodes[n].scan || o.samples <= 0) return t;
  const PoseNode& node = g.nodes[n];
  mrpt::maps::CSimplePointsMap local;
  for (const PoseNode& other : g.nodes) {
    if (other.id == n || !other.scan) continue;
    if (std::hypot(other.pose.x() - node.pose.x(), other.pose.y() - node.pose.y()) > o.map_radius)
      continue;
    addScan(local, *other.scan, other.pose);
  }
  if (local.size() == 0) return t;
  t.map_points = pointsOf(local);
  {
    mrpt::maps::CSimplePointsMap own;
    addScan(own, *node.scan, node.pose);
    t.scan_points = pointsOf(own);
  }

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
    RecognitionSample rs;
    if (cur.size() < 10) {  // nothing left to align: a failure
      rs.aligned = false;
      rs.guess = rs.result = node.pose;
      t.samples.push_back(rs);
      continue;
    }
    // Where the robot believes it is: anywhere in the window around the node.
    rs.guess = mrpt::poses::CPose2D(node.pose.x() + (2 * u01(rng) - 1) * o.half_x,
                                    node.pose.y() + (2 * u01(rng) - 1) * o.half_y,
                                    node.pose.phi() + (2 * u01(rng) - 1) * o.half_phi);
    mrpt::slam::CICP::TReturnInfo info;
    const auto pdf = icp.AlignPDF(&local, &cur, mrpt::poses::CPosePDFGaussian(rs.guess), info);
    rs.result = pdf->getMeanVal();
    const double dxy = std::hypot(rs.result.x() - node.pose.x(), rs.result.y() - node.pose.y());
    const double dphi = std::abs(mrpt::math::wrapToPi(rs.result.phi() - node.pose.phi()));
    rs.success = dxy <= o.success_xy && dphi <= o.success_phi;
    ok += rs.success;
    t.samples.push_back(rs);
  }
  t.p = static_cast<double>(ok) / o.samples;
  return t;
}

double recognitionProbability(const PoseGraph& g, NodeId n, const RecognitionMcOptions& o) {
  return recognitionTrial(g, n, o).p;
}

std::vector<double> recognitionProbabilities(
    const PoseGraph& g, const RecognitionMcOptions& o, unsigned threads,
    const std::function<void(std::size_t, std::size_t)>& progress) {
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  std::vector<double> pr(g.size(), 0.0);
  std::atomic<std::size_t> done{0};
  std::mutex report;
  std::vector<std::exception_ptr> failed(threads);
  auto work = [&](unsigned first) {
    try {
      for (std::size_t v = first; v < g.size(); v += threads) {
        pr[v] = recognitionProbability(g, static_cast<NodeId>(v), o);
        const std::size_t k = ++done;
        if (progress && k % 100 == 0) {
          std::lock_guard<std::mutex> lock(report);
          progress(k, g.size());
        }
      }
    } catch (...) {
      failed[first] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work, t);
  work(0);
  for (auto& t : pool) t.join();
  for (const auto& f : failed)
    if (f) std::rethrow_exception(f);
  return pr;
}

void writeRecognitionProbabilities(const std::string& path, const std::map<NodeId, double>& p) {
  std::ostringstream f;
  f << "# node_id p_recognition (Monte Carlo place recognition, asf)\n" << std::setprecision(6);
  for (const auto& [n, v] : p) f << n << ' ' << v << '\n';
  writeFileAtomically(path, f.str(), "recognition probabilities");
}

}  // namespace asf::planning
