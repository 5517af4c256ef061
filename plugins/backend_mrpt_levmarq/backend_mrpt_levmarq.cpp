// backend_mrpt_levmarq: MRPT's own pose-graph optimizer (mrpt::graphslam::
// optimize_graph_spa_levmarq on a CNetworkOfPoses2DInf), wrapped as the baseline the sparse
// back-end is measured against. MRPT gives no covariances: marginals() inverts the dense
// information matrix, so it is limited to small graphs.
#include <asf/backend.h>
#include <asf/errors.h>
#include <mrpt/graphs/CNetworkOfPoses.h>
#include <mrpt/graphslam/levmarq.h>

#include <Eigen/Dense>
#include <cmath>
#include <set>
#include <sstream>

namespace {

class MrptLevmarqBackend final : public asf::Backend {
 public:
  void configure(const asf::Params& p, const asf::PluginContext&) override {
    max_iterations_ = static_cast<int>(p.getInt("max_iterations"));
    initial_lambda_ = p.getDouble("initial_lambda");
    tau_ = p.getDouble("tau");
    e1_ = p.getDouble("e1");
    e2_ = p.getDouble("e2");
    marginals_max_nodes_ = static_cast<std::size_t>(p.getInt("marginals_max_nodes"));
  }

  asf::OptimizeReport optimize(asf::PoseGraph& g) override {
    check(g);
    asf::OptimizeReport r;
    r.initial_chi2 = r.final_chi2 = g.chi2();
    if (!std::isfinite(r.initial_chi2))
      throw asf::Error("mrpt_levmarq: the graph's chi2 is not finite (" +
                       std::to_string(r.initial_chi2) +
                       "): a pose, edge or information too large or not finite");
    r.converged = true;
    std::set<mrpt::graphs::TNodeID> free;
    for (std::size_t i = 1; i < g.size(); ++i) free.insert(i);
    for (asf::NodeId f : g.fixed) free.erase(f);
    if (g.size() < 2 || g.edges.empty() || free.empty()) {
      r.message = "nothing to optimize";
      return r;
    }
    bool has_edge = false;  // MRPT needs an edge touching a free node
    for (const auto& e : g.edges) has_edge |= free.count(e.from) || free.count(e.to);
    if (!has_edge) {
      r.message = "nothing to optimize (no edge reaches a free node)";
      return r;
    }

    mrpt::graphs::CNetworkOfPoses2DInf net;
    toNetwork(g, net);
    mrpt::containers::yaml params = mrpt::containers::yaml::Map();
    params["max_iterations"] = max_iterations_;
    params["initial_lambda"] = initial_lambda_;
    params["tau"] = tau_;
    params["e1"] = e1_;
    params["e2"] = e2_;
    mrpt::graphslam::TResultInfoSpaLevMarq info{};
    try {
      mrpt::graphslam::optimize_graph_spa_levmarq(net, info, &free, params);
    } catch (const std::exception& ex) {
      throw asf::Error(std::string("mrpt_levmarq: MRPT's optimizer failed: ") + ex.what());
    }

    // MRPT judges progress by the unweighted sum of squared errors; the contract is about
    // chi2 (information-weighted): keep MRPT's poses only if they lower it.
    asf::PoseGraph out = g;
    for (auto i : free) out.nodes[i].pose = net.nodes.at(i);
    const double chi = out.chi2();
    r.iterations = static_cast<int>(info.num_iters) + 1;  // MRPT reports the last loop index
    std::ostringstream msg;
    msg << "MRPT levmarq stopped after " << r.iterations
        << " iterations, final unweighted squared error " << info.final_total_sq_error;
    bool moved = false;
    for (auto i : free) {
      const auto &a = out.nodes[i].pose, &b = g.nodes[i].pose;
      moved |= a.x() != b.x() || a.y() != b.y() || a.phi() != b.phi();
    }
    if (!moved) {
      r.converged = r.iterations < max_iterations_;
      msg << "; no pose moved";
    } else if (std::isfinite(chi) && chi < r.initial_chi2) {
      for (auto i : free) g.nodes[i].pose = out.nodes[i].pose;
      ++g.revision;
      r.final_chi2 = chi;
      // MRPT does not say why it stopped (its criteria, or lambda above 1e9).
      r.converged = r.iterations < max_iterations_;
      if (!r.converged) msg << "; reached max_iterations";
    } else {
      r.converged = false;
      msg << "; its result has chi2 " << chi << ", not below the initial " << r.initial_chi2
          << ": kept the input poses";
    }
    r.message = msg.str();
    MRPT_LOG_DEBUG_STREAM("mrpt_levmarq: chi2 " << r.initial_chi2 << " -> " << r.final_chi2
                                                << " (" << r.message << ")");
    return r;
  }

