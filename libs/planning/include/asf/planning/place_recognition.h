#pragma once
/// \file place_recognition.h
/// p_recognition of thesis ch. 3 by Monte Carlo with MRPT's ICP: how likely a robot that
/// believes it is near pose-graph node n, within the localization window, recognizes the
/// place by aligning what it sees with the map. Each sample perturbs the node's pose inside
/// the window, degrades the node's own scan (a contiguous sector occluded, a few rays
/// shortened by clutter), aligns it (CICP, Levenberg-Marquardt) against the local map built
/// from the OTHER keyframes' scans near the node, and succeeds when the recovered pose is
/// within the success thresholds of the node's pose. Feature-poor places (a long corridor)
/// let ICP slide and fail; distinctive ones succeed.
///
/// Deterministic: node n's samples come from a generator seeded by (seed, n), whatever the
/// order in which nodes are queried.
#include <asf/pose_graph.h>

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace asf::planning {

struct RecognitionMcOptions {
  int samples = 40;
  /// Half sizes of the perturbation window: x, y [m], phi [rad] (the localization window).
  double half_x = 0.3, half_y = 0.3, half_phi = 0.5235987755982988;
  /// A sample succeeds when ICP returns within these of the node's pose [m], [rad].
  double success_xy = 0.1, success_phi = 0.08726646259971647;
  double occlusion = 0.25;  ///< up to this fraction of the rays removed, one random sector
  double clutter = 0.05;    ///< this fraction of the rays shortened to a random range
  double map_radius = 6.0;  ///< local map: scans of the other nodes within this distance [m]
  std::uint64_t seed = 1;
};

/// p_recognition of node n in [0, 1]; 0 when the node has no scan or no other node with a
/// scan lies within map_radius (nothing to recognize the place against).
double recognitionProbability(const PoseGraph& g, NodeId n, const RecognitionMcOptions& o);

/// One Monte Carlo sample: where the robot believed it was and where ICP put it (map frame).
struct RecognitionSample {
  mrpt::poses::CPose2D guess, result;
  bool aligned = true;  ///< false: too few rays left to align (a failure, result = guess)
  bool success = false;
};

/// The whole Monte Carlo of node n (thesis Fig. 3.3): the samples, the local map's points
/// and the node's scan (both in the map frame). p is recognitionProbability's value (same
/// draws); samples is empty when that is 0 for want of a scan or a map.
struct RecognitionTrial {
  NodeId node = 0;
  double p = 0;
  std::vector<RecognitionSample> samples;
  std::vector<std::pair<float, float>> map_points, scan_points;
};
RecognitionTrial recognitionTrial(const PoseGraph& g, NodeId n, const RecognitionMcOptions& o);

/// recognitionProbability of every node on `threads` threads (0: one per core); the values
/// do not depend on the thread count. `progress(done, total)` (optional) is called from the
/// worker threads, serialized, every 100 nodes. Rethrows a worker's exception.
std::vector<double> recognitionProbabilities(
    const PoseGraph& g, const RecognitionMcOptions& o, unsigned threads = 0,
    const std::function<void(std::size_t, std::size_t)>& progress = nullptr);

/// Writes "node_id p" lines, the format readRecognitionProbabilities
/// (expected_uncertainty.h) reads; throws asf::Error naming the file.
void writeRecognitionProbabilities(const std::string& path, const std::map<NodeId, double>& p);

}  // namespace asf::planning
