// Loop-closure alignment (loop_search.h) where the estimate has drifted: in a corridor of
// identical doors, ICP from the estimate and its perturbations converges to the wrong door
// and agrees with itself (a false loop the front-end's gates accept, as it matches the drifted
// estimate); the correlative search sees both doors in its window and refuses. In a room,
// the correlative search finds the loop from estimates 2 m and 17 degrees off.
#include <asf/pose_covariance.h>
#include <gtest/gtest.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "../loop_search.h"
#include "../match_gates.h"
#include "test_worlds.h"

namespace {

using asf::icp_graph::Cloud;
using asf::icp_graph::LoopSearchOptions;
using asf::icp_graph::poseDiff;
using mrpt::poses::CPose2D;

using asf_test_worlds::doors;
using asf_test_worlds::room;
using asf_test_worlds::World;

/// A laser scan from `pose` (361 rays over 360 degrees, range noise 1 cm) as a cloud in the
/// frame of `pose`: the nearest segment along each ray.
Cloud scan(const World& w, const CPose2D& pose, double max_range, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, 0.01);
  std::vector<float> xs, ys;
  for (int k = 0; k < 360; ++k) {
    const double a = k * M_PI / 180;
    const double best = asf_test_worlds::castRay(w, pose.x(), pose.y(), pose.phi() + a, max_range);
    if (best >= max_range) continue;
    const double r = best + noise(rng);
    xs.push_back(static_cast<float>(r * std::cos(a)));
    ys.push_back(static_cast<float>(r * std::sin(a)));
  }
  return Cloud::fromPoints(xs, ys);
}

/// The candidate's submap: scans from `poses`, in the frame of the first.
Cloud submap(const World& w, const std::vector<CPose2D>& poses, double max_range) {
  Cloud out;
  for (std::size_t k = 0; k < poses.size(); ++k)
    out.add(scan(w, poses[k], max_range, 100 + static_cast<unsigned>(k)),
            CPose2D() - poses[0] + poses[k]);
  return out;
}

LoopSearchOptions options(bool correlative) {
  LoopSearchOptions o;
  o.correlative = correlative;
  o.csm.window_xy = 4.0;  // wider than the doors' period: both doors are in view
  o.csm.window_phi = 0.35;
  o.csm.resolution = 0.05;
  o.csm.sigma = 0.05;
  return o;
}

}  // namespace

/// The corridor of identical doors (a door every 3 m): the first visit's scans every 1.5 m
/// along it in the frame of the one at xi = (15, 1, 0), and a scan of the revisit at xj.
struct DoorsLoop {
  World w = doors(40);
  CPose2D xi{15, 1, 0}, xj{15.4, 1.1, 0.05};
  Cloud ref, cur;
  CPose2D truth;
  DoorsLoop() {
    std::vector<CPose2D> visit{xi};
    for (double x = 3; x <= 30; x += 1.5) visit.emplace_back(x, 1, 0);
    ref = submap(w, visit, 12);
    cur = scan(w, xj, 8, 7);
    truth = CPose2D() - xi + xj;
  }
};

/// A room seen from xi = (3, 2, 0) (the candidate's submap) and from `xj` (the new scan).
struct RoomLoop {
  World w = room();
  CPose2D xi{3, 2, 0}, xj;
  Cloud ref, cur;
  CPose2D truth;
  explicit RoomLoop(const CPose2D& j) : xj(j) {
    ref = submap(w, {xi}, 12);
    cur = scan(w, xj, 12, 9);
    truth = CPose2D() - xi + xj;
  }
};

TEST(LoopSearch, RepeatedDoorsFoolIcpNotTheCorrelativeSearch) {
  const DoorsLoop d;
  const Cloud& ref = d.ref;
  const Cloud& cur = d.cur;
  const CPose2D& truth = d.truth;
  // Drift of one door period, and a little more.
  const CPose2D est = truth + CPose2D(3.05, 0.04, 0.02);

  std::string why, how;
  const auto naive = asf::icp_graph::loopAlignment(ref, cur, est, options(false), why, how);
  ASSERT_TRUE(naive) << why;
  const Eigen::Vector3d off = poseDiff(naive->pose, truth);
  EXPECT_NEAR(std::hypot(off.x(), off.y()), 3.0, 0.1) << "ICP took the wrong door: " << how;
  EXPECT_GT(naive->goodness, 0.8);
  EXPECT_GT(naive->inlier_ratio, 0.8);
  EXPECT_LT(naive->rmse, 0.03);
  const Eigen::Vector3d vs_est = poseDiff(naive->pose, est);
  EXPECT_LT(std::hypot(vs_est.x(), vs_est.y()), 0.3) << "it agrees with the drifted estimate";

  why.clear();
  const auto ours = asf::icp_graph::loopAlignment(ref, cur, est, options(true), why, how);
  EXPECT_FALSE(ours) << how;
  EXPECT_NE(why.find("ambiguous"), std::string::npos) << why;
}

