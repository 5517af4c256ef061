#pragma once
// Private to backend_sparse_lm: SparseSe2's state (the CHOLMOD factor and the normal equations
// it factors) and the scoped helpers its phases share; shared by sparse_se2.cpp (factorization
// and the Levenberg-Marquardt iterations) and sparse_se2_marginals.cpp (covariances).
#include <asf/backend.h>
#include <asf/errors.h>
#include <asf/pose_graph.h>
#include <cholmod.h>

#include <Eigen/Core>
#include <chrono>
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sparse_problem.h"
#include "sparse_se2.h"

// libgomp's per-thread "max active levels" ICV, bound only if the OpenMP runtime is loaded
// (it comes with Debian's CHOLMOD); weak, so a CHOLMOD without OpenMP needs nothing.
extern "C" {
int omp_get_max_active_levels() __attribute__((weak));
void omp_set_max_active_levels(int) __attribute__((weak));
}

namespace asf::sparse_lm {

namespace detail {

/// While alive, OpenMP parallel regions started by this thread run with one thread. SuiteSparse
/// 5 (Debian bookworm) parallelizes small loops of CHOLMOD's supernodal factorization with a
/// team fixed at compile time (4 threads): on a 2-core machine the wake-ups cost more than
/// the loops (city10000: optimize 0.45 s -> 0.24 s, marginals 0.13 s -> 0.08 s, measured).
/// The ICV is per thread (libgomp >= 11), so other threads keep their setting.
class SerialOpenMp {
 public:
  explicit SerialOpenMp(bool serialize)
      : on_(serialize && omp_get_max_active_levels && omp_set_max_active_levels) {
    if (!on_) return;
    saved_ = omp_get_max_active_levels();
    omp_set_max_active_levels(0);
  }
  ~SerialOpenMp() {
    if (on_) omp_set_max_active_levels(saved_);
  }
  SerialOpenMp(const SerialOpenMp&) = delete;
  SerialOpenMp& operator=(const SerialOpenMp&) = delete;

 private:
  bool on_;
  int saved_ = 0;
};

/// Adds the lifetime of the object to a seconds counter.
class Timer {
 public:
  explicit Timer(double& acc) : acc_(acc), t0_(std::chrono::steady_clock::now()) {}
  ~Timer() {
    acc_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  }

 private:
  double& acc_;
  std::chrono::steady_clock::time_point t0_;
};

/// Throws asf::Error for an edge or a fixed node that names a node the graph does not have.
void validate(const asf::PoseGraph& g);

}  // namespace detail

struct SparseSe2::Impl {
  cholmod_common cm;
  cholmod_factor* L = nullptr;
  detail::Structure S;  ///< the structure L was analysed for (valid if L)
  double fill_at_fresh = 0;
  Counters counters;
  std::string last_symbolic = "none";
  std::size_t last_cross_solved = 0;
  bool factor_valid = false;  ///< L holds a successful numeric factorization of S's matrix

  std::vector<double> H;   ///< values of H in S's pattern (undamped)
  std::vector<double> Ax;  ///< values handed to CHOLMOD (H plus damping)
  std::vector<double> b;   ///< J^T W e
  std::vector<int> diag;   ///< position of each diagonal entry in H

  Impl() {
    cholmod_start(&cm);
    cm.print = 0;
    cm.error_handler = nullptr;
    cm.supernodal = CHOLMOD_SUPERNODAL;
  }
  ~Impl() {
    if (L) cholmod_free_factor(&L, &cm);
    cholmod_finish(&cm);
  }

  [[noreturn]] void cholmodFailed(const char* what) const {
    throw asf::Error(std::string("sparse_lm: CHOLMOD ") + what + " failed (status " +
                     std::to_string(cm.status) + ")");
  }

  /// Makes L a symbolic factor of S: kept if S is unchanged, else analysed with the previous
  /// order extended (growth) or a fresh block AMD order.
  void prepare(detail::Structure S_new, const Options& o);
  /// Symbolic analysis of S with the given block order (empty: block AMD). Ordering the
  /// 3x3 blocks rather than scalars keeps each pose's three columns together and works on
  /// a graph 3 times smaller.
  cholmod_factor* analyze(const detail::Structure& s, std::vector<int> order);
  /// H and b at x (kernel weights applied); returns the cost at x.
  double linearize(const detail::Problem& P, const detail::Poses& x, const Options& o);
  bool factorize(const std::vector<double>& values);
  /// Solves H X = B for a dense column-major B with ncol columns.
  std::vector<double> solve(std::vector<double> B, std::size_t ncol);
  /// Columns of the factored matrix's inverse for free nodes `cols`: dim x 3 cols.size().
  Eigen::MatrixXd columns(const std::vector<int>& cols);

  asf::OptimizeReport optimize(asf::PoseGraph& g, const Options& o);
  asf::OptimizeReport optimizeWindow(asf::PoseGraph& g, const std::vector<asf::NodeId>& window,
                                     const std::vector<std::size_t>& edges, const Options& o);
  /// Solves P from g's poses over S_new's free nodes; writes them back to g if chi2 fell.
  asf::OptimizeReport run(asf::PoseGraph& g, const detail::Problem& P, detail::Structure S_new,
                          const Options& o, bool lago);
  std::optional<double> decrementBound(const asf::PoseGraph& g, const Options& o);
  double iterate(const detail::Problem& P, detail::Poses& x, const Options& o,
                 asf::OptimizeReport& r, int& steps, int& accepted);
  /// What the iterations carry from one linearization to the next.
  struct LmState {
    double F = 0;               ///< the cost at x
    double lambda = 0, nu = 2;  ///< damping (relative to diag(H)) and its growth factor
    std::vector<double> D;      ///< the damping's scale: diag(H) of this linearization, floored
    double xmax = 0;            ///< the largest |coordinate| of x
    detail::Poses x_new;        ///< the trial poses
  };
  /// Tries dampings of the current linearization (H, b) until a step lowers the cost (x and
  /// s.F then move to it); returns true when the iterations stop, r.message saying why.
  bool dampedSteps(const detail::Problem& P, detail::Poses& x, LmState& s, const Options& o,
                   asf::OptimizeReport& r, int& steps, int& accepted);
  /// The damped step at `lambda` from the factored matrix: x_new = x + h, its cost, the
  /// predicted decrease and the largest |h|.
  struct Trial {
    double F_new = 0, pred = 0, hmax = 0;
  };
  Trial tryStep(const detail::Problem& P, const detail::Poses& x, detail::Poses& x_new,
                const Options& o, double lambda, const std::vector<double>& D);
  asf::Marginals marginals(const asf::PoseGraph& g,
                           const std::vector<std::pair<asf::NodeId, asf::NodeId>>& cross,
                           const Options& o);
};

}  // namespace asf::sparse_lm
