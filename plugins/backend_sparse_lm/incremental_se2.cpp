// sparse_lm's incremental mode: see incremental_se2.h.
#include "incremental_se2.h"

#include <asf/errors.h>
#include <asf/pose_covariance.h>
#include <asf/se2_edge.h>
#include <asf/text.h>

#include <Eigen/Dense>
#include <algorithm>
#include <deque>

#include "sparse_problem.h"

namespace asf::sparse_lm {

using asf::NodeId;

namespace {

Eigen::Vector3d poseVector(const asf::PoseNode& n) {
  return {n.pose.x(), n.pose.y(), n.pose.phi()};
}

}  // namespace

bool IncrementalSe2::extendsLast(const asf::PoseGraph& g) const {
  if (!have_ || g.size() < poses_.size() || g.edges.size() < edges_.size() || g.fixed != fixed_)
    return false;
  for (std::size_t i = 0; i < poses_.size(); ++i)
    if (poseVector(g.nodes[i]) != poses_[i]) return false;
  for (std::size_t k = 0; k < edges_.size(); ++k) {
    const auto& e = g.edges[k];
    const EdgeCopy& c = edges_[k];
    if (e.from != c.from || e.to != c.to || e.mean.x() != c.x || e.mean.y() != c.y ||
        e.mean.phi() != c.phi || e.information != c.information)
      return false;
  }
  return true;
}

void IncrementalSe2::syncEdges(const asf::PoseGraph& g, bool extends) {
  if (!extends) {
    edges_.clear();
    incident_.clear();
    marg_ = {};  // its blocks belong to another graph: never propagated from
    update_.stop();
  }
  incident_.resize(g.size());
  for (std::size_t k = edges_.size(); k < g.edges.size(); ++k) {
    const auto& e = g.edges[k];
    edges_.push_back({e.from, e.to, e.mean.x(), e.mean.y(), e.mean.phi(), e.information});
    incident_[e.from].push_back(k);
    if (e.to != e.from) incident_[e.to].push_back(k);
  }
  fixed_ = g.fixed;
  have_ = true;
}

void IncrementalSe2::rememberPoses(const asf::PoseGraph& g) {
  poses_.resize(g.size());
  for (std::size_t i = 0; i < g.size(); ++i) poses_[i] = poseVector(g.nodes[i]);
}

std::vector<NodeId> IncrementalSe2::window(const asf::PoseGraph& g, std::size_t old_nodes,
                                           std::size_t old_edges, std::size_t factor_nodes,
                                           int hops) const {
  const std::size_t n = g.size();
  std::vector<int> depth(n, -1);
  std::deque<NodeId> queue;
  auto seed = [&](NodeId v) {
    if (depth[v] < 0) {
      depth[v] = 0;
      queue.push_back(v);
    }
  };
  for (std::size_t v = old_nodes; v < n; ++v) seed(static_cast<NodeId>(v));
  for (std::size_t k = old_edges; k < g.edges.size(); ++k) {
    seed(g.edges[k].from);
    seed(g.edges[k].to);
  }
  std::vector<NodeId> out;
  while (!queue.empty()) {
    const NodeId v = queue.front();
    queue.pop_front();
    out.push_back(v);
    if (depth[v] >= hops) continue;
    for (std::size_t k : incident_[v]) {
      const auto& e = g.edges[k];
      const NodeId w = e.from == v ? e.to : e.from;
      if (depth[w] < 0) {
        depth[w] = depth[v] + 1;
        queue.push_back(w);
      }
    }
  }
  // Nodes the last whole factorization does not know must all be at their window optimum:
  // the bound leaves their gradient out.
  for (std::size_t v = factor_nodes; v < n; ++v)
    if (depth[v] < 0) {
      depth[v] = 0;
      out.push_back(static_cast<NodeId>(v));
    }
  std::sort(out.begin(), out.end());
  return out;
}

asf::OptimizeReport IncrementalSe2::solveWhole(asf::PoseGraph& g, const Options& o,
                                               const IncrementalOptions& io,
                                               const std::string& why) {
  asf::OptimizeReport r = whole_.optimize(g, o);
  update_.stop();  // whole_'s factor is now a damped one of another graph
  cost_ = r.final_chi2;
  ++counters_.whole_solves;
  counters_.last_path = "whole graph (" + why + ")";
  last_whole_ = true;
  rememberPoses(g);
  return r;
}

asf::OptimizeReport IncrementalSe2::optimize(asf::PoseGraph& g, const Options& o,
                                             const IncrementalOptions& io) {
  if (!io.enabled) {
    have_ = false;  // nothing remembered: the next enabled call starts with a whole solve
    ++counters_.whole_solves;
    counters_.last_path = "whole graph (incremental off)";
    marg_ = {};
    update_.stop();
    return whole_.optimize(g, o);
  }
  const bool extends = extendsLast(g);
  const std::size_t old_nodes = extends ? poses_.size() : 0;
  const std::size_t old_edges = extends ? edges_.size() : 0;
  syncEdges(g, extends);
  if (!extends) return solveWhole(g, o, io, "not an extension of the last graph");
  const std::size_t factor_nodes = whole_.factorNodes();
  if (factor_nodes == 0) return solveWhole(g, o, io, "no factorization yet");
  const std::vector<NodeId> w = window(g, old_nodes, old_edges, factor_nodes, io.hops);
  if (w.size() > io.max_window || 2 * w.size() > g.size())
    return solveWhole(g, o, io, std::to_string(w.size()) + " window nodes");

  // The objective at the incoming poses: the remembered graph's plus the new edges'.
  std::vector<std::size_t> new_edges(g.edges.size() - old_edges);
  for (std::size_t k = 0; k < new_edges.size(); ++k) new_edges[k] = old_edges + k;
  double initial = cost_;
  for (const auto& e : detail::Problem(g, new_edges, o).edges) {
    const Eigen::Vector3d r =
        asf::se2::edgeError(poseVector(g.nodes[e.from]), poseVector(g.nodes[e.to]), e.z);
    initial += robustCost(e.kernel, o.robust_delta, r.dot(e.W * r));
  }
  std::vector<std::size_t> edges;
  for (NodeId v : w) edges.insert(edges.end(), incident_[v].begin(), incident_[v].end());
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  Options local = o;
  local.lago_init = false;
  local.verbosity = 0;
  const asf::OptimizeReport wr = window_.optimizeWindow(g, w, edges, local);
  const std::optional<double> bound = whole_.decrementBound(g, o);
  counters_.last_bound = bound ? *bound : -1;
  if (!bound || *bound > io.gap) {
    ++counters_.bound_exceeded;
    const std::string why = bound ? "bound " + asf::formatSignificant(*bound, 4) + " after a " +
                                        std::to_string(w.size()) + "-node window"
                                  : "no bound";
    asf::OptimizeReport r = solveWhole(g, o, io, why);
    r.initial_chi2 = initial;  // before the window moved anything
    return r;
  }
  ++counters_.window_solves;
  last_whole_ = false;
  rememberPoses(g);
  asf::OptimizeReport r;
  r.initial_chi2 = initial;
  r.final_chi2 = cost_ = initial + (wr.final_chi2 - wr.initial_chi2);  // only its edges moved
  r.iterations = wr.iterations;
  r.converged = wr.converged;
  r.message = "window of " + std::to_string(w.size()) + " nodes (" + wr.message +
              "); a whole-graph step would gain at most " + asf::formatSignificant(*bound, 4);
  counters_.last_path = "window of " + std::to_string(w.size()) + " nodes";
  return r;
}

bool IncrementalSe2::propagate(const asf::PoseGraph& g) {
  const std::size_t known = marg_.node.size();
  if (known == 0 || known > g.size()) return false;
  marg_.node.resize(g.size());
  for (std::size_t j = known; j < g.size(); ++j) {
    // Each edge between j and an older node gives an upper bound of Cov(x_j): the marginal
    // with that edge's information only. The smallest (by trace) is kept: after a revisit
    // the edge to the old place, not the chain's dead reckoning.
    bool any = false;
    double best = 0;
    for (std::size_t k : incident_[j]) {
      const auto& e = g.edges[k];
      const bool into = e.to == j && e.from < j, out_of = e.from == j && e.to < j;
      if (!into && !out_of) continue;
      const NodeId i = into ? e.from : e.to;
      const Eigen::Matrix3d Ce = asf::edgeCovarianceInFrom(e);  // frame of e.from
      Eigen::Matrix3d C;
      if (into) {
        asf::composeWithCov(g.nodes[i].pose, marg_.node[i], e.mean, Ce, C);
      } else {  // x_j = x_i (+) mean^-1
        Eigen::Matrix3d Cinv;
        const mrpt::poses::CPose2D inv = asf::inverseWithCov(e.mean, Ce, Cinv);
        asf::composeWithCov(g.nodes[i].pose, marg_.node[i], inv, Cinv, C);
      }
      if (!any || C.trace() < best) {
        marg_.node[j] = 0.5 * (C + C.transpose());
        best = C.trace();
        any = true;
      }
    }
    if (!any) return false;
  }
  return true;
}

asf::Marginals IncrementalSe2::marginals(const asf::PoseGraph& g,
                                         const std::vector<std::pair<NodeId, NodeId>>& cross,
                                         const Options& o, const IncrementalOptions& io) {
  if (!io.enabled) {
    ++counters_.exact_marginals;
    update_.stop();
    return whole_.marginals(g, cross, o);
  }
  const bool same = g.size() == poses_.size() && g.edges.size() == edges_.size() && extendsLast(g);
  const bool after_window = cross.empty() && same && !last_whole_;
  if (after_window && io.marginals == MarginalsMode::Updated &&
      update_.update(g, whole_, o, io.update_max_nodes, io.update_max_touched, marg_)) {
    ++counters_.updated_marginals;
    return marg_;
  }
  if (after_window && io.marginals == MarginalsMode::Propagated && propagate(g)) {
    ++counters_.propagated_marginals;
    marg_.cross.clear();
    marg_.graph_revision = g.revision;
    return marg_;
  }
  marg_ = whole_.marginals(g, cross, o);
  ++counters_.exact_marginals;
  if (same) {
    last_whole_ = true;  // the factor is now the whole graph's at these poses
    update_.start(g, marg_);
  } else {
    update_.stop();
  }
  return marg_;
}

}  // namespace asf::sparse_lm