TEST(LoopSearch, TheCorrelativeSearchFindsALoopFromAnEstimateFarOff) {
  const RoomLoop r(CPose2D(3.6, 1.7, 0.3));
  const Cloud& ref = r.ref;
  const Cloud& cur = r.cur;
  const CPose2D& truth = r.truth;
  for (const CPose2D& error : {CPose2D(1.0, -0.8, 0.25), CPose2D(-1.7, 1.2, -0.3)}) {
    SCOPED_TRACE(error.asString());
    std::string why, how;
    const auto ours =
        asf::icp_graph::loopAlignment(ref, cur, truth + error, options(true), why, how);
    ASSERT_TRUE(ours) << why;
    const Eigen::Vector3d d = poseDiff(ours->pose, truth);
    EXPECT_LT(std::hypot(d.x(), d.y()), 0.02) << how;
    EXPECT_LT(std::abs(d.z()), 0.01);
  }
}

// The ICP verification's cheap check first: a run from the estimate that fails the caller's
// gate ends the verification (one ICP); one that passes is tested by the perturbed guesses
// in order, which stop as soon as min_agree agree, and the result is the estimate's run.
TEST(LoopSearch, IcpVerificationStopsAtTheGateAndOnceEnoughAgree) {
  const RoomLoop r(CPose2D(3.3, 1.8, 0.1));
  const Cloud& ref = r.ref;
  const Cloud& cur = r.cur;
  const CPose2D& truth = r.truth;
  const CPose2D est = truth + CPose2D(0.05, -0.04, 0.02);
  LoopSearchOptions o = options(false);
  int gate_calls = 0;
  asf::icp_graph::MatchResult gated;
  const asf::icp_graph::LoopGate refuse = [&](const asf::icp_graph::MatchResult& m) {
    ++gate_calls;
    gated = m;
    return std::string("rmse too high (test)");
  };
  std::string why, how;
  EXPECT_FALSE(asf::icp_graph::loopAlignment(ref, cur, est, o, why, how, refuse));
  EXPECT_EQ(gate_calls, 1);
  EXPECT_EQ(why, "from the estimate: rmse too high (test)");
  const Eigen::Vector3d g = poseDiff(gated.pose, truth);
  EXPECT_LT(std::hypot(g.x(), g.y()), 0.02) << "the gate saw the estimate's ICP run";

  for (int need : {1, 4, 7}) {
    SCOPED_TRACE(need);
    o.min_agree = need;
    why.clear();
    const auto found = asf::icp_graph::loopAlignment(
        ref, cur, est, o, why, how,
        [](const asf::icp_graph::MatchResult&) { return std::string(); });
    ASSERT_TRUE(found) << why;
    EXPECT_EQ(how, std::to_string(need) + "/" + std::to_string(need) + " guesses agree");
    const Eigen::Vector3d d = poseDiff(found->pose, truth);
    EXPECT_LT(std::hypot(d.x(), d.y()), 0.02);
    EXPECT_LT(std::abs(d.z()), 0.01);
  }
}

// Guesses that cannot all reach the same pose: a corridor of identical doors seen from an
// estimate between two of them. The verification gives up as soon as min_agree is out of
// reach, and says how many it tried.
TEST(LoopSearch, IcpVerificationGivesUpWhenAgreementIsOutOfReach) {
  const DoorsLoop d;
  LoopSearchOptions o = options(false);
  o.min_agree = 7;
  o.perturb_xy = 1.5;  // half a door period: the shifted guesses fall into other doors
  std::string why, how;
  const auto found = asf::icp_graph::loopAlignment(d.ref, d.cur, d.truth, o, why, how);
  ASSERT_FALSE(found) << how;
  EXPECT_EQ(why.rfind("only ", 0), 0u) << why;
  EXPECT_NE(why.find("(7 needed)"), std::string::npos) << why;
}

