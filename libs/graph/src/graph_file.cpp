#include <asf/errors.h>
#include <asf/graph/file.h>
#include <asf/graph/topology_json.h>

#include <filesystem>

namespace asf::graph {

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

GraphFile fromG2o(const std::string& path, bool unit, NoiseReference reference) {
  GraphFile l;
  l.pose_graph = readG2o(path);
  const PoseGraph& pg = *l.pose_graph;
  if (pg.edges.empty()) throw InputError(path + ": the pose graph has no edges");
  l.noise = boundedNoise(pg, reference);
  l.g = poseGraphAsMultigraph(pg, unit ? std::vector<double>{} : l.noise->alpha);
  for (const auto& n : pg.nodes) l.positions.emplace_back(n.pose.x(), n.pose.y());
  return l;
}

GraphFile fromTopologyJson(const std::string& path) {
  RegionGraph r = readTopologyJson(path);
  GraphFile l;
  l.g = std::move(r.graph);
  for (const auto& [x, y] : r.centroids) l.positions.emplace_back(x, y);
  return l;
}

}  // namespace

const ListedGraph& graphOnLine(const std::vector<ListedGraph>& list, const std::string& path,
                               std::optional<int> line) {
  if (list.empty()) throw InputError(path + ": no graph in the file");
  if (!line) return list.front();
  for (const auto& lg : list)
    if (lg.line == *line) return lg;
  throw InputError(path + ":" + std::to_string(*line) + ": no graph on that line");
}

GraphFile readGraphFile(const std::string& path_in, std::optional<int> line, bool unit,
                        NoiseReference reference) {
  namespace fs = std::filesystem;
  std::string path = path_in;
  if (fs::is_directory(path)) {
    path = (fs::path(path) / "graph.g2o").string();
    if (!fs::exists(path))
      throw InputError(path_in + ": a directory without graph.g2o (expected an asf run output)");
  }
  const bool g2o = endsWith(path, ".g2o"), topo = endsWith(path, ".json");
  if ((g2o || topo) && line) throw InputError(path + ": --index applies to graph lists only");
  if (g2o) return fromG2o(path, unit, reference);
  if (topo) return fromTopologyJson(path);
  const std::vector<ListedGraph> list = readGraphList(path);
  const ListedGraph& pick = graphOnLine(list, path, line);
  GraphFile l;
  l.g = pick.graph;
  l.line = pick.line;
  return l;
}

}  // namespace asf::graph
