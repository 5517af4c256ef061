// backend_sparse_lm: Levenberg-Marquardt / Gauss-Newton on SE(2) pose graphs with sparse
// normal equations (SuiteSparse CHOLMOD, supernodal) and marginal covariances from the
// sparse inverse subset of the factor. The numerics are in sparse_se2.cpp.
#include <asf/backend.h>
#include <asf/errors.h>

#include "incremental_se2.h"

namespace {

using asf::sparse_lm::Kernel;
using asf::sparse_lm::Method;
using asf::sparse_lm::RobustEdges;

class SparseLmBackend final : public asf::Backend {
 public:
  void configure(const asf::Params& p, const asf::PluginContext&) override {
    const std::string method = p.getString("method");
    opt_.method = method == "gn" ? Method::GaussNewton : Method::LevenbergMarquardt;
    opt_.max_iterations = static_cast<int>(p.getInt("max_iterations"));
    opt_.tolerance = p.getDouble("tolerance");
    opt_.lambda_init = p.getDouble("lambda_init");
    opt_.lago_init = p.getBool("lago_init");
    const std::string k = p.getString("robust_kernel");
    opt_.kernel = k == "huber"    ? Kernel::Huber
                  : k == "cauchy" ? Kernel::Cauchy
                  : k == "dcs"    ? Kernel::Dcs
                                  : Kernel::None;
    opt_.robust_delta = p.getDouble("robust_delta");
    const std::string edges = p.getString("robust_edges");
    opt_.robust_edges = edges == "loops"   ? RobustEdges::LoopClosures
                        : edges == "links" ? RobustEdges::CrossLinks
                                           : RobustEdges::All;
    opt_.reorder_fill_ratio = p.getDouble("reorder_fill_ratio");
    opt_.cholmod_openmp = p.getBool("cholmod_openmp");
    opt_.verbosity = static_cast<int>(p.getInt("verbosity"));
    inc_.enabled = p.getBool("incremental");
    inc_.gap = p.getDouble("incremental_gap");
    inc_.hops = static_cast<int>(p.getInt("incremental_hops"));
    inc_.max_window = static_cast<std::size_t>(p.getInt("incremental_max_window"));
    const std::string marginals = p.getString("incremental_marginals");
    inc_.marginals = marginals == "updated"      ? asf::sparse_lm::MarginalsMode::Updated
                     : marginals == "propagated" ? asf::sparse_lm::MarginalsMode::Propagated
                                                 : asf::sparse_lm::MarginalsMode::Exact;
    inc_.update_max_nodes = static_cast<std::size_t>(p.getInt("incremental_update_nodes"));
    inc_.update_max_touched = static_cast<std::size_t>(p.getInt("incremental_update_touched"));
    opt_.log = [this](const std::string& line) { MRPT_LOG_INFO(line); };
  }

  asf::OptimizeReport optimize(asf::PoseGraph& g) override {
    const asf::OptimizeReport r = core_.optimize(g, opt_, inc_);
    MRPT_LOG_DEBUG_STREAM("sparse_lm: chi2 " << r.initial_chi2 << " -> " << r.final_chi2 << " in "
                                             << r.iterations << " iterations (" << r.message
                                             << ")");
    if (inc_.enabled)
      MRPT_LOG_DEBUG_STREAM("sparse_lm: " << core_.counters().last_path << "; so far "
                                          << core_.counters().window_solves << " window, "
                                          << core_.counters().whole_solves << " whole solves");
    return r;
  }

  asf::Marginals marginals(const asf::PoseGraph& g,
                           const std::vector<std::pair<asf::NodeId, asf::NodeId>>& cross) override {
    const long exact = core_.counters().exact_marginals;
    const long updated = core_.counters().updated_marginals;
    asf::Marginals m = core_.marginals(g, cross, opt_, inc_);
    if (core_.counters().updated_marginals != updated)
      MRPT_LOG_DEBUG_STREAM("sparse_lm: marginals of " << g.size() << " nodes updated ("
                                                       << core_.counters().updated_marginals
                                                       << " so far)");
    else if (core_.counters().exact_marginals == exact)
      MRPT_LOG_DEBUG_STREAM("sparse_lm: marginals of " << g.size()
                                                       << " nodes, the newer ones propagated");
    else
      MRPT_LOG_DEBUG_STREAM("sparse_lm: marginals of "
                            << g.size() << " nodes, symbolic: " << core_.whole().lastSymbolic()
                            << ", " << core_.whole().lastCrossSolved()
                            << " cross blocks solved by columns");
    return m;
  }