TEST(LoopSearch, TwoLoopClosuresAgreeOnlyWhenTheirCycleCloses) {
  // Old keyframes ia, ib and new ones ja, jb; the truth, and hypotheses built from it.
  const CPose2D ia(2, 1, 0.3), ib(3.2, 1.4, 0.5), ja(2.3, 0.8, 2.9), jb(3.0, 1.9, -2.8);
  const Eigen::Matrix3d C = Eigen::Vector3d(0.02 * 0.02, 0.02 * 0.02, 0.01 * 0.01).asDiagonal();
  const asf::icp_graph::LoopHypothesis a{0, 10, CPose2D() - ia + ja, C};
  asf::icp_graph::LoopHypothesis b{1, 11, CPose2D() - ib + jb, C};
  const CPose2D ia_to_ib = CPose2D() - ia + ib, ja_to_jb = CPose2D() - ja + jb;
  EXPECT_NEAR(asf::icp_graph::loopPairChi2(a, b, ia_to_ib, C, ja_to_jb, C), 0.0, 1e-12);
  // b one door off (0.6 m along its x): the cycle does not close.
  b.mean = b.mean + CPose2D(0.6, 0, 0);
  EXPECT_GT(asf::icp_graph::loopPairChi2(a, b, ia_to_ib, C, ja_to_jb, C), 100.0);
  // Both off the same way in the world (an aliased place seen twice): they agree, which is
  // the test's known limit.
  const CPose2D shift(0.6, 0, 0);
  const asf::icp_graph::LoopHypothesis a2{0, 10, CPose2D() - ia + (shift + ja), C};
  const asf::icp_graph::LoopHypothesis b2{1, 11, CPose2D() - ib + (shift + jb), C};
  EXPECT_NEAR(asf::icp_graph::loopPairChi2(a2, b2, ia_to_ib, C, ja_to_jb, C), 0.0, 1e-9);
}

// A held loop from old keyframe 21, "confirmed" by one from old keyframe 756: the cycle runs
// through 735 keyframes of sequential edges, whose chain covariance (metres) lets a loop 4.6 m
// along a corridor off agree (infinite-corridor's wrong edges). Only a partner whose old
// keyframe is near the held one's tests anything.
TEST(LoopSearch, ConfirmationNeedsTheSamePairOfPlaces) {
  const CPose2D ia(0, 0, 0), ib(1.5, 0.3, 0.1), ja(0.4, 0.6, 3.1), jb(2.2, 0.5, 3.0);
  const Eigen::Matrix3d C = Eigen::Vector3d(0.02 * 0.02, 0.02 * 0.02, 0.01 * 0.01).asDiagonal();
  const Eigen::Matrix3d long_chain = Eigen::Vector3d(3.0 * 3.0, 3.0 * 3.0, 0.1 * 0.1).asDiagonal();
  const CPose2D shift(4.6, 0, 0);  // the held loop lands one corridor bay off
  const asf::icp_graph::LoopHypothesis held{21, 765, CPose2D() - ia + (shift + ja), C};
  const asf::icp_graph::LoopHypothesis far{756, 763, CPose2D() - ib + jb, C};
  const CPose2D ia_to_ib = CPose2D() - ia + ib, ja_to_jb = CPose2D() - ja + jb;
  EXPECT_LT(asf::icp_graph::loopPairChi2(held, far, ia_to_ib, long_chain, ja_to_jb, C), 11.34)
      << "through a long chain the wrong loop agrees";
  EXPECT_GT(asf::icp_graph::loopPairChi2(held, far, ia_to_ib, C, ja_to_jb, C), 100.0)
      << "through a short, certain chain it would not";
  EXPECT_TRUE(asf::icp_graph::mayConfirm(held, far, 0)) << "span 0: any partner";
  EXPECT_FALSE(asf::icp_graph::mayConfirm(held, far, 30));
  const asf::icp_graph::LoopHypothesis near{24, 767, CPose2D(), C};
  EXPECT_TRUE(asf::icp_graph::mayConfirm(held, near, 30));
  EXPECT_TRUE(asf::icp_graph::mayConfirm(near, held, 3)) << "symmetric: 3 keyframes apart";
  EXPECT_FALSE(asf::icp_graph::mayConfirm(near, held, 2));
  EXPECT_FALSE(asf::icp_graph::mayConfirm(held, {21, 770, CPose2D(), C}, 0)) << "same old scan";
  EXPECT_FALSE(asf::icp_graph::mayConfirm(held, {30, 765, CPose2D(), C}, 0)) << "same new scan";
}

