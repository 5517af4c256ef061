#include "scan_matcher.h"

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/slam/CICP.h>

#include <Eigen/Dense>
#include <cmath>
#include <nanoflann.hpp>
#include <unordered_map>

namespace asf::icp_graph {

namespace {
constexpr double kDeg = M_PI / 180.0;
// Normal estimation: neighbours within this radius [m]; a neighbourhood is line-like when its
// smaller spread is below this fraction of the larger one.
constexpr double kLineRatio = 0.1;
}  // namespace

/// The cloud's points as nanoflann sees them. The vectors' buffers are read through pointers
/// taken at build time; the index is dropped whenever the points change or move.
struct Cloud::Index {
  struct Points {
    const float* x;
    const float* y;
    std::size_t n;
    std::size_t kdtree_get_point_count() const { return n; }
    float kdtree_get_pt(std::size_t i, std::size_t dim) const { return dim == 0 ? x[i] : y[i]; }
    template <class Box>
    bool kdtree_get_bbox(Box&) const {
      return false;
    }
  };
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Points>,
                                                   Points, 2, std::size_t>;
  explicit Index(const Points& p) : points(p), tree(2, points, {10}) {}
  Points points;
  Tree tree;
};

Cloud::Cloud() = default;
Cloud::~Cloud() = default;
Cloud::Cloud(Cloud&& o) noexcept
    : x_(std::move(o.x_)),
      y_(std::move(o.y_)),
      map_(std::move(o.map_)),
      normals_(std::move(o.normals_)),
      normal_done_(std::move(o.normal_done_)),
      normals_ok_(o.normals_ok_),
      normal_k_(o.normal_k_),
      normal_radius_(o.normal_radius_) {
  o.dropCaches();
}
Cloud& Cloud::operator=(Cloud&& o) noexcept {
  x_ = std::move(o.x_);
  y_ = std::move(o.y_);
  map_ = std::move(o.map_);
  index_.reset();
  normals_ = std::move(o.normals_);
  normal_done_ = std::move(o.normal_done_);
  normals_ok_ = o.normals_ok_;
  normal_k_ = o.normal_k_;
  normal_radius_ = o.normal_radius_;
  o.dropCaches();
  return *this;
}

void Cloud::dropCaches() {
  map_.reset();
  index_.reset();
  normals_ok_ = false;
}

Cloud Cloud::fromScan(const mrpt::obs::CObservation2DRangeScan& scan) {
  Cloud c;
  mrpt::maps::CSimplePointsMap m;
  // Keep every valid return: the default 2 cm thinning would bias the residual statistics.
  m.insertionOptions.minDistBetweenLaserPoints = 0;
  m.loadFromRangeScan(scan);
  const auto& xs = m.getPointsBufferRef_x();
  const auto& ys = m.getPointsBufferRef_y();
  c.x_.assign(xs.begin(), xs.end());
  c.y_.assign(ys.begin(), ys.end());
  return c;
}

Cloud Cloud::fromPoints(const std::vector<float>& x, const std::vector<float>& y) {
  Cloud c;
  const std::size_t n = std::min(x.size(), y.size());
  c.x_.assign(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(n));
  c.y_.assign(y.begin(), y.begin() + static_cast<std::ptrdiff_t>(n));
  return c;
}

void Cloud::add(const Cloud& other, const mrpt::poses::CPose2D& pose) {
  const double c = std::cos(pose.phi()), s = std::sin(pose.phi());
  x_.reserve(x_.size() + other.size());
  y_.reserve(y_.size() + other.size());
  for (std::size_t i = 0; i < other.size(); ++i) {
    x_.push_back(static_cast<float>(pose.x() + c * other.x_[i] - s * other.y_[i]));
    y_.push_back(static_cast<float>(pose.y() + s * other.x_[i] + c * other.y_[i]));
  }
  dropCaches();
}

void Cloud::thin(double cell) {
  if (!(cell > 0) || x_.empty()) return;
  // Cell -> its slot in the output (order of first occurrence), then the mean of its points.
  std::unordered_map<std::uint64_t, std::size_t> slot;
  slot.reserve(x_.size());
  std::vector<double> sx, sy;
  std::vector<int> count;
  for (std::size_t i = 0; i < x_.size(); ++i) {
    const auto cx = static_cast<std::int64_t>(std::floor(x_[i] / cell));
    const auto cy = static_cast<std::int64_t>(std::floor(y_[i] / cell));
    const std::uint64_t key = (static_cast<std::uint64_t>(cx) << 32) ^
                              static_cast<std::uint64_t>(static_cast<std::uint32_t>(cy));
    const auto [it, fresh] = slot.emplace(key, sx.size());
    if (fresh) sx.push_back(0), sy.push_back(0), count.push_back(0);
    sx[it->second] += x_[i];
    sy[it->second] += y_[i];
    ++count[it->second];
  }
  x_.resize(sx.size());
  y_.resize(sy.size());
  for (std::size_t k = 0; k < sx.size(); ++k) {
    x_[k] = static_cast<float>(sx[k] / count[k]);
    y_[k] = static_cast<float>(sy[k] / count[k]);
  }
  dropCaches();
}

std::size_t Cloud::size() const { return x_.size(); }

const mrpt::maps::CSimplePointsMap& Cloud::map() const {
  if (!map_) {
    map_ = std::make_unique<mrpt::maps::CSimplePointsMap>();
    map_->reserve(size());
    for (std::size_t i = 0; i < size(); ++i) map_->insertPointFast(x_[i], y_[i], 0);
    map_->mark_as_modified();
  }
  return *map_;
}

const Cloud::Index& Cloud::index() const {
  if (!index_) index_ = std::make_unique<Index>(Index::Points{x_.data(), y_.data(), size()});
  return *index_;
}

std::size_t Cloud::nearest(float x, float y, float& d2) const {
  const float q[2] = {x, y};
  std::size_t k = 0;
  index().tree.knnSearch(q, 1, &k, &d2);
  return k;
}

Eigen::Vector2d Cloud::normal(std::size_t i) const {
  // Per point on first use: a match only asks for the normals of the reference points
  // nearest to the current scan, a small part of a multi-keyframe submap.
  if (!normals_ok_) {
    normals_.assign(size(), Eigen::Vector2d::Zero());
    normal_done_.assign(size(), 0);
    normals_ok_ = true;
  }
  if (!normal_done_[i]) {
    normals_[i] = computeNormal(i);
    normal_done_[i] = 1;
  }
  return normals_[i];
}

Eigen::Vector2d Cloud::computeNormal(std::size_t i) const {
  std::vector<std::size_t> idx(normal_k_);
  std::vector<float> nd(normal_k_);
  const float q[2] = {x_[i], y_[i]};
  const std::size_t found = index().tree.knnSearch(q, normal_k_, idx.data(), nd.data());
  const double r2 = normal_radius_ * normal_radius_;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  int n = 0;
  for (std::size_t k = 0; k < found; ++k)
    if (nd[k] <= r2) mean += Eigen::Vector2d(x_[idx[k]], y_[idx[k]]), ++n;
  if (n < 4) return Eigen::Vector2d::Zero();
  mean /= n;
  Eigen::Matrix2d S = Eigen::Matrix2d::Zero();
  for (std::size_t k = 0; k < found; ++k)
    if (nd[k] <= r2) {
      const Eigen::Vector2d d = Eigen::Vector2d(x_[idx[k]], y_[idx[k]]) - mean;
      S += d * d.transpose();
    }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(S);
  const auto ev = es.eigenvalues();  // ascending
  if (ev(1) <= 0 || ev(0) > kLineRatio * kLineRatio * ev(1)) return Eigen::Vector2d::Zero();
  return es.eigenvectors().col(0).normalized();
}

namespace {
struct Residuals {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();  ///< J^T J
  Eigen::Vector3d b = Eigen::Vector3d::Zero();  ///< J^T r
  double sum_r2 = 0;                            ///< the cost (robust when a kernel is used)
  double sum_plain = 0;                         ///< plain sum of squared residuals
  std::size_t rows = 0, inliers = 0;
};

/// Which points of the current cloud count and how far their correspondence may be: every
/// `stride`-th point, within `dist` + `per_metre` x its range (CICP's thresholdDist and
/// thresholdAng).
struct Selection {
  std::size_t stride = 1;
  double per_metre = 0;
};

/// Residuals of `cur` placed at `pose` against `ref`: point-to-line against the reference's
/// local line where it has one (so a corridor leaves the along-wall direction unconstrained),
/// point-to-point else; only points within `inlier_dist` of the reference count. With
/// kernel_c > 0 each row is weighted by the Cauchy kernel w = 1 / (1 + (r/c)^2) (IRLS) and
/// sum_r2 holds the robust cost sum c^2 log(1 + (r/c)^2) instead of sum r^2.
Residuals residuals(const Cloud& ref, const Cloud& cur, const mrpt::poses::CPose2D& pose,
                    double inlier_dist, double kernel_c = 0, std::vector<double>* abs_res = nullptr,
                    const Selection& sel = {}) {
  Residuals out;
  const double c = std::cos(pose.phi()), s = std::sin(pose.phi());
  // Cauchy weight and cost of a squared residual (plain least squares without a kernel).
  auto robust = [&](double r2, double& w) {
    if (kernel_c <= 0) {
      w = 1;
      return r2;
    }
    const double u = r2 / (kernel_c * kernel_c);
    w = 1 / (1 + u);
    return kernel_c * kernel_c * std::log1p(u);
  };
  const double in2 = inlier_dist * inlier_dist;
  for (std::size_t i = 0; i < cur.size(); i += sel.stride) {
    const double px = cur.xs()[i], py = cur.ys()[i];
    const Eigen::Vector2d q(pose.x() + c * px - s * py, pose.y() + s * px + c * py);
    float d2 = 0;
    const std::size_t k = ref.nearest(static_cast<float>(q.x()), static_cast<float>(q.y()), d2);
    if (sel.per_metre > 0) {
      const double lim = inlier_dist + sel.per_metre * std::hypot(px, py);
      if (d2 > lim * lim) continue;
    } else if (d2 > in2) {
      continue;
    }
    ++out.inliers;
    const Eigen::Vector2d dq_dphi(-s * px - c * py, c * px - s * py);
    const Eigen::Vector2d e = q - Eigen::Vector2d(ref.xs()[k], ref.ys()[k]);
    const Eigen::Vector2d n = ref.normal(k);
    double w = 1;
    if (n.squaredNorm() > 0) {
      const Eigen::RowVector3d J(n.x(), n.y(), n.dot(dq_dphi));
      const double r = n.dot(e);
      out.sum_r2 += robust(r * r, w);
      out.sum_plain += r * r;
      out.H += w * J.transpose() * J;
      out.b += w * J.transpose() * r;
      out.rows += 1;
      if (abs_res) abs_res->push_back(std::abs(r));
    } else {
      Eigen::Matrix<double, 2, 3> J;
      J << 1, 0, dq_dphi.x(), 0, 1, dq_dphi.y();
      out.sum_r2 += robust(e.squaredNorm(), w);
      out.sum_plain += e.squaredNorm();
      out.H += w * J.transpose() * J;
      out.b += w * J.transpose() * e;
      out.rows += 2;
      if (abs_res) abs_res->push_back(e.norm() / std::sqrt(2.0));
    }
  }
  return out;
}

/// The Gauss-Newton step of `res`, leaving out the directions its J^T J barely constrains
/// (eigenvalues below 1e-6 of the largest: a corridor's axis is not moved).
Eigen::Vector3d gaussNewtonStep(const Residuals& res) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(res.H);
  const Eigen::Vector3d ev = es.eigenvalues();
  Eigen::Vector3d step = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k)
    if (ev(k) > 1e-6 * ev(2))
      step -= es.eigenvectors().col(k) * (es.eigenvectors().col(k).dot(res.b) / ev(k));
  return step;
}