 private:
  asf::sparse_lm::Options opt_;
  asf::sparse_lm::IncrementalOptions inc_;
  asf::sparse_lm::IncrementalSe2 core_;
};

const asf::KeySpec kKeys[] = {
    asf::keyEnum("method", "lm", "lm|gn",
                 "lm: Levenberg-Marquardt, a trust region that rejects steps raising chi2 "
                 "(Nielsen's damping update); gn: plain Gauss-Newton, stops at the first step "
                 "that does not lower chi2"),
    asf::keyInt("max_iterations", "100",
                "Maximum iterations (linearizations; LM may try several dampings in one)", 1,
                100000),
    asf::keyDouble("tolerance", "1e-5",
                   "Stop when an accepted step lowers chi2 by less than this fraction", 0, 1),
    asf::keyDouble("lambda_init", "1e-6",
                   "Initial Levenberg-Marquardt damping, relative to the diagonal of H", 0, 1e10),
    asf::keyBool("lago_init", "true",
                 "Also try a LAGO-style initial guess (orientations by linear least squares over "
                 "a spanning tree's unwrapped rotations) and start from it if its chi2 is lower"),
    asf::keyEnum("robust_kernel", "none", "none|huber|cauchy|dcs",
                 "Robust kernel on each edge's chi2 (huber, cauchy: g2o's definitions; dcs: "
                 "dynamic covariance scaling, Agarwal et al. 2013, Phi = robust_delta^2)"),
    asf::keyDouble("robust_delta", "2.8",
                   "Kernel width in units of sqrt(e^T Omega e) (2.8: the 95% quantile of a "
                   "3-dof chi2 is 2.8^2)",
                   1e-9, 1e9),
    asf::keyEnum("robust_edges", "all", "all|loops|links",
                 "Edges the kernel applies to: all; loops (loop closures only); links (every "
                 "edge but those between consecutive nodes: loop closures and matches against "
                 "older keyframes). The others stay quadratic"),
    asf::keyDouble("reorder_fill_ratio", "1.3",
                   "On growth keep the previous elimination order (new poses last) unless the "
                   "factor's fill exceeds this times that of the last fresh ordering",
                   1, 1e6),
    asf::keyBool("cholmod_openmp", "false",
                 "Let CHOLMOD run its OpenMP loops in parallel (Debian's build uses a fixed team "
                 "of 4 threads on small loops: slower on few cores); false serializes them in "
                 "the calling thread only"),
    asf::keyBool("incremental", "false",
                 "Solve a growing graph in a window around what is new (the new nodes and edge "
                 "ends, incremental_hops edges around them, and the nodes added since the last "
                 "solve of the whole graph) while a whole-graph Gauss-Newton step could lower "
                 "chi2 by at most incremental_gap (bounded with the last whole factorization); "
                 "else solve the whole graph (see incremental_marginals)"),
    asf::keyDouble("incremental_gap", "0.5",
                   "Most chi2 a whole-graph step may still gain after a window solve: the "
                   "estimate stays within sqrt(gap) standard deviations of the optimum",
                   0, 1e9),
    asf::keyInt("incremental_hops", "3",
                "Window: nodes up to this many edges from the new nodes and edge ends", 0, 1000000),
    asf::keyInt("incremental_max_window", "300",
                "A larger window solves the whole graph instead (as does one over half of it)", 1,
                100000000),
    asf::keyEnum("incremental_marginals", "exact", "exact|updated|propagated",
                 "With incremental: exact (a factorization of the whole graph every time), "
                 "updated (after a window solve, the last whole factorization's marginals "
                 "updated for what was added since: that linearization's exact blocks) or "
                 "propagated (after a window solve, the last exact blocks and newer nodes from "
                 "an edge to an older node: upper bounds, cheaper, and they change what "
                 "covariance gates admit)"),
    asf::keyInt("incremental_update_nodes", "32",
                "Updated marginals: factorize the whole graph again once the nodes added since "
                "plus the older nodes the new edges touch exceed this",
                1, 100000),
    asf::keyInt("incremental_update_touched", "8",
                "Updated marginals: factorize the whole graph again once the new edges touch "
                "more older nodes than this (each costs a solve; the update O(n) in their rank)",
                1, 100000),
    asf::keyInt("verbosity", "0",
                "0: quiet; 1: one INFO line per optimize(); 2: one INFO line per step", 0, 2),
};

}  // namespace

ASF_PLUGIN(SparseLmBackend, asf::PluginKind::Backend, "sparse_lm", "1.0.0",
           "Levenberg-Marquardt on SE(2) with sparse CHOLMOD factorization and marginals from "
           "the sparse inverse subset",
           asf::ThreadSafety::ThreadCompatible, kKeys)