TEST(LoopSearch, InverseCovarianceMatchesFiniteDifferences) {
  const CPose2D p(1.3, -0.7, 0.9);
  Eigen::Matrix3d J;  // d(-p)/dp numerically
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d h = Eigen::Vector3d::Zero();
    h(k) = 1e-6;
    const CPose2D up(p.x() + h(0), p.y() + h(1), p.phi() + h(2));
    const CPose2D down(p.x() - h(0), p.y() - h(1), p.phi() - h(2));
    J.col(k) = poseDiff(CPose2D() - up, CPose2D() - down) / 2e-6;
  }
  Eigen::Matrix3d C;
  C << 0.04, 0.01, 0.002, 0.01, 0.09, -0.003, 0.002, -0.003, 0.01;
  Eigen::Matrix3d out;
  const CPose2D q = asf::inverseWithCov(p, C, out);
  EXPECT_LT(poseDiff(q, CPose2D() - p).norm(), 1e-12);
  EXPECT_LT((out - J * C * J.transpose()).norm(), 1e-8);
}

namespace {

/// A first pass along y = 0 (nodes 0..9, 0.5 m apart), an excursion far away (10..29), and
/// a second pass (30, 31, then the new keyframe 32) back along y = 0.2; every node has a
/// scan and consecutive nodes are joined. `links` adds edges (from, to).
asf::PoseGraph secondPass(const std::vector<std::pair<asf::NodeId, asf::NodeId>>& links) {
  asf::PoseGraph g;
  for (int k = 0; k < 10; ++k) g.addNode(CPose2D(0.5 * k, 0, 0));
  for (int k = 10; k < 30; ++k) g.addNode(CPose2D(0, 50 + k, 0));
  g.addNode(CPose2D(1.0, 0.2, 0));
  g.addNode(CPose2D(1.5, 0.2, 0));
  g.addNode(CPose2D(2.0, 0.2, 0));
  auto any_scan = std::make_shared<const mrpt::obs::CObservation2DRangeScan>();
  for (auto& n : g.nodes) n.scan = any_scan;
  auto join = [&](asf::NodeId a, asf::NodeId b) {
    asf::PoseEdge e;
    e.from = a;
    e.to = b;
    g.addEdge(e);
  };
  for (asf::NodeId k = 0; k + 1 < g.size(); ++k) join(k, k + 1);
  for (const auto& [a, b] : links) join(a, b);
  return g;
}

std::vector<asf::NodeId> candidates(const asf::PoseGraph& g, bool skip_linked, int min_gap = 1) {
  asf::icp_graph::CandidateGate o;
  o.skip_recent = 20;
  o.radius = 3;
  o.max_candidates = 3;
  o.skip_linked = skip_linked;
  o.min_gap = min_gap;
  return asf::icp_graph::loopCandidates(g, 32, 31, nullptr, std::nullopt, o);
}

}  // namespace

// Karto's "near linked scans": a first-pass keyframe the graph already ties to the previous
// keyframe through edges between keyframes near the new one is no loop candidate; one tied
// only through keyframes far away (or through the new keyframe's own edges) still is.
TEST(LoopSearch, CandidatesLeaveOutKeyframesLinkedNearby) {
  const std::vector<asf::NodeId> nearest{4, 3, 5};  // (2, 0), (1.5, 0), (2.5, 0)
  EXPECT_EQ(candidates(secondPass({}), true), nearest) << "no link: a loop";
  EXPECT_EQ(candidates(secondPass({{2, 30}}), false), nearest) << "skip_linked off";
  EXPECT_TRUE(candidates(secondPass({{2, 30}}), true).empty())
      << "30 -> 2 ties the whole first pass to the previous keyframe";
  EXPECT_EQ(candidates(secondPass({{30, 15}, {15, 3}}), true), nearest)
      << "a tie through node 15, 50 m away, is no tie near the new keyframe";
  EXPECT_EQ(candidates(secondPass({{7, 32}}), true), nearest)
      << "the new keyframe's own edges do not count";

  const asf::PoseGraph g = secondPass({{2, 30}});
  const std::vector<char> linked = asf::icp_graph::linkedNear(g, 31, g.nodes[32].pose, 3, 32);
  for (asf::NodeId k = 0; k < g.size(); ++k)
    EXPECT_EQ(linked[k], k < 10 || k == 30 || k == 31) << "node " << k;
}

