// topology.json both ways: written from a TopoGraph (topology_json.h), read as a region graph
// (multigraph.h; shared by `asf optimal` and the fuzz target).
#include <asf/errors.h>
#include <asf/graph/multigraph.h>
#include <asf/graph/topology_json.h>

#include <climits>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

namespace asf::graph {

namespace {

long regionId(const nlohmann::json& v, const std::string& name, const char* what) {
  if (!v.is_number_integer() ||
      (v.is_number_unsigned() &&
       v.get<unsigned long long>() > static_cast<unsigned long long>(LONG_MAX)))
    throw InputError(name + ": not a topology.json as asf writes it: " + what + " " + v.dump() +
                     " is not a region id (an integer)");
  return v.get<long>();
}

RegionGraph regionGraph(const nlohmann::json& j, const std::string& name) {
  if (!j.is_object() || !j.contains("nodes") || !j.contains("edges") || !j["nodes"].is_array() ||
      !j["edges"].is_array())
    throw InputError(name + ": no \"nodes\" and \"edges\" lists (expected a topology.json)");
  RegionGraph out;
  std::map<long, int> index;
  bool centroids = true;
  for (const auto& n : j["nodes"]) {
    const long r = regionId(n.at("region"), name, "node region");
    if (r <= 0) continue;  // the unexplored node
    if (!index.emplace(r, static_cast<int>(index.size())).second)
      throw InputError(name + ": region " + std::to_string(r) + " is listed twice");
    out.regions.push_back(r);
    const auto c = n.find("centroid");
    if (c != n.end() && c->is_array() && c->size() == 2)
      out.centroids.emplace_back((*c)[0].get<double>(), (*c)[1].get<double>());
    else
      centroids = false;
  }
  if (!centroids) out.centroids.clear();
  out.graph.n = static_cast<int>(index.size());
  for (const auto& e : j["edges"]) {
    if (!e.is_object()) throw InputError(name + ": edge " + e.dump() + " is not an object");
    if (e.value("frontier", false)) continue;
    const auto a = index.find(regionId(e.at("a"), name, "edge end"));
    const auto b = index.find(regionId(e.at("b"), name, "edge end"));
    if (a == index.end() || b == index.end())
      throw InputError(name + ": edge " + e.dump() + " names a region that is not a node");
    out.graph.edges.push_back({a->second, b->second, 1.0});
  }
  return out;
}

}  // namespace

RegionGraph parseTopologyJson(const std::string& text, const std::string& name) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(name + ": not JSON: " + e.what());
  }
  try {
    return regionGraph(j, name);
  } catch (const nlohmann::json::exception& e) {  // a field missing or of another type
    throw InputError(name + ": not a topology.json as asf writes it: " + e.what());
  }
}

RegionGraph readTopologyJson(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot be read");
  std::stringstream ss;
  ss << in.rdbuf();
  return parseTopologyJson(ss.str(), path);
}


std::string topologyJson(const TopoGraph& topo) {
  using nlohmann::json;
  json j;
  j["current"] = topo.current;
  j["nodes"] = json::array();
  for (const auto& n : topo.nodes)
    j["nodes"].push_back({{"region", n.region},
                          {"centroid", {n.centroid.x, n.centroid.y}},
                          {"area_m2", n.area},
                          {"visited", n.visited},
                          {"entrance_edge", n.entrance_edge}});
  j["edges"] = json::array();
  for (const auto& e : topo.edges) {
    json t = json::array();
    for (const auto& tr : e.traversals) t.push_back({{"forward", tr.forward}, {"time_s", tr.time}});
    j["edges"].push_back({{"a", e.a},
                          {"b", e.b},
                          {"frontier", e.frontier()},
                          {"midpoint", {e.midpoint.x, e.midpoint.y}},
                          {"width_m", e.width},
                          {"traversals", t}});
  }
  return j.dump(2) + "\n";
}

}  // namespace asf::graph