mrpt::poses::CPose2D applyStep(const mrpt::poses::CPose2D& p, const Eigen::Vector3d& step) {
  mrpt::poses::CPose2D next(p.x() + step.x(), p.y() + step.y(), p.phi() + step.z());
  next.normalizePhi();
  return next;
}

/// MRPT's CICP (LM variant) from `guess`: fills pose, goodness, iterations and cicp_cov of `r`.
void alignCicp(const Cloud& ref, const Cloud& cur, const mrpt::poses::CPose2D& guess,
               const IcpOptions& o, MatchResult& r) {
  mrpt::slam::CICP icp;
  icp.options.ICP_algorithm = mrpt::slam::icpLevenbergMarquardt;
  icp.options.maxIterations = static_cast<unsigned>(o.max_iterations);
  icp.options.thresholdDist = o.threshold_dist;
  icp.options.thresholdAng = o.threshold_ang_deg * kDeg;
  icp.options.ALFA = o.alfa;
  icp.options.smallestThresholdDist = o.smallest_threshold_dist;
  icp.options.corresponding_points_decimation = static_cast<std::uint32_t>(o.decimation);
  icp.options.doRANSAC = false;
  mrpt::slam::CICP::TReturnInfo info;
  const auto pdf = icp.AlignPDF(&ref.map(), &cur.map(), mrpt::poses::CPosePDFGaussian(guess), info);
  r.pose = pdf->getMeanVal();
  r.pose.normalizePhi();
  r.goodness = info.goodness;
  r.iterations = info.nIterations;
  if (auto g = std::dynamic_pointer_cast<mrpt::poses::CPosePDFGaussian>(pdf))
    r.cicp_cov = g->cov.asEigen();
}

