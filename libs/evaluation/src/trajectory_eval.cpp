#include <asf/errors.h>
#include <asf/evaluation/trajectory_eval.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace asf::evaluation {

using mrpt::poses::CPose2D;

CPose2D alignSE2(const std::vector<CPose2D>& a, const std::vector<CPose2D>& b) {
  if (a.empty() || a.size() != b.size())
    throw Error("alignSE2: needs as many target as source poses, at least one");
  const double n = static_cast<double>(a.size());
  double ax = 0, ay = 0, bx = 0, by = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ax += a[i].x(), ay += a[i].y(), bx += b[i].x(), by += b[i].y();
  }
  ax /= n, ay /= n, bx /= n, by /= n;
  // The optimal rotation angle is atan2 of the summed cross and dot products of the centred
  // point sets (the 2D case of Kabsch, where the SVD reduces to one angle).
  double sdot = 0, scross = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double px = a[i].x() - ax, py = a[i].y() - ay;
    const double qx = b[i].x() - bx, qy = b[i].y() - by;
    sdot += px * qx + py * qy;
    scross += px * qy - py * qx;
  }
  const double th = (sdot == 0 && scross == 0) ? 0.0 : std::atan2(scross, sdot);
  const double c = std::cos(th), s = std::sin(th);
  return CPose2D(bx - (c * ax - s * ay), by - (s * ax + c * ay), th);
}

TrajectoryError evaluateMatched(const std::vector<CPose2D>& est, const std::vector<CPose2D>& gt,
                                bool align) {
  if (est.empty() || est.size() != gt.size())
    throw Error("trajectory evaluation: no estimated pose has a ground-truth match");
  TrajectoryError r;
  r.poses = est.size();
  r.aligned = align;
  r.alignment = align ? alignSE2(est, gt) : CPose2D();
  double s2 = 0, s = 0, mx = 0, r2 = 0;
  for (std::size_t i = 0; i < est.size(); ++i) {
    const CPose2D p = r.alignment + est[i];
    const double e = std::hypot(p.x() - gt[i].x(), p.y() - gt[i].y());
    s2 += e * e, s += e, mx = std::max(mx, e);
    r.errors_m.push_back(e);
    const double dphi = mrpt::math::wrapToPi(p.phi() - gt[i].phi());
    r2 += dphi * dphi;
  }
  const double n = static_cast<double>(est.size());
  r.ate_rmse_m = std::sqrt(s2 / n);
  r.ate_mean_m = s / n;
  r.ate_max_m = mx;
  r.rot_rmse_deg = mrpt::RAD2DEG(std::sqrt(r2 / n));
  return r;
}

RelativePoseError relativePoseError(const std::vector<CPose2D>& est, const std::vector<CPose2D>& gt,
                                    std::size_t delta) {
  if (est.size() != gt.size() || delta == 0 || est.size() < delta + 1)
    throw Error("relative pose error: needs as many estimated as true poses, more than delta (" +
                std::to_string(delta) + ")");
  RelativePoseError r;
  double t2 = 0, r2 = 0;
  for (std::size_t i = 0; i + delta < est.size(); ++i) {
    const CPose2D moved_est = est[i + delta] - est[i];  // est_i^-1 (+) est_{i+delta}
    const CPose2D moved_gt = gt[i + delta] - gt[i];
    const CPose2D e = moved_est - moved_gt;
    const double t = std::hypot(e.x(), e.y()), a = mrpt::math::wrapToPi(e.phi());
    t2 += t * t, r2 += a * a;
    r.trans_max_m = std::max(r.trans_max_m, t);
    ++r.pairs;
  }
  r.trans_rmse_m = std::sqrt(t2 / r.pairs);
  r.rot_rmse_deg = mrpt::RAD2DEG(std::sqrt(r2 / r.pairs));
  return r;
}

TrajectoryError evaluateTrajectory(const std::vector<TimedPose>& estimate,
                                   const std::vector<io::GroundTruthPose>& ground_truth,
                                   double max_gap, bool align) {
  std::vector<CPose2D> est, gt;
  std::vector<double> times;
  std::size_t unmatched = 0;
  for (const TimedPose& p : estimate) {
    const auto g = io::interpolateGroundTruth(ground_truth, p.t, max_gap);
    if (!g) {
      ++unmatched;
      continue;
    }
    est.push_back(p.pose);
    gt.push_back(*g);
    times.push_back(p.t);
  }
  TrajectoryError r = evaluateMatched(est, gt, align);
  r.times = std::move(times);
  r.unmatched = unmatched;
  return r;
}

std::vector<TimedPose> readTrajectory(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw InputError(path + ": cannot open trajectory");
  std::vector<TimedPose> out;
  std::string line;
  int ln = 0;
  while (std::getline(f, line)) {
    ++ln;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#' || line[first] == '%') continue;
    std::istringstream is(line);
    double t = 0, x = 0, y = 0, phi = 0;
    if (!(is >> t >> x >> y >> phi) || !std::isfinite(t) || !std::isfinite(x) ||
        !std::isfinite(y) || !std::isfinite(phi))
      throw InputError(path + ":" + std::to_string(ln) +
                       ": expected 't x y phi' (seconds, metres, radians)");
    out.push_back({t, CPose2D(x, y, phi)});
  }
  return out;
}

}  // namespace asf::evaluation
