#pragma once
/// \file correlative_matcher.h
/// Correlative scan matching (Olson, "Real-time correlative scan matching", ICRA 2009): the
/// pose of a scan in a reference is the one that maximizes the mean likelihood of its points
/// in a likelihood field of the reference, searched exhaustively over a window of x, y and
/// heading, so it does not need a good initial guess. The window is searched by branch and
/// bound over precomputed max-pooled grids (Hess, Kohler, Rapp, Andor, "Real-time loop
/// closure in 2D LIDAR SLAM", ICRA 2016): the result is the exhaustive search's optimum on the
/// lattice, found without scoring most of it. Pure: Eigen only.
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace asf::icp_graph {

/// Points as parallel x / y arrays (a Cloud's xs() and ys()).
struct Points2 {
  const std::vector<float>& x;
  const std::vector<float>& y;
  std::size_t size() const { return x.size(); }
};

/// A likelihood field of reference points: cell value exp(-d^2 / (2 sigma^2)) of the distance d
/// from the cell's centre to the nearest reference point (cut at 3 sigma), with max-pooled
/// copies for branch and bound: level h holds at (i, j) the largest level-0 value over the
/// cells [i, i + 2^h) x [j, j + 2^h).
class LikelihoodGrid {
 public:
  /// `margin` extends the grid beyond the points' bounding box [m]; `cover` (min x, min y,
  /// max x, max y), if given, is inside the grid too, added in whole cells so that the cells'
  /// values do not change: a search whose moved scan stays inside reads without bounds tests.
  LikelihoodGrid(Points2 ref, double resolution, double sigma, int levels, double margin,
                 const std::array<double, 4>* cover = nullptr);
  /// Gives its cell buffers back to this thread's pool: the next grid reuses them (fresh
  /// allocations of a few megabytes per search were page faults and zero-filling).
  ~LikelihoodGrid();
  LikelihoodGrid(const LikelihoodGrid&) = delete;
  LikelihoodGrid& operator=(const LikelihoodGrid&) = delete;

  double resolution() const { return res_; }
  int levels() const { return static_cast<int>(level_.size()); }
  /// Level-h value of cell (i, j); 0 outside the grid.
  float at(int h, int i, int j) const {
    if (i < 0 || j < 0 || i >= w_ || j >= h_) return 0.f;
    return level_[static_cast<std::size_t>(h)][static_cast<std::size_t>(j) * w_ + i];
  }
  /// Level h's cells, row-major (width() x height()): the unchecked access of at().
  const float* data(int h) const { return level_[static_cast<std::size_t>(h)].data(); }
  int width() const { return w_; }
  int height() const { return h_; }
  /// Cell index of a coordinate.
  int cellX(double x) const;
  int cellY(double y) const;

 private:
  double res_, x0_, y0_;
  int w_ = 0, h_ = 0;
  std::vector<std::vector<float>> level_;
};

struct CorrelativeOptions {
  double window_xy = 1.0;    ///< translations searched: guess +- this in x and y [m]
  double window_phi = 0.35;  ///< headings searched: guess +- this [rad]
  /// Heading step [rad]; 0 = the step that moves the farthest point by one cell (Hess et al.).
  double step_phi = 0;
  double min_score = 0.0;  ///< poses scoring below this are not searched further
};

struct CorrelativeResult {
  bool found = false;             ///< a pose scored at least min_score
  Eigen::Vector3d pose{0, 0, 0};  ///< (x, y, phi) of the scan's frame in the reference's
  double score = 0;               ///< mean likelihood of the scan's points at `pose`, in [0, 1]
  std::size_t scored = 0;         ///< leaf poses scored exactly (the lattice has far more)
  std::size_t lattice = 0;        ///< poses in the searched lattice
};

/// A search of `scan` (points in its own frame) in `grid`'s frame over the window around
/// `guess`, prepared once (the scan's cells at every heading, the coarsest blocks' bounds) and
/// run as often as asked: the best pose, then the best outside its peak (ambiguity). The grid
/// must outlive it.
class CorrelativeSearch {
 public:
  CorrelativeSearch(const LikelihoodGrid& grid, Points2 scan, const Eigen::Vector3d& guess,
                    const CorrelativeOptions& o);
  ~CorrelativeSearch();
  CorrelativeSearch(const CorrelativeSearch&) = delete;
  CorrelativeSearch& operator=(const CorrelativeSearch&) = delete;
  /// The best pose scoring at least `min_score` whose translation lies outside the disc of
  /// `exclude_radius` around `exclude_xy` (exclude_radius <= 0: anywhere).
  CorrelativeResult run(double min_score,
                        const Eigen::Vector2d& exclude_xy = Eigen::Vector2d::Zero(),
                        double exclude_radius = 0) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Best pose of `scan` (points in its own frame) in `grid`'s frame over the window around
/// `guess` (a CorrelativeSearch run once at o.min_score). Poses whose translation lies within
/// `exclude_radius` of `exclude_xy` are skipped (exclude_radius <= 0: none): the best pose outside
/// a peak, to see whether it is unique.
CorrelativeResult correlativeMatch(const LikelihoodGrid& grid, Points2 scan,
                                   const Eigen::Vector3d& guess, const CorrelativeOptions& o,
                                   const Eigen::Vector2d& exclude_xy = Eigen::Vector2d::Zero(),
                                   double exclude_radius = 0);

/// Mean likelihood of `scan` at `pose` (level 0): what correlativeMatch maximizes.
double correlativeScore(const LikelihoodGrid& grid, Points2 scan, const Eigen::Vector3d& pose);

}  // namespace asf::icp_graph
