/// \file frontend_tests.cpp
/// Conformance tests of `frontend` plugins (see frontend.h), on exact synthetic laser frames
/// of SegmentWorld::twoRooms(5, 4, 1).
#include <asf/errors.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <cmath>
#include <map>
#include <mutex>
#include <sstream>

#include "kit.h"
#include "synthetic.h"

namespace asf::conformance::detail {

using mrpt::poses::CPose2D;

namespace {

constexpr double kPoseTolerance = 0.1;  ///< metres and radians
constexpr std::size_t kMaxProblems = 8;

struct Problems {
  std::vector<std::string> first_frame, growth, revision, edges, pose;
};

void note(std::vector<std::string>& list, const std::string& what) {
  if (list.size() < kMaxProblems) list.push_back(what);
  else if (list.size() == kMaxProblems) list.push_back("(more problems not shown)");
}

std::string str(const CPose2D& p) {
  std::ostringstream os;
  os << "(" << p.x() << ", " << p.y() << ", " << p.phi() << ")";
  return os.str();
}

struct FeedResult {
  Problems problems;
  Trace trace;
  std::string exception;  ///< set when process()/currentPose() threw (feeding stopped)
};

/// Growth: ids consecutive, nothing removed, existing nodes never move.
void checkGrowth(const std::string& at, const PoseGraph& before, const PoseGraph& graph,
                 Problems& pr) {
  if (graph.nodes.size() < before.nodes.size())
    note(pr.growth, at + "nodes were removed");
  if (graph.edges.size() < before.edges.size())
    note(pr.growth, at + "edges were removed");
  for (std::size_t i = before.nodes.size(); i < graph.nodes.size(); ++i)
    if (graph.nodes[i].id != i)
      note(pr.growth, at + "node at index " + std::to_string(i) + " has id " +
                          std::to_string(graph.nodes[i].id));
  for (std::size_t i = 0; i < std::min(before.nodes.size(), graph.nodes.size()); ++i)
    if (!samePose(graph.nodes[i].pose, before.nodes[i].pose, 1e-12))
      note(pr.growth, at + "existing node " + std::to_string(i) + " moved from " +
                          str(before.nodes[i].pose) + " to " + str(graph.nodes[i].pose));
  for (std::size_t i = 0; i < std::min(before.edges.size(), graph.edges.size()); ++i)
    if (graph.edges[i].from != before.edges[i].from || graph.edges[i].to != before.edges[i].to)
      note(pr.growth, at + "existing edge " + std::to_string(i) + " was changed");
}

/// The edges a frame added: between existing nodes, finite means, SPD information.
void checkNewEdges(const std::string& at, const PoseGraph& before, const PoseGraph& graph,
                   Problems& pr) {
  for (std::size_t i = before.edges.size(); i < graph.edges.size(); ++i) {
    const PoseEdge& e = graph.edges[i];
    const std::string ed = at + "edge " + std::to_string(i) + " (" + std::to_string(e.from) +
                           " -> " + std::to_string(e.to) + "): ";
    if (e.from >= graph.nodes.size() || e.to >= graph.nodes.size())
      note(pr.edges, ed + "references a node that does not exist");
    if (!(std::isfinite(e.mean.x()) && std::isfinite(e.mean.y()) &&
          std::isfinite(e.mean.phi())))
      note(pr.edges, ed + "mean is not finite");
    if (auto r = isSymmetricPd(e.information); !r)
      note(pr.edges, ed + "information " + r.message());
  }
}

/// Feeds a sequence to a frontend, checking the contract after every frame. No GoogleTest
/// assertions here: it also runs in the kit's worker threads.
FeedResult feed(Frontend& p, const FrameSequence& seq) {
  FeedResult out;
  Problems& pr = out.problems;
  Trace& tr = out.trace;
  PoseGraph graph;
  const Marginals marginals;
  for (std::size_t k = 0; k < seq.frames.size(); ++k) {
    const std::string at = "frame " + std::to_string(k) + ": ";
    const PoseGraph before = graph;
    bool changed = false;
    CPose2D current;
    try {
      changed = p.process(seq.frames[k], graph, marginals);
      current = p.currentPose(graph);
    } catch (...) {
      out.exception = at + describeException(std::current_exception());
      return out;
    }
    const std::string l = "frame[" + std::to_string(k) + "]";
    tr.num(l + ".returned", changed);
    tr.num(l + ".nodes", static_cast<double>(graph.nodes.size()));
    tr.num(l + ".edges", static_cast<double>(graph.edges.size()));
    tr.pose(l + ".current", current);

    if (k == 0) {
      if (graph.nodes.empty()) note(pr.first_frame, "the first frame created no node");
      else if (!samePose(graph.nodes[0].pose, CPose2D(), 1e-9))
        note(pr.first_frame, "node 0 is at " + str(graph.nodes[0].pose) + ", not the origin");
      if (!changed) note(pr.first_frame, "process() returned false on the first frame");
    }
    checkGrowth(at, before, graph, pr);

    // Revision and return value.
    const bool grew = graph.nodes.size() != before.nodes.size() ||
                      graph.edges.size() != before.edges.size();
    if (changed && graph.revision <= before.revision)
      note(pr.revision, at + "process() returned true but revision stayed " +
                            std::to_string(graph.revision));
    if (!changed && graph.revision != before.revision)
      note(pr.revision, at + "process() returned false but revision changed");
    if (!changed && grew) note(pr.revision, at + "the graph grew but process() returned false");

    checkNewEdges(at, before, graph, pr);

    // Pose estimate against the truth.
    const CPose2D& truth = seq.truth[k];
    const double dpos = std::hypot(current.x() - truth.x(), current.y() - truth.y());
    const double dang = std::abs(angleDiff(current.phi(), truth.phi()));
    if (!(dpos <= kPoseTolerance && dang <= kPoseTolerance))
      note(pr.pose, at + "currentPose " + str(current) + " vs true " + str(truth) +
                        " (map frame): error " + std::to_string(dpos) + " m, " +
                        std::to_string(dang) + " rad");
  }
  for (std::size_t i = 0; i < graph.nodes.size(); ++i) {
    tr.pose("node[" + std::to_string(i) + "].pose", graph.nodes[i].pose);
    tr.num("node[" + std::to_string(i) + "].timestamp", graph.nodes[i].timestamp);
  }
  for (std::size_t i = 0; i < graph.edges.size(); ++i) {
    const PoseEdge& e = graph.edges[i];
    const std::string l = "edge[" + std::to_string(i) + "]";
    tr.num(l + ".from", e.from);
    tr.num(l + ".to", e.to);
    tr.num(l + ".kind", static_cast<int>(e.kind));
    tr.pose(l + ".mean", e.mean);
    tr.mat(l + ".information", e.information);
  }
  return out;
}

const FrameSequence& sequence(ScanMode mode) {
  static std::mutex m;
  static std::map<ScanMode, FrameSequence> cache;
  std::lock_guard<std::mutex> lock(m);
  auto it = cache.find(mode);
  if (it == cache.end()) it = cache.emplace(mode, makeFrameSequence(mode)).first;
  return it->second;
}

/// The standard run of one plugin, computed once and shared by the tests that only read it.
const FeedResult& standardFeed(KindTest<Frontend>& t) {
  static std::map<const PluginDescriptor*, FeedResult> cache;
  auto it = cache.find(&t.descriptor());
  if (it == cache.end()) {
    auto h = t.make();
    it = cache.emplace(&t.descriptor(), feed(*h, sequence(ScanMode::All))).first;
  }
  return it->second;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += "\n  " + x;
  return s;
}

}  // namespace

Trace standardRun(Frontend& p) {
  FeedResult r = feed(p, sequence(ScanMode::All));
  if (!r.exception.empty()) throw Error(r.exception);
  return r.trace;
}

void registerFrontendTests(const InfoPtr& info) {
  using T = Frontend;
  using Check = std::vector<std::string> Problems::*;
  const auto check = [info](const std::string& name, Check which, const std::string& what) {
    addTest<T>(info, name, Needs::Instance, [which, what](KindTest<T>& t) {
      const FeedResult& r = standardFeed(t);
      ASSERT_EQ(r.exception, "") << "exception escaped from process()/currentPose()";
      const auto& list = r.problems.*which;
      EXPECT_TRUE(list.empty()) << what << ":" << join(list);
    });
  };
  check("first_frame_creates_node_zero_at_origin", &Problems::first_frame,
        "the first frame must create node 0 at the origin and return true");
  check("node_ids_consecutive_and_existing_nodes_never_move", &Problems::growth,
        "nodes must be added with consecutive ids and never moved or removed");
  check("revision_increments_iff_process_returns_true", &Problems::revision,
        "graph.revision must increase exactly when process() returns true");
  check("edges_join_existing_nodes_with_symmetric_pd_information", &Problems::edges,
        "edges must reference existing nodes and carry symmetric positive-definite information");
  check("current_pose_tracks_exact_odometry_within_0_1_m", &Problems::pose,
        "with exact odometry and scans currentPose() must stay within 0.1 m / 0.1 rad of the "
        "truth");

  addTest<T>(info, "frames_without_scan_are_accepted", Needs::Instance, [](KindTest<T>& t) {
    for (ScanMode mode : {ScanMode::SomeMissing, ScanMode::None}) {
      const char* name = mode == ScanMode::None ? "odometry-only frames"
                                                : "frames 0, 4, 8, ... without scan";
      SCOPED_TRACE(name);
      auto h = t.make();
      const FeedResult r = feed(*h, sequence(mode));
      ASSERT_EQ(r.exception, "") << "exception on " << name;
      const Problems& p = r.problems;
      EXPECT_TRUE(p.first_frame.empty()) << join(p.first_frame);
      EXPECT_TRUE(p.growth.empty()) << join(p.growth);
      EXPECT_TRUE(p.revision.empty()) << join(p.revision);
      EXPECT_TRUE(p.edges.empty()) << join(p.edges);
      if (mode == ScanMode::None) {  // nothing but exact odometry: the estimate must follow it
        EXPECT_TRUE(p.pose.empty()) << join(p.pose);
      }
    }
  });
}

}  // namespace asf::conformance::detail