// Candidates a few keyframes apart would search nearly the same reference: with a gap, the
// next nearest far enough along the trajectory from every one taken.
TEST(LoopSearch, CandidatesKeepTheirGapAlongTheTrajectory) {
  const asf::PoseGraph g = secondPass({});
  // Distances from (2, 0.2): 4 0.2 m; 3 and 5 0.54 m; 2 and 6 1.02 m; 1 and 7 1.51 m.
  EXPECT_EQ(candidates(g, false, 1), (std::vector<asf::NodeId>{4, 3, 5}));
  EXPECT_EQ(candidates(g, false, 2), (std::vector<asf::NodeId>{4, 2, 6}));
  EXPECT_EQ(candidates(g, false, 3), (std::vector<asf::NodeId>{4, 1, 7}));
  EXPECT_EQ(candidates(g, false, 10), (std::vector<asf::NodeId>{4}))
      << "every other first-pass keyframe is within 10 of node 4";
}

namespace {

TEST(MatchGates, SequentialGateSaysWhichTestFailed) {
  asf::icp_graph::MatchGates g;
  g.max_iterations = 80;
  g.max_sigma_xy = 0.1;
  g.max_sigma_phi = 0.05;
  g.odometry_chi2 = 16;
  const Eigen::Matrix3d odo_cov = Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal();
  asf::icp_graph::MatchResult m;
  m.ran = true;
  m.iterations = 10;
  m.goodness = 0.4;
  m.pose = CPose2D(1.0, 0.0, 0.0);
  m.cov = Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal();
  const CPose2D odo(1.01, 0.0, 0.0);  // chi2 = 0.01^2 / 2e-4 = 0.5
  EXPECT_NE(sequentialGateFailure(m, odo, odo_cov, 0.6, g).find("goodness 0.4 < 0.6"),
            std::string::npos);
  // The likelihood path's gate: everything but goodness.
  EXPECT_EQ(sequentialGateFailure(m, odo, odo_cov, 0.0, g), "");
  EXPECT_NE(sequentialGateFailure(m, CPose2D(1.2, 0, 0), odo_cov, 0.0, g).find("disagrees"),
            std::string::npos);
  asf::icp_graph::MatchResult ill = m;
  ill.cov(1, 1) = 0.2 * 0.2;  // the std of one direction above max_sigma_xy
  EXPECT_NE(sequentialGateFailure(ill, odo, odo_cov, 0.0, g).find("ill-conditioned"),
            std::string::npos);
  asf::icp_graph::MatchResult slow = m;
  slow.iterations = 80;
  EXPECT_NE(sequentialGateFailure(slow, odo, odo_cov, 0.0, g).find("did not converge"),
            std::string::npos);
  asf::icp_graph::MatchResult none;  // never ran: refused even without a reason
  EXPECT_NE(sequentialGateFailure(none, odo, odo_cov, 0.0, g), "");
  none.reason = "too few points";
  EXPECT_EQ(sequentialGateFailure(none, odo, odo_cov, 0.0, g), "too few points");
}

TEST(MatchGates, SearchWindowCoversTheSigmasWithinItsBounds) {
  // Position stds 0.2 and 0.1 m (the larger counts), heading std 0.05 rad.
  const Eigen::Matrix3d C = Eigen::Vector3d(0.01, 0.04, 0.0025).asDiagonal();
  auto w = asf::icp_graph::windowCovering(C, 3, 0.1, 8, 0.01, M_PI);
  EXPECT_NEAR(w.xy, 0.6, 1e-12);
  EXPECT_NEAR(w.phi, 0.15, 1e-12);
  w = asf::icp_graph::windowCovering(C, 3, 2, 8, 0.35, M_PI);  // the minimum wins
  EXPECT_EQ(w.xy, 2);
  EXPECT_EQ(w.phi, 0.35);
  w = asf::icp_graph::windowCovering(100 * C, 3, 0.1, 5, 0.01, 1);  // the maximum wins
  EXPECT_EQ(w.xy, 5);
  EXPECT_EQ(w.phi, 1);
  // A rotated covariance: the largest eigenvalue, not a diagonal entry.
  Eigen::Matrix3d R = Eigen::Matrix3d::Zero();
  R(0, 0) = R(1, 1) = 0.025;
  R(0, 1) = R(1, 0) = 0.015;  // eigenvalues 0.04 and 0.01
  R(2, 2) = 0.0025;
  EXPECT_NEAR(asf::icp_graph::windowCovering(R, 3, 0.1, 8, 0.01, M_PI).xy, 0.6, 1e-9);
}

}  // namespace