  asf::Marginals marginals(const asf::PoseGraph& g,
                           const std::vector<std::pair<asf::NodeId, asf::NodeId>>& cross)
      override {
    check(g);
    asf::Marginals m;
    m.graph_revision = g.revision;
    const std::size_t n = g.size();
    for (const auto& [i, j] : cross)
      if (i >= n || j >= n)
        throw asf::Error("mrpt_levmarq: cross-covariance requested for (" + std::to_string(i) +
                         ", " + std::to_string(j) + ") but the graph has " + std::to_string(n) +
                         " nodes");
    if (n == 0) return m;
    if (n > marginals_max_nodes_)
      throw asf::Error("mrpt_levmarq: MRPT's optimizer gives no covariances; this back-end "
                       "inverts the dense information matrix instead, limited to "
                       "marginals_max_nodes = " + std::to_string(marginals_max_nodes_) +
                       " nodes (the graph has " + std::to_string(n) +
                       "); use the sparse_lm back-end for marginals of large graphs");
    asf::requireAnchored(g, "mrpt_levmarq");
    // Variables: every node except node 0 and the fixed ones.
    std::vector<int> index;
    const Eigen::MatrixXd H = asf::denseInformation(g, index);
    const int dim = static_cast<int>(H.rows());
    m.node.assign(n, Eigen::Matrix3d::Zero());
    Eigen::MatrixXd S;
    if (dim > 0) {
      Eigen::LDLT<Eigen::MatrixXd> ldlt(H);
      const double dmax = ldlt.vectorD().cwiseAbs().maxCoeff();
      if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-14 * dmax))
        throw asf::Error("mrpt_levmarq: the information matrix is singular (degenerate edge "
                         "information?); no covariance defined");
      S = ldlt.solve(Eigen::MatrixXd::Identity(dim, dim));
      S = 0.5 * (S + S.transpose());
      for (std::size_t i = 0; i < n; ++i)
        if (index[i] >= 0) m.node[i] = S.block<3, 3>(index[i], index[i]);
    }
    for (const auto& [i, j] : cross)
      m.cross[{i, j}] = index[i] >= 0 && index[j] >= 0
                            ? Eigen::Matrix3d(S.block<3, 3>(index[i], index[j]))
                            : Eigen::Matrix3d::Zero();
    return m;
  }

 private:
  /// g's nodes and edges into MRPT's graph (rooted at node 0), as optimize_graph_spa_levmarq
  /// takes them.
  static void toNetwork(const asf::PoseGraph& g, mrpt::graphs::CNetworkOfPoses2DInf& net) {
    net.root = 0;
    for (std::size_t i = 0; i < g.size(); ++i) net.nodes[i] = g.nodes[i].pose;
    for (const auto& e : g.edges) {
      if (e.from == e.to) continue;  // carries no information on a pose; MRPT rejects it
      mrpt::poses::CPosePDFGaussianInf m;
      m.mean = e.mean;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) m.cov_inv(a, b) = e.information(a, b);
      net.insertEdgeAtEnd(e.from, e.to, m);
    }
  }

  static void check(const asf::PoseGraph& g) {
    for (const auto& e : g.edges)
      if (e.from >= g.size() || e.to >= g.size())
        throw asf::Error("mrpt_levmarq: edge " + std::to_string(e.from) + " -> " +
                         std::to_string(e.to) + " names a node that does not exist");
    for (asf::NodeId f : g.fixed)
      if (f >= g.size())
        throw asf::Error("mrpt_levmarq: fixed node " + std::to_string(f) + " does not exist");
  }

  int max_iterations_ = 100;
  double initial_lambda_ = 0, tau_ = 1e-3, e1_ = 1e-6, e2_ = 1e-6;
  std::size_t marginals_max_nodes_ = 1000;
};

const asf::KeySpec kKeys[] = {
    asf::keyInt("max_iterations", "100", "MRPT's max_iterations (Levenberg-Marquardt loops)", 1,
                100000),
    asf::keyDouble("initial_lambda", "0", "MRPT's initial_lambda; 0: tau * max(diag(H))", 0,
                   1e20),
    asf::keyDouble("tau", "1e-3", "MRPT's tau, the initial damping when initial_lambda is 0",
                   0, 1e6),
    asf::keyDouble("e1", "1e-6", "MRPT's stop criterion 1: infinity norm of the gradient", 0,
                   1e6),
    asf::keyDouble("e2", "1e-6", "MRPT's stop criterion 2: relative step size", 0, 1e6),
    asf::keyInt("marginals_max_nodes", "1000",
                "marginals() inverts the dense information matrix (MRPT gives no "
                "covariances); larger graphs throw asf::Error",
                1, 100000),
};

}  // namespace

ASF_PLUGIN(MrptLevmarqBackend, asf::PluginKind::Backend, "mrpt_levmarq", "1.0.0",
           "MRPT's optimize_graph_spa_levmarq (baseline); dense marginals for small graphs",
           asf::ThreadSafety::ThreadCompatible, kKeys)