/// IcpMethod::PointToLine from `guess`: Gauss-Newton on the point-to-line residuals of every
/// `decimation`-th point whose nearest reference point is within the correspondence
/// distance (every point at the last distance), correspondences searched again after each
/// step; when a step moves less than 1e-5 (m, rad) the distance shrinks by `alfa` down to
/// `smallest_threshold_dist`, and convergence there ends it: CICP's schedule and keys with
/// our kd-tree and point-to-line rows, no damping. Fills pose, goodness (the share of the
/// decimated points with a correspondence at the last distance, as CICP's) and iterations
/// (max_iterations when it did not converge: correspondences that keep switching). A
/// variant: about twice as fast as CICP in the front-end, but worse on the real CARMEN logs
/// and MRPT's simulated ones (plugin README, "Coarse alignment").
void alignPointToLine(const Cloud& ref, const Cloud& cur, const mrpt::poses::CPose2D& guess,
                      const IcpOptions& o, MatchResult& r) {
  Selection sel;
  sel.stride = static_cast<std::size_t>(std::max(1, o.decimation));
  sel.per_metre = o.threshold_ang_deg * kDeg;
  double dist = o.threshold_dist;
  mrpt::poses::CPose2D pose = guess;
  int it = 0;
  bool converged = false;
  while (it < o.max_iterations && !converged) {
    ++it;
    // Every point at the last distance: the decimated points' optimum is noisier than the
    // refinement below would then correct (it stops at the first step that does not lower
    // the mean residual).
    Selection at = sel;
    if (dist <= o.smallest_threshold_dist) at.stride = 1;
    const Residuals res = residuals(ref, cur, pose, dist, 0, nullptr, at);
    if (res.rows <= 3) break;  // nothing left to align with: the goodness says so
    const Eigen::Vector3d step = gaussNewtonStep(res);
    if (!step.allFinite()) break;
    pose = applyStep(pose, step);
    if (std::hypot(step.x(), step.y()) < 1e-5 && std::abs(step.z()) < 1e-5) {
      if (dist <= o.smallest_threshold_dist) converged = true;
      dist = std::max(dist * o.alfa, o.smallest_threshold_dist);
    }
  }
  const std::size_t considered = (cur.size() + sel.stride - 1) / sel.stride;
  const Residuals last = residuals(ref, cur, pose, dist, 0, nullptr, sel);
  r.pose = pose;
  r.goodness = considered ? static_cast<double>(last.inliers) / static_cast<double>(considered) : 0;
  r.iterations = converged ? static_cast<unsigned>(it) : static_cast<unsigned>(o.max_iterations);
}

}  // namespace

MatchResult match(const Cloud& ref, const Cloud& cur, const mrpt::poses::CPose2D& guess,
                  const IcpOptions& o, std::size_t min_points) {
  MatchResult r;
  r.pose = guess;
  if (ref.size() < min_points || cur.size() < min_points) {
    r.reason = "too few points (reference " + std::to_string(ref.size()) + ", current " +
               std::to_string(cur.size()) + ")";
    return r;
  }
  r.ran = true;
  if (o.method == IcpMethod::PointToLine)
    alignPointToLine(ref, cur, guess, o, r);
  else
    alignCicp(ref, cur, guess, o, r);

  // CICP minimizes point-to-point distances, which sparse scans of the same wall bias by up to
  // half the point spacing, and it sees every decimation-th point only; a few Gauss-Newton
  // steps on point-to-line residuals of all points (point-to-point where the reference has no
  // line) remove that. Directions the scene leaves unconstrained (a corridor's axis) are not
  // moved.
  // Robust scale: the Cauchy kernel's c from the median absolute residual at CICP's solution
  // (1.4826 MAD = sigma for Gaussian noise; c = 2.385 sigma is the kernel's 95% efficiency).
  double kc = 0;
  if (o.robust) {
    std::vector<double> a;
    residuals(ref, cur, r.pose, o.inlier_dist, 0, &a);
    if (a.size() > 3) {
      std::nth_element(a.begin(), a.begin() + a.size() / 2, a.end());
      kc = 2.385 * std::max(o.sigma_floor, 1.4826 * a[a.size() / 2]);
    }
  }
  const double inlier = o.inlier_dist;
  Residuals res = residuals(ref, cur, r.pose, inlier, kc);
  for (int it = 0; it < o.refine_iterations && res.rows > 3; ++it) {
    const Eigen::Vector3d step = gaussNewtonStep(res);
    if (!step.allFinite()) break;
    const mrpt::poses::CPose2D next = applyStep(r.pose, step);
    Residuals nres = residuals(ref, cur, next, inlier, kc);
    // Keep the step only if it lowers the mean residual without losing inliers.
    if (nres.rows < res.rows * 0.95 || nres.sum_r2 / std::max<std::size_t>(nres.rows, 1) >
                                           res.sum_r2 / std::max<std::size_t>(res.rows, 1))
      break;
    r.pose = next;
    res = nres;
    if (std::hypot(step.x(), step.y()) < 1e-5 && std::abs(step.z()) < 1e-6) break;
  }
  r.inlier_ratio = static_cast<double>(res.inliers) / static_cast<double>(cur.size());
  r.residuals = res.rows;
  r.rmse = res.rows ? std::sqrt(res.sum_plain / static_cast<double>(res.rows)) : 0;
  const double sigma2 =
      std::max(o.sigma_floor * o.sigma_floor,
               res.rows > 3 ? res.sum_plain / static_cast<double>(res.rows - 3) : 0.0);
  // Degenerate directions (a straight corridor) get a huge variance instead of a NaN.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(res.H);
  Eigen::Vector3d inv_ev;
  for (int k = 0; k < 3; ++k) inv_ev(k) = 1.0 / std::max(es.eigenvalues()(k), 1e-9);
  r.cov = o.cov_scale * sigma2 * es.eigenvectors() * inv_ev.asDiagonal() *
          es.eigenvectors().transpose();
  r.cov = 0.5 * (r.cov + r.cov.transpose());
  return r;
}

Eigen::Vector3d poseDiff(const mrpt::poses::CPose2D& a, const mrpt::poses::CPose2D& b) {
  return Eigen::Vector3d(a.x() - b.x(), a.y() - b.y(), mrpt::math::wrapToPi(a.phi() - b.phi()));
}

}  // namespace asf::icp_graph
